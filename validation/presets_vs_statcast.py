"""The fitted game presets against the real balls in play they were fitted to.

Runs each preset, and prints the two-sample Kolmogorov-Smirnov distances of its launch
speed and launch angle from the 424 balls in play (with both) of
``data/statcast_2020-09-03_in_play.csv``, the shares of weak contact (< 80 mph) and of
pop-ups (> 50 deg) on both sides, and the median backspin per 5 deg of launch angle over
15-40 deg against Nathan's average spin model evaluated on the same balls
(``docs/batting.md``, "Presets fitted to real balls in play")::

    NUMBA_NUM_THREADS=1 .venv/bin/python -m validation presets_vs_statcast --samples 20000

The game presets meet one pitch type each; they are compared with the balls in play of
that type too (four-seamers and sinkers; curveballs and knuckle curves).
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

import mcbat
from mcbat.statcast import read
from mcbat.statcast.spin import nathan_average_spin
from mcbat.stats.compare.comparison import ks_test

ROOT = Path(__file__).resolve().parents[1]
REAL = ROOT / "data" / "statcast_2020-09-03_in_play.csv"
PRESETS = {"mlb_balls_in_play": None, "game_fastball": ("FF", "SI"),
           "game_curveball": ("CU", "KC")}


def real_balls(types=None):
    """The in-play rows with launch speed and angle (of ``types`` if given)."""
    t = read(REAL)
    if types is not None:
        t = t[t["pitch_type"].isin(types)]
    t = t[t["launch_speed"].notna() & t["launch_angle"].notna()]
    return t["launch_speed"].to_numpy(float), t["launch_angle"].to_numpy(float)


def simulate(name, samples, seed=None):
    """The preset's batted balls (status 0)."""
    study = mcbat.load_study(ROOT / "studies" / f"{name}.toml")
    with tempfile.TemporaryDirectory() as tmp:
        mcbat.run(study, Path(tmp) / "d", samples=samples, seed=seed, progress=False)
        df = mcbat.load(Path(tmp) / "d", columns=["launch_speed", "launch_angle",
                                                  "spray_angle", "backspin", "sidespin",
                                                  "handedness", "status"])
    return df[df["status"] == 0]


def spin_rows(df):
    """Median backspin (ours, Nathan's) per 5 deg over 15-40 deg, and the sidespin spread."""
    la = df["launch_angle"].to_numpy()
    back, side = nathan_average_spin(la, df["spray_angle"].to_numpy(),
                                     np.where(df["handedness"] > 0, "R", "L"))
    rows = []
    for low in range(15, 40, 5):
        m = (la >= low) & (la < low + 5)
        rows.append((low, int(m.sum()), float(np.median(df["backspin"].to_numpy()[m])),
                     float(np.median(back[m]))))
    m = (la >= 15) & (la < 40)
    d = df["sidespin"].to_numpy()[m] - side[m]
    return rows, (float(np.median(df["sidespin"].to_numpy()[m])), float(np.median(side[m])),
                  *np.percentile(d, [10, 90]), float(np.std(d)))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=20000)
    parser.add_argument("--seed", type=int, default=None, help="default: each study's")
    parser.add_argument("--presets", default=",".join(PRESETS),
                        help="comma-separated, of: " + ", ".join(PRESETS))
    args = parser.parse_args(argv)
    for name in args.presets.split(","):
        types = PRESETS[name]
        df = simulate(name, args.samples, args.seed)
        ls, la = df["launch_speed"].to_numpy(), df["launch_angle"].to_numpy()
        for label, sel in (("all balls in play", None), ("same pitch types", types)):
            if label == "same pitch types" and types is None:
                continue
            rs, ra = real_balls(sel)
            print(f"{name} vs {label} ({len(rs)} real, {len(ls)} simulated): "
                  f"KS launch_speed {ks_test(ls, rs)['statistic']:.3f}, "
                  f"launch_angle {ks_test(la, ra)['statistic']:.3f}; "
                  f"< 80 mph {np.mean(ls < 80):.1%} (real {np.mean(rs < 80):.1%}), "
                  f"> 50 deg {np.mean(la > 50):.1%} (real {np.mean(ra > 50):.1%}); "
                  f"median {np.median(ls):.1f} mph (real {np.median(rs):.1f}), "
                  f"sd {np.std(ls):.1f} (real {np.std(rs):.1f})")
        rows, side = spin_rows(df)
        print("  backspin median per 5 deg (ours / Nathan's, ratio): " + "; ".join(
            f"{lo}-{lo + 5}: {o:.0f} / {n:.0f} ({o / n:.2f})" for lo, _, o, n in rows))
        print(f"  sidespin 15-40 deg: median {side[0]:.0f} rpm (Nathan {side[1]:.0f}); "
              f"ours - Nathan's, ball by ball: 10-90 % {side[2]:.0f} to {side[3]:.0f}, "
              f"sd {side[4]:.0f} rpm")


if __name__ == "__main__":
    main()
