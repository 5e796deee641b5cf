"""Is the test behind a conditional limit calibrated? Its p-value at the truth, table by table.

Run:  .venv/bin/python -m validation drop_fit_checks --settings onset_low --tables 800 \
          --workers 2 --out fit-validation
      .venv/bin/python -m validation limit_calibration --records fit-validation \
          --setting onset_low --workers 2 --out limit-calibration
      .venv/bin/python -m validation limit_calibration --summary limit-calibration \
          --figure docs/figures/limit_calibration.png

A one-sided limit holds the truth or not: one bit a table, so 100 tables that report a
limit measure its 95 % to +-2.2 %. The test that sets a conditional limit
(:mod:`mcbat.stats.fit.selective`) says more: applied to the true value, its p-value is uniform
over the tables that report a limit when the test is calibrated, and the share of p-values
below 0.05, 0.10, 0.20 and 0.50 tests that at four levels at once. A truth on the
surrogate's plateau (nothing there can be excluded) has p = 1 and counts at no level below 1.

The tables are those of ``fit_validation`` whose fit reported a limit on ``mu`` (read from
``--records``); each is fitted again and tested by
:func:`harness.fit_validation.limit_p_value`, and its record appended as one JSON
line to DIR/<setting>.<worker>.jsonl, so an interrupted run goes on where it stopped.
"""

import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from harness.fit_validation import (  # noqa: E402
    SETTINGS,
    limit_p_value,
    p_value_shares,
    run_jobs,
)
from validation.drop_fit_checks import read_records  # noqa: E402


def worker(args):
    index, workers, tables, setting, out = args
    from mcbat.study import load_study

    study = load_study(ROOT / "studies" / "cross_nathan_2006.toml")
    done = {r["table"] for r in read_records(out) if r["setting"] == setting}
    for k in tables[index::workers]:
        if k in done:
            continue
        rec = limit_p_value(setting, k, study)
        with open(Path(out) / f"{setting}.{index}.jsonl", "a") as handle:
            handle.write(json.dumps(rec) + "\n")


def summary(records, setting):
    """Printed lines: the tables, how many the surrogate saw flat, and the shares of
    p-values at or below each level against the level."""
    these = [r for r in records if r["setting"] == setting and r.get("limit") is not None]
    tested = [r["p_value"] for r in these if r.get("flat")]
    held = sum(r["truth"] >= r["limit"] if r["status"] == "lower_limit"
               else r["truth"] <= r["limit"] for r in these)
    lines = [f"{setting}: {len(these)} tables with a limit on mu, {held} holding the truth; "
             f"{len(tested)} flat in the surrogate, {sum(p >= 1 for p in tested)} of them "
             f"with the truth on its plateau (p = 1)"]
    for level, share, error in p_value_shares(tested):
        lines.append(f"  p <= {level:.2f}: {100 * share:5.1f} % of the tables "
                     f"(uniform: {100 * level:.0f} +- {100 * error:.1f})")
    return lines


def figure(records, setting, path):
    """The p-values' empirical distribution against the uniform one, with the band that
    holds a uniform sample's share at each level 95 % of the time (pointwise, binomial)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    p = np.sort([r["p_value"] for r in records
                 if r["setting"] == setting and r.get("flat")])
    n = len(p)
    levels = np.linspace(0.0, 1.0, 201)
    share = np.searchsorted(p, levels, side="right") / n
    band = 1.96 * np.sqrt(levels * (1 - levels) / n)
    fig, ax = plt.subplots(figsize=(5.2, 4.4))
    ax.fill_between(levels, levels - band, levels + band, color="0.85",
                    label="uniform p-values: 95 % band")
    ax.plot(levels, levels, "k-", lw=0.8)
    ax.step(levels, share, where="post", color="C0",
            label=f"{n} tables with a limit, flat in the surrogate")
    ax.axvline(0.05, color="C3", lw=0.8, ls="--", label="0.05: the limit's level")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_xlabel("level a")
    ax.set_ylabel("share of tables with p-value at the truth <= a")
    ax.set_title(f"{setting}: the conditional test at the true mu", fontsize=10)
    ax.legend(fontsize=8, loc="upper left", frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"figure written to {path}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--records", metavar="DIR",
                        help="fit_validation's output: the tables whose fit gave a limit")
    parser.add_argument("--setting", default="onset_low", choices=tuple(SETTINGS))
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--out", default="limit-calibration")
    parser.add_argument("--summary", metavar="DIR", help="only summarise DIR")
    parser.add_argument("--figure", metavar="PATH",
                        help="also draw the p-values' distribution against the uniform (PNG)")
    args = parser.parse_args(argv)
    if not args.summary:
        if not args.records:
            parser.error("--records DIR is needed to run (or --summary DIR to summarise)")
        tables = sorted(r["table"] for r in read_records(args.records)
                        if r["setting"] == args.setting and "refused" not in r
                        and r["params"]["mu"].get("limit") is not None)
        if not tables:
            parser.error(f"no table of {args.setting!r} in {args.records} reports a limit")
        Path(args.out).mkdir(parents=True, exist_ok=True)
        run_jobs(worker, [(i, args.workers, tables, args.setting, args.out)
                          for i in range(args.workers)])
    records = read_records(args.summary or args.out)
    for line in summary(records, args.setting):
        print(line)
    if args.figure:
        figure(records, args.setting, args.figure)


if __name__ == "__main__":
    sys.exit(main())
