"""The drop-test likelihood's first-order bias, from its gradient at the truth, beside the
exact marginal likelihood's.

Run:  NUMBA_NUM_THREADS=1 .venv/bin/python -m validation marginal_scores --setting large \
          --stated-errors truth --tables 100 --workers 2 --out DIR
      .venv/bin/python -m validation marginal_scores --setting large --stated-errors truth \
          --summary DIR

A fit that maximises a correct likelihood is unbiased to first order: the likelihood's
score (its gradient in the parameters) at the truth averages zero over tables, and the
best fit lies ``H^-1 g`` from the truth (``g`` the score, ``H`` the Fisher information,
the covariance of the scores over tables). So the mean of ``-H^-1 g`` over tables, in
units of the error ``sqrt((H^-1)_jj)``, is the fit's mean pull to first order, measured
without fitting: seconds a table instead of minutes.

For each table of :mod:`harness.fit_validation` (the fit check's seeds and noise)
the score of ``-ln L`` in ``e*`` and ``mu`` at the truth is taken by central differences
for three likelihoods:

* ``mcbat``: :class:`mcbat.stats.fit.likelihood.Likelihood` as :func:`mcbat.stats.fit.estimate.fit`
  builds it (the study ``studies/cross_nathan_2006.toml``, the fit's draws and seed, its
  prior of the impact parameters fitted with the parameters), its draws refined at the
  truth;
* ``marginal``: the exact marginal likelihood (each row's impact parameter and contact
  point integrated over their true uniform distributions by quadrature,
  :func:`harness.textbook_fit.marginal_neg_log_likelihood`), what mcbat estimates;
* ``true_contacts``: the same with the contact points at their true values, which no
  fit of a real table knows.

The summary prints each likelihood's first-order mean pulls, and mcbat's against the
exact marginal likelihood's table by table (both in the latter's errors): that
difference is what mcbat's draws, its fitted prior and its covering range add.
About 20 s a 3000-row table; one JSON line a table, so a rerun goes on.
"""

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from harness.fit_validation import SETTINGS, TRUTH, make_table, run_jobs  # noqa: E402

QUICK_ARGS = ["--setting", "inside", "--tables", "2", "--out", "marginal-scores-quick"]
STEP = 2e-5
"""The central differences' step in ``e*`` and ``mu`` (a hundredth of their errors at 60
rows, a tenth at 3000)."""
LIKELIHOODS = ("mcbat", "marginal", "true_contacts")


def gradient(nll, point):
    """Central-difference gradient of ``nll`` (a function of ``(e*, mu)``) at ``point``."""
    out = []
    for j in range(len(point)):
        up, down = np.array(point, float), np.array(point, float)
        up[j] += STEP
        down[j] -= STEP
        out.append((nll(*up) - nll(*down)) / (2 * STEP))
    return out


def record(setting, k, stated_errors):
    """Table ``k`` of ``setting``, its errors stated as ``stated_errors`` says: the three
    likelihoods' scores at the truth."""
    from harness.textbook_fit import marginal_neg_log_likelihood
    from mcbat.stats.fit.likelihood import Likelihood
    from mcbat.study import load_study

    t0 = time.perf_counter()
    table = make_table(setting, k, stated_errors=stated_errors)
    truth = [float(table.attrs["truth"][p]) for p in TRUTH]
    study = load_study(ROOT / "studies" / "cross_nathan_2006.toml")
    like = Likelihood(study, table, list(TRUTH), seed=k)  # as fit(..., seed=k) builds it
    like.refine(np.array(truth))
    exact = marginal_neg_log_likelihood(table, nodes=64, contact_nodes=8)
    known = marginal_neg_log_likelihood(table, nodes=128)
    scores = {"mcbat": gradient(lambda e, mu: like([e, mu]), truth),
              "marginal": gradient(lambda e, mu: float(exact(e, mu).sum()), truth),
              "true_contacts": gradient(lambda e, mu: float(known(e, mu).sum()), truth)}
    return {"setting": setting, "stated_errors": stated_errors, "table": k,
            "truth": dict(zip(TRUTH, truth)),
            "scores": {name: [float(v) for v in g] for name, g in scores.items()},
            "seconds": time.perf_counter() - t0}


def read_dir(directory):
    """Every record in ``directory``'s ``*.jsonl`` files."""
    out = []
    for path in sorted(Path(directory).glob("*.jsonl")):
        out += [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return out


def first_order_pulls(scores, fisher):
    """``-H^-1 g`` of each table in units of ``sqrt((H^-1)_jj)``: (tables, parameters)."""
    inverse = np.linalg.inv(fisher)
    return -(scores @ inverse) / np.sqrt(np.diag(inverse))


def _mean(values):
    values = np.asarray(values, float)
    se = values.std(ddof=1) / np.sqrt(len(values))
    return f"{values.mean():+.3f} +- {se:.3f}"


def summary(records):
    """Printed lines: first-order mean pulls per likelihood and parameter, and mcbat's
    against the exact marginal likelihood's."""
    scores = {name: np.array([r["scores"][name] for r in records]) for name in LIKELIHOODS}
    # The Fisher information of a correct likelihood is the covariance of its scores; the
    # exact marginal likelihood's sets the errors in which mcbat's shifts are given.
    fisher = {name: np.cov(g, rowvar=False) for name, g in scores.items()}
    pulls = {name: first_order_pulls(scores[name], fisher[name]) for name in
             ("marginal", "true_contacts")}
    pulls["mcbat"] = first_order_pulls(scores["mcbat"], fisher["marginal"])
    errors = np.sqrt(np.diag(np.linalg.inv(fisher["marginal"])))
    lines = []
    for j, p in enumerate(TRUTH):
        lines.append(f"{p:3s} tables {len(records):4d}  error {errors[j]:.6f}  first-order mean "
                     f"pull: marginal {_mean(pulls['marginal'][:, j])}  mcbat "
                     f"{_mean(pulls['mcbat'][:, j])}  true contacts "
                     f"{_mean(pulls['true_contacts'][:, j])}  mcbat - marginal "
                     f"{_mean(pulls['mcbat'][:, j] - pulls['marginal'][:, j])}")
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m validation marginal_scores",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--setting", default="large", choices=list(SETTINGS))
    parser.add_argument("--tables", type=int, default=100)
    parser.add_argument("--stated-errors", default="truth",
                        choices=("truth", "measured", "constant"),
                        help="the errors the tables state for the exit speed and the outgoing "
                             "spin (harness.drop_tables.drop_table)")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--out", default="marginal-scores", metavar="DIR")
    parser.add_argument("--summary", metavar="DIR", help="summarise DIR and stop")
    args = parser.parse_args(argv)
    if not args.summary:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        name = f"{args.setting}-{args.stated_errors}"
        done = {(r["setting"], r["stated_errors"], r["table"]) for r in read_dir(out)}
        todo = [k for k in range(args.tables)
                if (args.setting, args.stated_errors, k) not in done]
        jobs = [(args.setting, args.stated_errors, todo[w::args.workers],
                 str(out / f"{name}.{w}.jsonl"))
                for w in range(args.workers) if todo[w::args.workers]]
        if jobs:
            run_jobs(_work, jobs)
    directory = args.summary or args.out
    records = [r for r in read_dir(directory)
               if (r["setting"], r["stated_errors"]) == (args.setting, args.stated_errors)]
    if len(records) < 3:
        print(f"{len(records)} records: too few for a summary")
        return 0 if records else 1
    for line in summary(records):
        print(line)
    return 0


def _work(job):
    setting, stated_errors, tables, path = job
    for k in tables:
        rec = record(setting, k, stated_errors)
        with open(path, "a") as out:
            out.write(json.dumps(rec) + "\n")
        print(f"{setting} ({stated_errors} errors) table {k}: {rec['seconds']:.0f} s",
              flush=True)


if __name__ == "__main__":
    sys.exit(main())
