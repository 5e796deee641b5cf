"""The textbook fit of the validation's drop tables: how often mu's profile interval holds
the truth when every input is known and the model is exact.

Run:  .venv/bin/python -m validation textbook_coverage --settings inside,wide,slide --tables 200 \
          --out textbook.jsonl
      .venv/bin/python -m validation textbook_coverage --summary textbook.jsonl
      .venv/bin/python -m validation textbook_coverage --settings inside --hold 22 --draws 60
      .venv/bin/python -m validation textbook_coverage --settings inside --box-bias 3,9,22
      .venv/bin/python -m validation textbook_coverage --settings inside --tables 300 \
          --calibrate 100 --out calibrated.jsonl

Each table of :mod:`harness.fit_validation` (the same seeds and noise as the fit's
check) is fitted by :func:`harness.textbook_fit.textbook_fit` with its true impact
parameters and contact points: nothing is drawn, marginalised or estimated but e* and mu.
The summary gives, per setting, the share of 68 % intervals of mu holding the truth, the
pulls' mean and spread, and the same split by how much of mu's Fisher information the three
most informative rows carry (:func:`harness.textbook_fit.mu_information_share`).
About 2 s a table; results are appended one JSON line each, so a rerun goes on.
``--hold K`` keeps table K's geometry (its true impact parameters, contacts and errors)
and draws new noise ``--draws`` times: the coverage, mean pull and spread of one geometry.
``--box-bias K,...`` prints the second-order bias of the maximum-likelihood estimate at the
truth for those tables' geometries (Box 1971, for least squares with a smooth model),
in units of the Fisher errors: what the model's curvature alone would shift the fit by.
``--calibrate N`` calibrates each table's interval by a parametric bootstrap: ``N`` toy
tables drawn at the best fit with the table's geometry give the distribution of ``mu``'s
profile likelihood ratio, and the interval is where the table's own ratio stays below that
distribution's 68.3 % quantile (instead of 1); the summary compares the coverage of the two.
"""

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from harness.fit_validation import SETTINGS, make_table  # noqa: E402
from harness.textbook_fit import mu_information_share, textbook_fit  # noqa: E402

QUICK_ARGS = ["--tables", "3", "--settings", "inside", "--out", "textbook-quick.jsonl"]

SHARE_BINS = ((0.0, 0.4), (0.4, 0.6), (0.6, 1.01))


def record(setting, k):
    """One table's textbook fit: the truth, the interval, the pull and the share."""
    table = make_table(setting, k)
    truth = float(table.attrs["truth"]["mu"])
    r = textbook_fit(table)
    share, fisher_error = mu_information_share(table)
    err = r["upper_error"] if truth > r["mu"] else r["lower_error"]
    return {"setting": setting, "table": k, "truth": truth, **r,
            "pull": (r["mu"] - truth) / err if math.isfinite(err) else None,
            "top3_share": share, "fisher_error": fisher_error}


def calibrated(setting, k, toys, seed=1000):
    """Table ``k``'s profile likelihood ratio of ``mu`` at the truth, and the threshold that
    ``toys`` parametric-bootstrap tables at its best fit give for a 68.3 % interval."""
    from scipy import optimize

    from harness.drop_tables import kernel_solver
    from harness.textbook_fit import _arrays

    table = make_table(setting, k)
    b, spin, axial, e_x, y, s = _arrays(table)
    r = textbook_fit(table)
    mu0, e0 = r["mu"], r["e"]
    step = max(min(r["lower_error"], r["upper_error"], 0.05), 1e-3)

    def nll(data, e, mu):
        f = kernel_solver(b, spin, axial, e, min(max(mu, 1e-3), 2.0), e_x)
        return 0.5 * float((((data - f) / s) ** 2).sum())

    def profile(data, mu):
        return optimize.minimize_scalar(lambda e: nll(data, e, mu), bounds=(0.3, 0.95),
                                        method="bounded", options={"xatol": 1e-7}).fun

    def minimum(data):
        # two simplex searches, one from each side of the best value (the profile in mu
        # has kinks where rows start to roll, and a single search can stop at one)
        found = [optimize.minimize(lambda t: nll(data, *t), start[0], method="Nelder-Mead",
                                   options={"initial_simplex": start, "xatol": 1e-6,
                                            "fatol": 1e-6}).fun
                 for start in ([[e0, mu0], [e0 + 3e-3, mu0], [e0, mu0 + step]],
                               [[e0, mu0 - step], [e0 + 3e-3, mu0 - step],
                                [e0, mu0 - 2 * step]])]
        return min(found)

    exact = kernel_solver(b, spin, axial, e0, mu0, e_x)
    rng = np.random.default_rng(seed + k)
    ratios = []
    for _ in range(toys):
        toy = exact + s * rng.standard_normal(s.shape)
        at_best = profile(toy, mu0)
        ratios.append(2 * (at_best - min(at_best, minimum(toy))))
    truth = float(table.attrs["truth"]["mu"])
    ratio = 2 * (profile(y, truth) - r["neg_log_likelihood"])
    threshold = float(np.quantile(ratios, 0.683))
    return {"setting": setting, "table": k, "ratio_at_truth": ratio, "threshold": threshold,
            "covered": bool(ratio <= 1.0), "covered_calibrated": bool(ratio <= threshold)}


def held_geometry(setting, k, draws, seed=5):
    """Pulls of ``mu`` over ``draws`` new noise draws on table ``k``'s geometry."""
    from harness.drop_tables import kernel_solver
    from harness.textbook_fit import OBSERVABLES

    table = make_table(setting, k)
    truth = table.attrs["truth"]
    errors = table[[f"{c}_err" for c in OBSERVABLES]].to_numpy(float)
    exact = kernel_solver(np.asarray(truth["impact_parameter"]), table["spin_in"].to_numpy(),
                          np.asarray(truth["axial"]), truth["e"], truth["mu"], truth["e_x"])
    rng = np.random.default_rng(seed)
    pulls = []
    for _ in range(draws):
        noisy = table.copy()
        noisy.attrs = table.attrs
        noisy[list(OBSERVABLES)] = exact + errors * rng.standard_normal(errors.shape)
        r = textbook_fit(noisy)
        err = r["upper_error"] if truth["mu"] > r["mu"] else r["lower_error"]
        pulls.append((r["mu"] - truth["mu"]) / err)
    return np.array(pulls)


def box_bias(setting, k, steps=(1e-4, 1e-3)):
    """Box's (1971) second-order bias of ``(e*, mu)`` at the truth of table ``k``, in units
    of the Fisher errors: ``-1/2 (J^T J)^-1 J^T d`` with ``d_i = tr((J^T J)^-1 H_i)``, ``J``
    and ``H_i`` the Jacobian and Hessians of the error-scaled observables (central
    differences of ``steps`` in ``e*`` and ``mu``)."""
    from harness.drop_tables import kernel_solver
    from harness.textbook_fit import _arrays

    table = make_table(setting, k)
    truth = table.attrs["truth"]
    b, spin, axial, e_x, _, s = _arrays(table)

    def scaled(theta):
        return (kernel_solver(b, spin, axial, theta[0], theta[1], e_x) / s).ravel()

    theta, h = np.array([truth["e"], truth["mu"]], float), np.asarray(steps, float)
    unit = np.eye(2) * h
    f0 = scaled(theta)
    up, down = [scaled(theta + u) for u in unit], [scaled(theta - u) for u in unit]
    jac = np.stack([(up[a] - down[a]) / (2 * h[a]) for a in range(2)], axis=1)
    hess = np.empty((f0.size, 2, 2))
    for a in range(2):
        hess[:, a, a] = (up[a] - 2 * f0 + down[a]) / h[a] ** 2
    hess[:, 0, 1] = hess[:, 1, 0] = (
        scaled(theta + unit[0] + unit[1]) - scaled(theta + unit[0] - unit[1])
        - scaled(theta - unit[0] + unit[1]) + scaled(theta - unit[0] - unit[1])) / (4 * h[0] * h[1])
    cov = np.linalg.inv(jac.T @ jac)
    bias = -0.5 * cov @ jac.T @ np.einsum("ab,iab->i", cov, hess)
    return bias / np.sqrt(np.diag(cov))


def _line(label, pulls):
    """Coverage (an infinite pull counts as not covered), mean pull and spread."""
    finite = pulls[np.isfinite(pulls)]
    n = len(pulls)
    covered = 100 * np.mean(np.abs(pulls) <= 1)
    error = 100 * math.sqrt(0.68 * 0.32 / n)
    return (f"{label}tables {n:4d}  coverage {covered:5.1f} % (+-{error:.1f})  "
            f"mean pull {finite.mean():+.3f}  pull sd {finite.std(ddof=1):.2f}")


def summary_lines(records):
    """Printed lines: per setting, coverage and pulls, then split by the top-3 share."""
    lines = []
    for setting in SETTINGS:
        rows = [r for r in records if r["setting"] == setting]
        if len(rows) < 2:
            continue
        pulls = np.array([r["pull"] if r["pull"] is not None else np.inf for r in rows])
        share = np.array([r["top3_share"] for r in rows])
        lines.append(_line(f"{setting:7s} mu  ", pulls)
                     + f"  median top-3 share {np.median(share):.2f}")
        for lo, hi in SHARE_BINS:
            m = (share >= lo) & (share < hi)
            if m.sum() >= 2:
                lines.append(_line(f"    top-3 share {lo:.1f}-{min(hi, 1.0):.1f}: ", pulls[m]))
    return lines


def calibration_run(args):
    """``--calibrate``: resumable records in ``--out``, then the two coverages."""
    path = Path(args.out)
    setting = args.settings.split(",")[0]
    done = ({json.loads(line)["table"] for line in path.open()} if path.exists() else set())
    with path.open("a") as handle:
        for k in range(args.tables):
            if k not in done:
                handle.write(json.dumps(calibrated(setting, k, args.calibrate)) + "\n")
                handle.flush()
    records = [json.loads(line) for line in path.read_text().splitlines()]
    n = len(records)
    error = 100 * math.sqrt(0.683 * 0.317 / n)
    for key, label in (("covered", "rise of 1/2"), ("covered_calibrated", "calibrated")):
        share = 100 * np.mean([r[key] for r in records])
        print(f"{setting:7s} mu  tables {n:4d}  coverage {share:5.1f} % (+-{error:.1f})  {label}")
    print(f"thresholds: median {np.median([r['threshold'] for r in records]):.2f} (1 without "
          "calibration)")
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tables", type=int, default=200)
    parser.add_argument("--settings", default="inside")
    parser.add_argument("--out", default="textbook.jsonl")
    parser.add_argument("--summary", metavar="FILE", help="only summarise FILE")
    parser.add_argument("--hold", type=int, metavar="K",
                        help="keep table K's geometry and draw new noise --draws times")
    parser.add_argument("--draws", type=int, default=60)
    parser.add_argument("--calibrate", type=int, metavar="TOYS",
                        help="calibrate each interval with TOYS bootstrap tables")
    parser.add_argument("--box-bias", metavar="K,...",
                        help="print the second-order bias at those tables' truth")
    args = parser.parse_args(argv)
    if args.box_bias:
        setting = args.settings.split(",")[0]
        for k in map(int, args.box_bias.split(",")):
            e_bias, mu_bias = box_bias(setting, k)
            print(f"{setting:7s} table {k}: second-order bias of e* {e_bias:+.3f}, "
                  f"of mu {mu_bias:+.3f} (Fisher errors)")
        return 0
    if args.hold is not None:
        setting = args.settings.split(",")[0]
        print(_line(f"{setting:7s} table {args.hold} held, new noise: ",
                    held_geometry(setting, args.hold, args.draws)))
        return 0
    if args.calibrate:
        return calibration_run(args)
    path = Path(args.summary or args.out)
    if not args.summary:
        settings = args.settings.split(",")
        unknown = [s for s in settings if s not in SETTINGS]
        if unknown:
            parser.error(f"unknown setting {unknown[0]!r} (choose from {', '.join(SETTINGS)})")
        done = ({(r["setting"], r["table"]) for r in map(json.loads, path.open())}
                if path.exists() else set())
        with path.open("a") as handle:
            for k in range(args.tables):
                for setting in settings:
                    if (setting, k) not in done:
                        handle.write(json.dumps(record(setting, k)) + "\n")
                        handle.flush()
    records = [json.loads(line) for line in path.read_text().splitlines()]
    for line in summary_lines(records):
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
