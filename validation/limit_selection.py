"""How often a one-sided limit holds the truth among the tables that report one.

Run:  .venv/bin/python -m validation limit_selection --tables 20000

A model with the shape of a drop test's friction, small enough to fit 10^4 tables a
second: row ``i`` observes ``y_i = slope * min(mu - stick_i, 0) + noise`` (unit noise), so
it depends on ``mu`` below its own stick threshold ``stick_i`` and not above (the drop
rolls off the bat). The thresholds are drawn uniformly per table. Each table's profile of
``-ln L`` in ``mu`` (exact, on a fine grid) is read as :mod:`mcbat.stats.fit.intervals` reads a
fit's: a side where the rise stays below 1/2 up to the end of the range gives a one-sided
95 % limit where the rise reaches 1.353.

It prints, per configuration, the share of tables that report a lower limit, how often
those limits hold the truth, and how often a limit excludes the truth among all tables.
Where limits are common, they hold the truth in about 95 % of the tables that report one;
where they are rare, a table reports one only when its noise made the few rows that slide
at the truth look stuck, and the same noise moves its limit above the truth: then the
limits hold the truth in well under 95 % of those tables, while the share of all tables
whose limit excludes the truth stays below 5 %. That is a property of choosing between an
interval and a limit from the data (Feldman & Cousins, Phys. Rev. D 57, 3873 (1998), call
it flip-flopping), not of a fit.
"""

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from mcbat.stats.fit.intervals import LIMIT_95, ONE_SIGMA  # noqa: E402

CONFIGURATIONS = (
    # rows, stick thresholds (low, high), slope of a sliding row's observable in mu
    (20, (0.08, 0.20), 40.0),
    (60, (0.08, 0.20), 40.0),
    (60, (0.00, 0.20), 300.0),
    (60, (0.10, 0.20), 100.0),
    (60, (0.15, 0.19), 200.0),
)
"""Configurations, from frequent limits to rare ones."""
TRUE_MU = 0.18
GRID = np.linspace(0.0, 0.5, 1001)


def table_limits(rows, stick, slope, tables, rng, true_mu=TRUE_MU):
    """Per table with a lower limit: whether the limit holds ``true_mu``; and the count of
    tables."""
    holds = []
    for _ in range(tables):
        thresholds = rng.uniform(*stick, rows)
        model = slope * np.minimum(GRID - thresholds[:, None], 0.0)
        y = slope * np.minimum(true_mu - thresholds, 0.0) + rng.standard_normal(rows)
        rise = 0.5 * ((y[:, None] - model) ** 2).sum(axis=0)
        best = int(rise.argmin())
        rise -= rise[best]
        if rise[best:].max() >= ONE_SIGMA:  # bounded above: an interval, not a limit
            continue
        beyond = np.nonzero(rise[:best + 1] >= LIMIT_95)[0]
        limit = GRID[beyond.max()] if len(beyond) else GRID[0]
        holds.append(limit <= true_mu)
    return np.array(holds, bool)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tables", type=int, default=20000,
                        help="tables per configuration (default 20000)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    print(f"truth mu = {TRUE_MU}; {args.tables} tables per configuration")
    for rows, stick, slope in CONFIGURATIONS:
        holds = table_limits(rows, stick, slope, args.tables, rng)
        n = len(holds)
        share = n / args.tables
        cover = holds.mean() if n else float("nan")
        se = np.sqrt(cover * (1 - cover) / n) if n else float("nan")
        print(f"rows {rows:3d}  thresholds {stick[0]:.2f}-{stick[1]:.2f}  slope {slope:5.0f}: "
              f"limits in {100 * share:5.1f} % of tables, holding the truth in "
              f"{100 * cover:5.1f} % (+-{100 * se:.1f}) of them; excluding it in "
              f"{100 * (n - holds.sum()) / args.tables:.2f} % of all tables")


if __name__ == "__main__":
    sys.exit(main())
