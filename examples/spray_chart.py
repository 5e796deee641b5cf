"""A spray chart of a Savant export: where the model lands every ball in play, home runs
called against the fences, the measured home runs circled.

    python examples/spray_chart.py [SAVANT.csv] [--park COL] [--out spray_chart.png]

Without a file it reads the shipped day of games, data/statcast_2020-09-03.csv. Each ball
is flown with its measured launch speed, launch angle and spray angle (Nathan's average
spin, its season's ball) in its own park and air, or at ``--park`` (a Statcast
``home_team`` code); ``mcbat replay FILE --out balls.csv`` writes the same table.
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from mcbat.statcast import parks, read  # noqa: E402
from mcbat.statcast.replay import Conditions, replay  # noqa: E402

SHIPPED = Path(__file__).resolve().parents[1] / "data" / "statcast_2020-09-03.csv"

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("file", nargs="?", default=SHIPPED, help="a Savant export")
parser.add_argument("--park", help="fly every ball at this team's park (COL, MIA, ...)")
parser.add_argument("--out", default="spray_chart.png", help="the figure (PNG)")
args = parser.parse_args()

balls = replay(read(args.file), Conditions(park=args.park))   # one row per ball in play
air = balls[balls["launch_angle"] > 10]                       # line drives and fly balls
home_run = air["home_run"].fillna(False).astype(bool)
measured = air["events"] == "home_run"

fig, ax = plt.subplots(figsize=(7, 6.5))
ax.scatter(air["landing_x"][~home_run], air["landing_y"][~home_run], s=12, alpha=0.6,
           label="in the park")
ax.scatter(air["landing_x"][home_run], air["landing_y"][home_run], s=18, color="C3",
           label="home run (model)")
ax.scatter(air["landing_x"][measured], air["landing_y"][measured], s=70, facecolors="none",
           edgecolors="k", linewidths=0.8, label="home run (game)")
for r in (200, 300, 400):                                     # distance arcs, ft
    a = np.radians(np.linspace(-45, 45, 91))
    ax.plot(r * np.sin(a), r * np.cos(a), color="0.85", lw=0.8, zorder=0)
ax.plot([-350, 0, 350], [350, 0, 350], color="0.6", lw=0.8, zorder=0)  # foul lines
if args.park:                                                 # that park's fence, today
    park_id = balls["park"].dropna().iloc[0]
    angles = np.linspace(-45, 45, 181)
    distance, _ = parks.fence(park_id, angles)
    ax.plot(distance * np.sin(np.radians(angles)), distance * np.cos(np.radians(angles)),
            color="k", lw=1.5, label=f"fence: {park_id}")
where = f"at {args.park}" if args.park else "in their own parks"
ax.set_title(f"{Path(args.file).name}: {len(air)} balls in the air {where}\n"
             f"{home_run.sum()} home runs by the model, {measured.sum()} in the games")
ax.set_xlabel("landing x, ft (towards right field)")
ax.set_ylabel("landing y, ft (towards centre field)")
ax.set_aspect("equal")
ax.set_xlim(-420, 420)
ax.set_ylim(-20, 520)
ax.legend(loc="lower left", fontsize=8)
fig.savefig(args.out, dpi=120, bbox_inches="tight")
print(f"{args.out}: {len(air)} balls, {home_run.sum()} home runs {where}")
