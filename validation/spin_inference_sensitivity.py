"""How the inferred spin moves with the assumptions (the table of docs/spin_inference.md).

Balls are simulated with the game kernel from known contacts under the default
assumptions (the game presets: attack angle 10 deg, vertical bat angle -30 deg, contact
6 in from the barrel end, mu 0.5, the game restitution), on sampled pitches, bat speeds,
undercuts and attack directions. The inference is then run on the same launch numbers,
with the attack angle taken as known (``attack_angle_nodes = 1``: the assumption whose
change is measured, not averaged over), once with the true assumptions (it must give the
truth back) and once per changed assumption; the table gives the median change of the
inferred backspin, sidespin and spin rate against the truth, and the fraction of balls
still reproduced.

    .venv/bin/python -m validation spin_inference_sensitivity --n 400
"""

import argparse
import dataclasses
import math

import numpy as np
import pandas as pd

from mcbat.bodies.restitution import GAME_RESTITUTION
from mcbat.inference import InferenceOptions, SpinAssumptions, infer_spin, predict_batted_balls

DEG = math.pi / 180


def simulate(n, seed):
    rng = np.random.default_rng(seed)
    table = pd.DataFrame({
        "pitch_speed": rng.normal(86, 6, n).clip(70, 100),
        "vertical_approach_angle": rng.normal(-6.5, 1.5, n).clip(-12, -2),
        "horizontal_approach_angle": rng.normal(0, 1.5, n).clip(-5, 5),
        "spin_rate": rng.normal(2250, 300, n).clip(1200, 3200),
        "spin_axis": rng.uniform(0, 360, n),
        "handedness": np.where(rng.random(n) < 0.6, "R", "L"),
    })
    balls = predict_batted_balls(table, undercut=rng.uniform(-0.025, 0.025, n),
                                 attack_direction=rng.normal(0, 8, n).clip(-30, 30),
                                 bat_speed=rng.normal(71.5, 4, n).clip(60, 82))
    ok = (balls["status"] == "ok").to_numpy()
    table = table.assign(launch_speed=balls["launch_speed"],
                         launch_angle=balls["launch_angle"], spray_angle=balls["spray_angle"])
    return table[ok].reset_index(drop=True), balls[ok].reset_index(drop=True)


def variants():
    base = SpinAssumptions()
    rest = GAME_RESTITUTION
    yield "none (the truth)", base
    for d in (-10, 10):
        yield (f"vertical bat angle {d:+d} deg",
               dataclasses.replace(base, vertical_bat_angle=base.vertical_bat_angle + d * DEG))
    for d in (-5, 5):
        yield (f"attack angle {d:+d} deg",
               dataclasses.replace(base, attack_angle=base.attack_angle + d * DEG))
    for d in (-0.03, 0.03):
        yield (f"e* {d:+.2f} (e_ref)",
               dataclasses.replace(base, restitution=dataclasses.replace(rest,
                                                                         e_ref=rest.e_ref + d)))
    for d in (-0.1, 0.1):
        yield f"mu {d:+.1f}", dataclasses.replace(base, mu=base.mu + d)
    for d in (-0.1, 0.1):
        yield (f"e_x {d:+.2f}",
               dataclasses.replace(base, restitution=dataclasses.replace(rest,
                                                                         e_x=rest.e_x + d)))
    yield "e_x = 0 (rigid)", dataclasses.replace(
        base, restitution=dataclasses.replace(rest, e_x=0.0))
    for d in (-1.0, 1.0):
        yield (f"contact {d:+.0f} in from the barrel end",
               dataclasses.replace(base, from_barrel_end=base.from_barrel_end + d * 0.0254))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=400)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args(argv)
    table, truth = simulate(args.n, args.seed)
    print(f"{len(table)} simulated balls; median launch angle "
          f"{table['launch_angle'].median():.1f} deg, backspin {truth['backspin'].median():.0f} "
          f"rpm, |sidespin| {truth['sidespin'].abs().median():.0f} rpm\n")
    print("| assumption changed | reproduced | median backspin change (rpm) | "
          "median sidespin change (rpm, RHB sign) | median spin-rate change |")
    print("|---|---|---|---|---|")
    for label, assumptions in variants():
        out = infer_spin(table, assumptions=assumptions,
                         options=InferenceOptions(attack_angle_nodes=1))
        ok = (out["inference_status"] == "converged").to_numpy()
        d_back = (out["backspin"] - truth["backspin"])[ok]
        # sidespin in the right-handed batter's sign (a mirror image flips it)
        hand = np.where(table["handedness"] == "L", -1.0, 1.0)
        d_side = ((out["sidespin"] - truth["sidespin"]) * hand)[ok]
        rel = ((out["spin_rate"] - truth["spin_rate"]) / truth["spin_rate"])[ok]
        print(f"| {label} | {ok.mean():.1%} | {d_back.median():+.0f} | {d_side.median():+.0f} "
              f"| {rel.median():+.1%} |")


if __name__ == "__main__":
    main()
