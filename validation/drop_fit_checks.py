"""The drop-test fit against tables it did not simulate: pulls, coverage, limits, refusals.

Run:  .venv/bin/python -m validation drop_fit_checks --settings inside,edges --tables 400 \
          --workers 2 --out fit-validation
      .venv/bin/python -m validation drop_fit_checks --summary fit-validation
      .venv/bin/python -m validation drop_fit_checks --crosscheck 3
      .venv/bin/python -m validation drop_fit_checks --summary fit-validation \
          --figure docs/figures/fit_checks_pulls.png

The tables, the fit and the summary are :mod:`harness.fit_validation` (its docstring
lists the settings). The impacts of the tables are solved by the kernel, because the
reference solver takes ~0.5 s an impact; `--crosscheck N` makes N tables with both solvers
from the same random numbers and prints their largest difference over the measurement
errors, and `--solver reference` uses the reference for every table.

Each result is one JSON line in DIR/<setting>.<worker>.jsonl, so an interrupted run keeps
what it did and a rerun goes on from there. Tables advance together across the settings.
`--refit-limits EARLIER` refits only the tables of EARLIER whose fit reported a one-sided
limit (after a change to how limits are set) and keeps the others' records.
"""

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from harness.fit_validation import (  # noqa: E402
    SETTINGS,
    TRUTH,
    fit_table,
    make_table,
    pulls_and_limits,
    run_jobs,
    summarize,
    summary_line,
)

BASE = "base.jsonl"
"""With ``--refit-limits``: the earlier run's records, read before (and overridden by) the
refits."""


def read_records(out, base=True):
    """Every record in DIR's .jsonl files (the last one of a table wins; :data:`BASE`
    first, or not at all with ``base=False``)."""
    recs = {}
    paths = sorted(Path(out).glob("*.jsonl"), key=lambda path: (path.name != BASE, path.name))
    for path in paths:
        if path.name == BASE and not base:
            continue
        for line in path.read_text().splitlines():
            rec = json.loads(line)
            recs[(rec["setting"], rec["table"])] = rec
    return [recs[key] for key in sorted(recs)]


def worker(args):
    index, workers, jobs, out, solver = args
    from mcbat.study import load_study

    study = load_study(ROOT / "studies" / "cross_nathan_2006.toml")
    done = {(r["setting"], r["table"]) for r in read_records(out, base=False)}
    for setting, k in jobs[index::workers]:
        if (setting, k) in done:
            continue
        rec = fit_table(setting, k, study, solver)
        with open(Path(out) / f"{setting}.{index}.jsonl", "a") as handle:
            handle.write(json.dumps(rec) + "\n")


def limit_jobs(records):
    """``(setting, table)`` of each record whose fit reported a one-sided limit."""
    return [(r["setting"], r["table"]) for r in records if "refused" not in r
            and any(v.get("limit") is not None for v in r["params"].values())]


def crosscheck(n):
    """Largest difference between reference and kernel tables, over the stated errors."""
    worst = 0.0
    for k in range(n):
        ref, ker = make_table("inside", k, "reference"), make_table("inside", k, "kernel")
        for col in ("exit_speed", "scattering_angle", "spin_out"):
            worst = max(worst, float(np.max(np.abs(ref[col] - ker[col]) / ref[f"{col}_err"])))
    print(f"{n} tables of 60 rows: reference and kernel differ by at most {worst:.2e} of a "
          f"stated error")
    return worst


def figure(records, path, min_tables=50):
    """Histograms of the pulls of each setting with at least ``min_tables`` tables, one row
    of panels per setting and one column per parameter, over the unit normal they should
    follow; the panel's title counts the one-sided limits and those holding the truth."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    settings = [s for s in SETTINGS
                if sum(r["setting"] == s for r in records) >= min_tables]
    fig, axes = plt.subplots(len(settings), len(TRUTH), figsize=(8, 2.2 * len(settings)),
                             squeeze=False, sharex=True)
    grid = np.linspace(-4, 4, 161)
    edges = np.linspace(-4, 4, 33)
    for row, setting in zip(axes, settings):
        fitted = [r for r in records if r["setting"] == setting and "refused" not in r]
        for ax, p in zip(row, TRUTH):
            pulls, limits = pulls_and_limits([(r["params"][p], r["truth"][p])
                                              for r in fitted])
            ax.hist(np.clip(pulls, -3.99, 3.99), bins=edges, density=True, color="0.7",
                    label=f"{len(pulls)} intervals")
            ax.plot(grid, np.exp(-grid ** 2 / 2) / np.sqrt(2 * np.pi), "k-", lw=1,
                    label="unit normal")
            title = f"{setting}, {p}: mean pull {pulls.mean():+.2f}" if len(pulls) else \
                f"{setting}, {p}"
            if limits:
                title += f"; {sum(limits)} of {len(limits)} limits hold"
            ax.set_title(title, fontsize=9)
            ax.legend(fontsize=7, loc="upper left", frameon=False)
    for ax in axes[-1]:
        ax.set_xlabel("pull (clipped at +-4)")
    fig.suptitle("The drop-test fit on independently simulated tables: pulls, (value - truth)"
                 " / error on the truth's side", fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(path, dpi=110)
    print(f"figure written to {path}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tables", type=int, default=400)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--settings", default="inside,edges")
    parser.add_argument("--solver", choices=("kernel", "reference"), default="kernel")
    parser.add_argument("--out", default="fit-validation")
    parser.add_argument("--summary", metavar="DIR", help="only summarise DIR")
    parser.add_argument("--refit-limits", metavar="DIR",
                        help="refit only the tables of DIR that reported a one-sided limit, "
                             "keeping DIR's other records (the fit of a table without a "
                             "limit does not depend on how limits are set)")
    parser.add_argument("--figure", metavar="PATH",
                        help="also draw the pulls of the summarised tables (PNG)")
    parser.add_argument("--crosscheck", type=int, metavar="N",
                        help="compare N tables made by the reference and by the kernel")
    args = parser.parse_args(argv)
    if args.crosscheck:
        crosscheck(args.crosscheck)
        return
    if not args.summary:
        settings = args.settings.split(",")
        unknown = [s for s in settings if s not in SETTINGS]
        if unknown:
            parser.error(f"unknown setting {unknown[0]!r} (choose from {', '.join(SETTINGS)})")
        Path(args.out).mkdir(parents=True, exist_ok=True)
        if args.refit_limits:
            earlier = [r for r in read_records(args.refit_limits) if r["setting"] in settings]
            base = Path(args.out) / BASE
            if not base.exists():
                base.write_text("".join(json.dumps(r) + "\n" for r in earlier))
            jobs = limit_jobs(earlier)
        else:
            jobs = [(setting, k) for k in range(args.tables) for setting in settings]
        run_jobs(worker, [(i, args.workers, jobs, args.out, args.solver)
                          for i in range(args.workers)])
    records = read_records(args.summary or args.out)
    for row in summarize(records):
        print(summary_line(row))
    if args.figure:
        figure(records, args.figure)


if __name__ == "__main__":
    sys.exit(main())
