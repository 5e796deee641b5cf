"""The drop-test fit against tables it did not simulate: one table's fit, and the summary.

Each table comes from ``harness.drop_tables`` (its own geometry, draws and noise;
not the study machinery nor ``mcbat synth``) and is fitted as a user would fit it:
``fit(studies/cross_nathan_2006.toml, table, ("e", "mu"))`` with profile intervals. The
summary gives, per setting and parameter, the share of two-sided 68 % intervals holding
the truth, the pulls, how often one-sided 95 % limits hold it, refusals and zero-width
intervals. ``validation/drop_fit_checks.py`` runs many tables; the tests run a few.

Settings (truth e* = 0.6; 5 mm of stated error on the impact parameter unless said; the
study's range of the impact parameter is +-1 in):

  inside    mu = 0.18, b uniform in +-2.54 cm, 60 rows
  edges     mu = 0.18, b within 0.5 cm of the ends of +-2.54 cm, 60 rows
  wide      mu = 0.18, b uniform in +-4 cm (beyond the study's range), 60 rows
  stick     mu = 0.5, most drops stick (mu bounded from below only), 60 rows
  onset     mu = 0.2, where the drops start to stick all along: many tables bound mu
            from below only, and their limits are tested where they can fail
  onset_low mu = 0.19, at the low end of the tables' onsets of sticking (0.178-0.213
            over 400 tables): in nearly every table some drop still slides, yet about one
            table in seven looks flat (163 of 1200), and its limit is tested below its onset
  edges_low mu = 0.203, b within 0.5 cm of the ends of +-2.54 cm: just below the onsets
            of sticking of these tables (0.206-0.2125 over 40 tables; at mu = 0.19, 313
            tables reported no limit), the limits at the edges of the study's range
  plateau   mu = each table's own onset of sticking (its design's, from 0.19 to 0.21: with
            mu there every drop sticks, the last only just): the data are distributed as
            on the plateau above, and a lower limit excludes the truth no more often
            than it excludes mu = 2
  slide     mu = 0.1, most drops slide, 60 rows
  spins     mu = 0.18, spins of -200, -100, 0, 100 and 200 rad/s (the study's are 79, 0
            and -72): the drops slide longer, and stick from mu = 0.41-0.43 on
  small     mu = 0.18, 20 rows
  large     mu = 0.18, 3000 rows
  err1      mu = 0.18, 1 mm of error on b
  err10     mu = 0.18, 10 mm of error on b

Table ``k`` of a setting uses the seed ``1000 + k``, its fit the seed ``k``. Each table
states for the exit speed and the outgoing spin the very errors their noise was drawn with
(relative to each row's true value), unless ``make_table`` is told otherwise
(``stated_errors`` of ``harness.drop_tables.drop_table``).
"""

import math
import time

import numpy as np

__all__ = ["SETTINGS", "TRUTH", "fit_table", "format_or_dash", "interval_statistics",
           "limit_holds", "limit_p_value", "make_table", "p_value_shares", "pull",
           "pulls_and_limits", "run_jobs", "summarize", "summary_line"]

SETTINGS = {
    "inside": {},
    "edges": {"edges": 0.005},
    "wide": {"impact_parameter": (-0.04, 0.04)},
    "stick": {"mu": 0.5},
    "onset": {"mu": 0.2},
    "onset_low": {"mu": 0.19},
    "edges_low": {"edges": 0.005, "mu": 0.203},
    "plateau": {"mu": "design_onset"},
    "slide": {"mu": 0.1},
    "spins": {"spins": (-200.0, -100.0, 0.0, 100.0, 200.0)},
    "small": {"rows": 20},
    "large": {"rows": 3000},
    "err1": {"impact_parameter_err": 0.001},
    "err10": {"impact_parameter_err": 0.010},
}
"""Each setting's departures from ``TRUTH``, 60 rows and 5 mm errors on ``b``."""
TRUTH = {"e": 0.6, "mu": 0.18}
"""The fitted parameters and their true values, unless a setting says otherwise."""


def make_table(setting, k, solver="kernel", stated_errors="truth"):
    """Table ``k`` of ``setting``, solved by ``"kernel"`` or ``"reference"``, its errors
    stated as ``stated_errors`` says (``harness.drop_tables.drop_table``)."""
    from harness.drop_tables import (
        design_stick_onset,
        drop_table,
        kernel_solver,
        reference_solver,
    )

    spec = {**TRUTH, **SETTINGS[setting]}
    rows = spec.pop("rows", 60)
    chosen = reference_solver if solver == "reference" else kernel_solver
    if spec["mu"] == "design_onset":
        spec["mu"] = design_stick_onset(rows, 1000 + k, **spec)
    return drop_table(rows, 1000 + k, solver=chosen, stated_errors=stated_errors, **spec)


def fit_table(setting, k, study, solver="kernel"):
    """Fit table ``k`` of ``setting`` with ``study``; a JSON-ready record: the truth, and
    the fit's parameters, chi2, warnings, the inputs whose measured values reject the
    study's range and the fitted prior's share beyond it, or the refusal's message."""
    from mcbat.errors import InputError
    from mcbat.stats.fit.estimate import fit

    table = make_table(setting, k, solver)
    truth = {p: table.attrs["truth"][p] for p in TRUTH}
    t0 = time.perf_counter()
    rec = {"setting": setting, "table": k, "truth": truth}
    try:
        r = fit(study, table, tuple(TRUTH), seed=k)
    except InputError as err:
        rec.update(refused=str(err), seconds=time.perf_counter() - t0)
        return rec
    out = r.to_dict()
    rec.update(seconds=time.perf_counter() - t0, chi2=r.chi2, dof=r.dof,
               params=out["params"], warnings=out["warnings"],
               rejected=[k for k, v in out["input_priors"].items()
                         if v.get("rejects_study_range")],
               share_beyond={k: v["share_beyond_study_range"]
                             for k, v in out["input_priors"].items()
                             if "share_beyond_study_range" in v})
    return rec


def limit_p_value(setting, k, study, parameter="mu", solver="kernel"):
    """The conditional p-value of the true ``parameter`` of table ``k`` of ``setting``,
    where its fit reports a one-sided limit; a JSON-ready record.

    A conditional limit (``mcbat.stats.fit.selective``) excludes the values whose p-value,
    among simulated tables flat on the same side, is below 5 %. Here that test is applied to
    the truth itself: the surrogate is built along the profile (the other free parameters
    minimised, independently of the fit's own profile), over a grid through the truth, the
    tables are simulated under the truth, and the p-value is the share of the flat ones that
    rise at the truth by as much as the data do. Where the test is calibrated these p-values
    are uniform over the tables that report a limit (a truth on the surrogate's plateau,
    where nothing can be excluded, has p = 1), and the share below 0.05 is the rate at which
    a limit with no other rule would exclude the truth. The limits themselves are, in
    addition, never above the 68 % interval's end.

    Returns
    -------
    dict
        ``setting``, ``table``, ``truth``, the fit's ``status``, ``limit`` and
        ``limit_kind``; with a limit, ``flat`` (whether the surrogate's profile is flat on
        the limit's free side), and where it is, ``p_value`` and ``rise`` (the data's rise of
        ``-ln L`` at the truth in the surrogate).
    """
    from scipy import optimize

    from mcbat.stats.fit.estimate import fit
    from mcbat.stats.fit.intervals import ONE_SIGMA
    from mcbat.stats.fit.likelihood import FREE, Likelihood
    from mcbat.stats.fit.search import search
    from mcbat.stats.fit.selective import (
        conditional_p_value,
        flat_side_mask,
        surrogate,
        surrogate_rises,
    )

    table = make_table(setting, k, solver)
    truth = float(table.attrs["truth"][parameter])
    free = tuple(TRUTH)
    result = fit(study, table, free, seed=k)
    entry = result.intervals[parameter]
    rec = {"setting": setting, "table": k, "truth": truth, "status": entry["status"],
           "limit": entry["limit"], "limit_kind": entry.get("limit_kind")}
    if entry["status"] not in ("lower_limit", "upper_limit") or entry["limit"] is None:
        return rec
    sign = -1 if entry["status"] == "lower_limit" else 1
    value = result.params[parameter]
    root = value - entry["lower_error"] if sign < 0 else value + entry["upper_error"]
    edge = FREE[parameter][1] if sign < 0 else FREE[parameter][0]
    # The fit's likelihood: the same draws, refined where the fit's search refined them.
    like = Likelihood(study, table, free, seed=k)
    search(like)
    best = np.array([result.params[p] for p in free])
    i = free.index(parameter)
    others = [j for j in range(len(free)) if j != i]

    def point(t):
        x = best.copy()
        x[i] = t

        def nll(y):
            x[others] = y
            return like(x)
        if len(others) == 1:  # Brent's method from the best fit's value
            y0 = best[others[0]]
            got = optimize.minimize_scalar(lambda y: nll([y]), bracket=(y0 - 1e-3, y0 + 1e-3),
                                           options={"xtol": 1e-5})
            x[others] = got.x
        else:
            x[others] = optimize.minimize(nll, best[others], method="Nelder-Mead").x
        return x

    span = max(abs(root - entry["limit"]), 1e-4)
    near = min(truth, entry["limit"]) if sign < 0 else max(truth, entry["limit"])
    bounded = np.linspace(near + sign * 4 * span, root, 17)
    flat_side = root + (edge - root) * np.linspace(0.0, 1.0, 11)[1:] ** 2
    grid = np.unique(np.concatenate([bounded, flat_side, [truth]]))
    sur = surrogate(like, best, grid, point)
    rec["flat"] = False
    if sur is None or len(sur.grid) < 4 or truth not in sur.grid:
        return rec
    curves, variance = sur.statistic()
    rises = surrogate_rises(curves, variance, sur.y)
    rec["flat"] = bool(flat_side_mask(rises, sign, ONE_SIGMA)[0])
    if rec["flat"]:
        j = int(np.flatnonzero(sur.grid == truth)[0])
        rng = np.random.default_rng(np.random.SeedSequence(k, spawn_key=(2**31 + 19, i)))
        rec["rise"] = float(rises[j])
        rec["p_value"] = conditional_p_value(curves, variance, rises[j], j, sign, rng,
                                             ONE_SIGMA, null=sur.null)
    return rec


def p_value_shares(p_values, levels=(0.05, 0.10, 0.20, 0.50)):
    """Share of ``p_values`` at or below each level, with its binomial error at that level
    (the share expected of uniform p-values); a list of ``(level, share, error)``."""
    p = np.asarray(p_values, float)
    n = max(len(p), 1)
    return [(a, float((p <= a).mean()) if len(p) else math.nan, math.sqrt(a * (1 - a) / n))
            for a in levels]


def pull(entry, truth):
    """(value - truth) / the profile error on the truth's side; None without an interval."""
    if entry.get("status") != "measured":
        return None
    err = entry["upper_error"] if truth > entry["value"] else entry["lower_error"]
    return (entry["value"] - truth) / err if err else None


def limit_holds(entry, truth):
    """None if the entry is not a one-sided limit, else whether it holds the truth."""
    if entry.get("status") == "lower_limit":
        return truth >= entry["limit"]
    if entry.get("status") == "upper_limit":
        return truth <= entry["limit"]
    return None


def pulls_and_limits(entries):
    """The pulls of the entries with a two-sided interval (an array) and, for each
    one-sided limit, whether it holds the truth (a list of bool); ``entries`` as in
    ``interval_statistics``."""
    pulls = np.array([x for x in (pull(e, t) for e, t in entries) if x is not None])
    limits = [x for x in (limit_holds(e, t) for e, t in entries) if x is not None]
    return pulls, limits


def interval_statistics(entries, tables):
    """Coverage, pulls and limits of one parameter over fitted tables.

    Parameters
    ----------
    entries : list of (dict, float)
        Each fitted table's entry of the parameter (``FitResult.to_dict()["params"]``) and
        its true value.
    tables : int
        The tables fitted (a table without an interval counts as not covered).

    Returns
    -------
    dict
        ``coverage`` (two-sided 68 % intervals holding the truth, over all tables) and its
        binomial error ``coverage_se``, ``interval_coverage`` (over the two-sided intervals
        only), ``mean_pull`` and its error ``mean_pull_se``, ``pull_sd``, ``limits`` (one-sided
        limits reported) and ``limit_coverage`` (the share holding the truth), ``zero_width``
        (intervals with an error of zero on a side); None where undefined.
    """
    pv, limits = pulls_and_limits(entries)
    n = max(tables, 1)
    return {
        "coverage": float((np.abs(pv) <= 1).sum() / n),
        "coverage_se": math.sqrt(0.68 * 0.32 / n),
        "interval_coverage": float((np.abs(pv) <= 1).mean()) if len(pv) else None,
        "mean_pull": float(pv.mean()) if len(pv) else None,
        "mean_pull_se": float(pv.std(ddof=1) / math.sqrt(len(pv))) if len(pv) > 1 else None,
        "pull_sd": float(pv.std(ddof=1)) if len(pv) > 1 else None,
        "limits": len(limits),
        "limit_coverage": float(np.mean(limits)) if limits else None,
        "zero_width": sum(1 for e, _ in entries if e.get("status") == "measured"
                          and (e.get("lower_error") == 0 or e.get("upper_error") == 0))}


def summarize(records):
    """Per setting and parameter: tables, refusals, tables whose measured inputs reject the
    study's range, the median fitted share of the prior beyond it, the statistics of
    ``interval_statistics`` and the median seconds a fit took."""
    rows = []
    for setting in SETTINGS:
        these = [r for r in records if r["setting"] == setting]
        if not these:
            continue
        fitted = [r for r in these if "refused" not in r]
        for p in TRUTH:
            entries = [(r["params"][p], r["truth"][p]) for r in fitted]
            rows.append({
                "setting": setting, "param": p, "tables": len(these),
                "refused": len(these) - len(fitted),
                "rejected": sum(bool(r.get("rejected")) for r in fitted),
                "share_beyond": float(np.median([sum(r["share_beyond"].values())
                                                 for r in fitted]))
                if fitted and all("share_beyond" in r for r in fitted) else None,
                **interval_statistics(entries, len(fitted)),
                "median_seconds": float(np.median([r["seconds"] for r in these]))})
    return rows


def run_jobs(worker, jobs):
    """``worker(job)`` for each job: in this process for one job, else in a pool of spawned
    processes, one a job (fresh interpreters: numba and BLAS start single-threaded as the
    environment says, not as a forked parent left them)."""
    if len(jobs) == 1:
        worker(jobs[0])
        return
    import multiprocessing

    with multiprocessing.get_context("spawn").Pool(len(jobs)) as pool:
        pool.map(worker, jobs)


def _percent(share):
    return None if share is None else 100 * share


def format_or_dash(value, spec):
    """``value`` formatted by ``spec``, or "-" for None."""
    return "-" if value is None else format(value, spec)



def summary_line(row):
    """One printed line of a ``summarize`` row."""
    dash = format_or_dash
    return (f"{row['setting']:7s} {row['param']:3s} tables {row['tables']:4d} refused "
            f"{row['refused']:3d} rejecting the range {row['rejected']:3d} (median share "
            f"beyond {dash(row['share_beyond'], '.3f')})  coverage "
            f"{100 * row['coverage']:5.1f} % (+-{100 * row['coverage_se']:.1f}; "
            f"{dash(_percent(row['interval_coverage']), '.1f')} % of "
            f"the intervals)  mean pull "
            f"{dash(row['mean_pull'], '+.3f')} (+-{dash(row['mean_pull_se'], '.3f')})  pull sd "
            f"{dash(row['pull_sd'], '.2f')}  95 % limits {row['limits']} holding "
            f"{dash(row['limit_coverage'], '.3f')}  zero-width {row['zero_width']}  "
            f"{row['median_seconds']:.1f} s/fit")
