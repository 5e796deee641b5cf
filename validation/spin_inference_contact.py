"""Where along the bat the inference puts a ball's contact when the swing was not
measured: the position at which the bat speeds inferred without the measured swing have
the measured swings' median, fitted on the tracked balls in play of the fit files, then
judged on the others (their slopes of backspin on launch angle, without and with their
measured swings, and Nathan's on the same balls).

    .venv/bin/python -m validation spin_inference_contact

Where the bat speed is measured the inference solves for the contact's position; where
it is not, it solves for the bat speed with the contact at one assumed position
(``SpinAssumptions.from_barrel_end``). At the sweet spot every ball is perfectly struck
and needs a bat 6-7 mph slower than Statcast measures; the spin it gives runs up to 12 %
above the measured-swing inference on the same balls. ``--fit`` and ``--judge`` take
export paths (default: the 2024 development exports fitted, the others judged); ``--also``
adds exports to judge (e.g. a fetched 2024 export without bat tracking, data/README.md).

Reads ``../shared/data/statcast/`` (relative to the repository; skipped where absent)
and the shipped ``data/`` exports.
"""

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from mcbat import statcast
from mcbat.inference import SpinAssumptions, infer_spin
from validation.spin_inference_slopes import ROOT, SHARED, nathan_backspin, slope

INCH = 0.0254
FIT = (SHARED / "statcast_2024_skubal.csv", SHARED / "statcast_2024_ohtani.csv")
JUDGE = (SHARED / "statcast_2025-05-01.csv", SHARED / "statcast_2021-09-01_10_11.csv",
         ROOT / "data" / "statcast_2020-09-03.csv", ROOT / "data" / "statcast_2019_darvish.csv")
GRID = (6.0, 8.0, 9.0, 10.0, 10.5, 11.0, 12.0)


def load(path):
    pitches = statcast.read(path)
    return pitches[statcast.balls_in_play(pitches)]


def unmeasured(balls, position_in):
    """The inference without the measured swing, the contact at ``position_in``."""
    a = dataclasses.replace(SpinAssumptions(), from_barrel_end=position_in * INCH)
    return infer_spin(balls, assumptions=a, use_bat_speed=False, use_attack_angle=False,
                      use_swing_plane=False)


def fit(paths, grid):
    """The position (in) whose inferred bat speeds have the measured median, pooled over
    the fit files' balls with a measured bat speed that converge both ways."""
    files = [load(p) for p in paths if Path(p).is_file()]
    measured = []
    for balls in files:
        ok = (infer_spin(balls)["inference_status"] == "converged").to_numpy()
        measured.append(ok & balls["bat_speed"].notna().to_numpy())
    target = np.median(np.concatenate([b["bat_speed"].to_numpy()[m]
                                       for b, m in zip(files, measured)]))
    medians = []
    for z in grid:
        runs = [unmeasured(b, z) for b in files]
        speed = np.concatenate([r["bat_speed"].to_numpy()[m & (r["inference_status"]
                                                                == "converged").to_numpy()]
                                for r, m in zip(runs, measured)])
        medians.append(float(np.median(speed)))
        print(f"  contact {z:4.1f} in from the barrel end: inferred bat speed median "
              f"{medians[-1]:.1f} mph (measured {target:.1f}; {speed.size} balls)")
    # the median rises with the position toward the handle: interpolate the crossing
    return float(np.interp(target, medians, grid)), target


def judge(paths, positions):
    print("| file | balls in play | measured swings | " + " | ".join(
        f"contact at {z:.1f} in: slope (converged)" for z in positions)
        + " | with its measured swings | Nathan on the same balls | bat speed median at "
        f"{positions[-1]:.1f} in: inferred / measured (mph) |")
    print("|---|---|---|" + "---|" * (len(positions) + 3))
    for path in paths:
        if not Path(path).is_file():
            continue
        balls = load(path)
        la = balls["launch_angle"].to_numpy()
        cells = []
        for z in positions:
            out = unmeasured(balls, z)
            ok = (out["inference_status"] == "converged").to_numpy()
            (s, _), n = slope(la, out["backspin"].to_numpy(), ok)
            cells.append(f"{s:.0f} ({ok.mean():.1%})")
        tracked = "bat_speed" in balls and balls["bat_speed"].notna().any()
        ref = infer_spin(balls)
        ok = (ref["inference_status"] == "converged").to_numpy()
        speeds = "–"
        if tracked:
            both = ok & (out["inference_status"] == "converged").to_numpy() \
                & balls["bat_speed"].notna().to_numpy()
            speeds = (f"{np.median(out['bat_speed'].to_numpy()[both]):.1f} / "
                      f"{np.median(balls['bat_speed'].to_numpy()[both]):.1f}")
        (sr, _), _ = slope(la, ref["backspin"].to_numpy(), ok)
        (sn, _), _ = slope(la, nathan_backspin(balls), ok)
        print(f"| {Path(path).name} | {len(balls)} | {'yes' if tracked else 'no'} | "
              + " | ".join(cells) + f" | {f'{sr:.0f}' if tracked else '–'} | {sn:.0f} | {speeds} |")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fit", nargs="*", default=[str(p) for p in FIT])
    parser.add_argument("--judge", nargs="*", default=[str(p) for p in JUDGE])
    parser.add_argument("--also", nargs="*", default=[], help="more exports to judge")
    args = parser.parse_args(argv)
    print("fit on: " + ", ".join(Path(p).name for p in args.fit))
    position, target = fit(args.fit, GRID)
    print(f"fitted: {position:.2f} in from the barrel end (the default: "
          f"{SpinAssumptions().from_barrel_end / INCH:.2f} in)")
    judge([*args.judge, *args.also], (6.0, SpinAssumptions().from_barrel_end / INCH))


if __name__ == "__main__":
    main()
