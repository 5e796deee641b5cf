"""Inferred spin of the shipped real balls in play against Nathan's average spin model.

Reads the Statcast files shipped in ``data/`` (data/README.md: provenance), infers every
ball in play's contact and spin under the default assumptions (the game presets), and
prints the convergence counts and, per launch-angle bin, the median inferred backspin
and sidespin next to the median of Nathan's trajectory calculator's average spin model
for the same balls (right-handed batter: backspin ~ -763 + 120 LA + 21 phi,
sidespin ~ -849 - 94 phi, rpm, phi the spray angle in deg; a left-handed batter's ball
is compared in the mirror image: phi -> -phi, sidespin -> -sidespin). Nothing is tuned.

    .venv/bin/python -m validation spin_inference_real
"""

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from mcbat import statcast
from mcbat.inference import infer_spin

ROOT = Path(__file__).resolve().parents[1]
FILES = ("statcast_2020-09-03.csv", "statcast_2019_darvish.csv", "statcast_2014_jeter.csv")
BINS = (-90, -20, -10, 0, 10, 20, 30, 40, 50, 90)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.parse_args(argv)
    frames = []
    for name in FILES:
        pitches = statcast.read(ROOT / "data" / name)
        frames.append(pitches[statcast.balls_in_play(pitches)])
    balls = pd.concat(frames, ignore_index=True)
    out = infer_spin(balls)
    counts = out.attrs["status_counts"]
    usable = len(balls) - counts["missing_input"]
    print(f"balls in play: {len(balls)} ({', '.join(FILES)}); with every input: {usable}")
    print(f"status: {counts}; converged {counts['converged'] / usable:.1%} of those with "
          "every input\n")
    ok = (out["inference_status"] == "converged").to_numpy()
    hand = np.where(balls["handedness"] == "L", -1.0, 1.0)
    phi = balls["spray_angle"].to_numpy() * hand  # batter's frame: > 0 opposite field
    la = balls["launch_angle"].to_numpy()
    nathan_back = -763 + 120 * la + 21 * phi
    nathan_side = -849 - 94 * phi
    back = out["backspin"].to_numpy()
    side = out["sidespin"].to_numpy() * hand
    print("| launch angle (deg) | balls | median backspin, inferred (rpm) | Nathan's model "
          "(rpm) | ratio | median sidespin, inferred (rpm, RHB sign) | Nathan's model |")
    print("|---|---|---|---|---|---|---|")
    for lo, hi in zip(BINS[:-1], BINS[1:]):
        sel = ok & (la >= lo) & (la < hi)
        if not sel.any():
            continue
        b, nb = np.median(back[sel]), np.median(nathan_back[sel])
        print(f"| [{lo}, {hi}) | {sel.sum()} | {b:.0f} | {nb:.0f} | "
              f"{b / nb if abs(nb) > 200 else float('nan'):.2f} | {np.median(side[sel]):.0f} | "
              f"{np.median(nathan_side[sel]):.0f} |")
    sel = ok & (la >= 10) & (la < 40)
    slope = np.polyfit(la[sel], back[sel], 1)[0]
    print(f"\nbackspin per degree of launch angle, 10-40 deg (least squares): {slope:.0f} rpm "
          "(Nathan: 120)")


if __name__ == "__main__":
    main()
