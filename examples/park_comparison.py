"""Park comparison: the batted balls of a Savant export flown again at every park, the
home runs each park would give and the median carry of the fly balls.

    python examples/park_comparison.py [SAVANT.csv] [--out park_comparison.png]

Without a file it reads the shipped day of games, data/statcast_2020-09-03.csv. Each park
flies every ball with its elevation, roof and climate normal for the ball's month, and calls
home runs against the fences standing on the ball's date (``mcbat replay FILE --park CODE``
for one park). Parks without a sourced fence height are left out.
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from mcbat.statcast import parks, read  # noqa: E402
from mcbat.statcast.replay import Conditions, replay, replay_summary  # noqa: E402

SHIPPED = Path(__file__).resolve().parents[1] / "data" / "statcast_2020-09-03.csv"

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("file", nargs="?", default=SHIPPED, help="a Savant export")
parser.add_argument("--out", default="park_comparison.png", help="the figure (PNG)")
args = parser.parse_args()

pitches = read(args.file)
rows = {}
for code in sorted({p["home_team"] for p in parks.parks()}):
    balls = replay(pitches, Conditions(park=code))
    park = balls["park"].dropna()
    if park.empty or balls["home_run"].isna().all() or park.iloc[0] in rows:
        continue  # no park for this code on these dates, no fence height, or seen
    rows[park.iloc[0]] = (code, replay_summary(balls))
as_played = replay_summary(balls)  # (the "as it was" numbers are the same for every park)

order = sorted(rows, key=lambda p: rows[p][1]["home_runs"])
fig, (left, right) = plt.subplots(1, 2, figsize=(11, 0.28 * len(order) + 1.5), sharey=True)
labels = [f"{rows[p][0]}  {p}" for p in order]
left.barh(labels, [rows[p][1]["home_runs"] for p in order], color="C0")
left.axvline(as_played["actual_home_runs"], color="k", ls="--", lw=1,
             label=f"in their own parks ({as_played['actual_home_runs']})")
left.set_xlabel("home runs (model's call at the fences)")
left.legend(loc="lower right", fontsize=8)
right.barh(labels, [rows[p][1]["median_distance_ft"] for p in order], color="C1")
right.axvline(as_played["median_actual_distance_ft"], color="k", ls="--", lw=1)
right.set_xlabel("median carry of the 20-50 deg fly balls, ft")
right.set_xlim(left=0.9 * min(rows[p][1]["median_distance_ft"] for p in order))
fig.suptitle(f"{Path(args.file).name}: {as_played['balls']} balls in play at every park")
fig.tight_layout()
fig.savefig(args.out, dpi=120)
best, worst = order[-1], order[0]
longest = max(rows, key=lambda p: rows[p][1]["median_distance_ft"])
print(f"{args.out}: {len(order)} parks; most home runs at {best} "
      f"({rows[best][1]['home_runs']}), fewest at {worst} ({rows[worst][1]['home_runs']}); "
      f"{as_played['actual_home_runs']} in their own parks; longest median carry at "
      f"{longest} ({rows[longest][1]['median_distance_ft']:.0f} ft)")
