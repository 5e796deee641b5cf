"""Bat-speed scan: the real pitches of a Savant export met by swings of 60-85 mph, and what
each mph of bat speed buys: launch speed and the share of balls carried over 380 ft.

    python examples/bat_speed_scan.py [SAVANT.csv] [--samples N] [--out bat_speed_scan.png]

Without a file it reads the shipped day of games, data/statcast_2020-09-03.csv. The study
(written beside the figure as bat_speed_scan.toml) draws the right-handers' four-seamers
and sinkers of the file, a swing and a contact from the game presets' distributions
(studies/game_fastball.toml) but a bat speed uniform over 60-85 mph, and flies every ball
in Nathan's standard air. Its ``[summary]`` bins the bat speed and keeps only the
statistics (``--summary-only``: no rows stored), with the share above 380 ft and its
binomial error (docs/study-format.md).
"""

import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import mcbat  # noqa: E402

SHIPPED = Path(__file__).resolve().parents[1] / "data" / "statcast_2020-09-03.csv"

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("file", nargs="?", default=SHIPPED, help="a Savant export")
parser.add_argument("--samples", type=int, default=50_000, help="swings (default 50,000)")
parser.add_argument("--out", default="bat_speed_scan.png", help="the figure (PNG)")
args = parser.parse_args()

STUDY = f"""
[study]
name = "bat_speed_scan"
samples = {args.samples}
seed = 7

[ball]
preset = "baseball"
[bat]
preset = "r161"

[pitches]
file = {json.dumps(Path(args.file).resolve().as_posix())}
pitch_type = ["FF", "SI"]
p_throws = "R"
[pitches.fallback]
spin_axis = {{ dist = "uniform", low = 195, high = 240, unit = "deg" }}
[pitch]
spin_efficiency = 0.9

[swing]
bat_speed = {{ dist = "uniform", low = 60, high = 85, unit = "mph" }}
attack_angle = {{ dist = "truncnormal", mean = 10, std = 8.2, low = -35, high = 35, unit = "deg" }}
[swing.vertical_bat_angle]
dist = "truncnormal"
mean = -30
std = 6
low = -50
high = -10
unit = "deg"

[contact]
from_barrel_end = {{ dist = "truncnormal", mean = 6, std = 4.6, low = 0.5, high = 18, unit = "in" }}
undercut = {{ dist = "truncnormal", mean = 0.24, std = 0.94, low = -2, high = 2, unit = "in" }}

[friction]
mu = 0.5

[flight]
model = "nathan"

[summary]
by = {{ bat_speed = {{ bins = 10, low = 60, high = 85, unit = "mph" }} }}
columns = ["launch_speed", "hit_distance"]
quantiles = [0.5, 0.9]
share_above = {{ hit_distance = 380 }}
"""

out = Path(args.out).resolve()
study_file = out.with_name("bat_speed_scan.toml")
study_file.write_text(STUDY)
run = mcbat.run(study_file, out.with_name("bat_speed_scan"), summary_only=True,
                overwrite=True, progress=False)
table = mcbat.load_summary(run.directory)                     # one row per bat-speed bin
speed = (table["bat_speed_low"] + table["bat_speed_high"]) / 2

fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.5, 7), sharex=True)
top.plot(speed, table["launch_speed_p50"], "o-", label="median")
top.plot(speed, table["launch_speed_p90"], "s--", label="90th percentile")
top.set_ylabel("launch speed, mph")
top.legend()
bottom.errorbar(speed, 100 * table["hit_distance_above_380"],
                yerr=100 * table["hit_distance_above_380_err"], fmt="o-", capsize=3)
bottom.set_ylabel("balls carried over 380 ft, %")
bottom.set_xlabel("bat speed, mph")
share = run.summary["share_above"][0]
fig.suptitle(f"{Path(args.file).name}: {args.samples:,} swings at its right-handers' "
             f"fastballs\nover 380 ft: {100 * share['share']:.1f} +- "
             f"{100 * share['error']:.1f} % of all batted balls")
fig.tight_layout()
fig.savefig(out, dpi=120)
slope = (table["launch_speed_p50"].iloc[-1] - table["launch_speed_p50"].iloc[0]) / (
    speed.iloc[-1] - speed.iloc[0])
print(f"{args.out}: median launch speed +{slope:.2f} mph per mph of bat speed; over 380 ft "
      f"{100 * table['hit_distance_above_380'].iloc[0]:.1f} % at {speed.iloc[0]:g} mph, "
      f"{100 * table['hit_distance_above_380'].iloc[-1]:.1f} % at {speed.iloc[-1]:g} mph")
