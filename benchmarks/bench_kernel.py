"""Single-thread throughput of the impact kernel on a randomized mix, default accuracy.

Run:  .venv/bin/python -m benchmarks kernel [--n 200000] [--repeats 5]

The mix: the Sec. V bat and ball, contact 0-30 cm towards the barrel from the CM and at
any azimuth within +-70 deg, ball speed 2-40 m/s with a random transverse component, spins
up to 300 rad/s on all axes, a moving and spinning bat, mu in [0, 1], e* in [0, 1]. The
figure is the median of ``--repeats`` timed runs after a warm-up (compilation excluded).
"""

import argparse

import numpy as np

import harness
from mcbat.core.cabo2012 import solve_impact
from mcbat.core.cabo2012.contact import (
    DEFAULT_MAX_STEPS,
    DEFAULT_STEPS,
    DEFAULT_TOLERANCE,
    Accuracy,
)
from mcbat.core.cabo2012.impact import ImpactInputs
from mcbat.core.jit import njit

#: python -m benchmarks --quick kernel
QUICK_ARGS = ["--n", "20000", "--repeats", "3"]


@njit
def _solve_all(axial, angle, speed, v_side, w, vb, wb, mu, e, out_status, out_steps):
    for i in range(axial.shape[0]):
        r = solve_impact(ImpactInputs(
            0.145, 0.036, 0.4, 0.989, 0.046, 4.39e-4, axial[i], angle[i], 0.03335, 0.0,
            -speed[i] * np.cos(angle[i]), -speed[i] * np.sin(angle[i]) + v_side[i, 0],
            v_side[i, 1], w[i, 0], w[i, 1], w[i, 2],
            vb[i, 0], vb[i, 1], vb[i, 2], wb[i, 0], wb[i, 1], wb[i, 2], mu[i], e[i], 0.0),
            Accuracy(DEFAULT_STEPS, DEFAULT_TOLERANCE, DEFAULT_MAX_STEPS))
        out_status[i] = r[0]
        out_steps[i] = r[-1]


def random_mix(n, seed=20261121):
    rng = np.random.default_rng(seed)
    return dict(
        axial=rng.uniform(0.0, 0.30, n), angle=rng.uniform(-1.2, 1.2, n),
        speed=rng.uniform(2.0, 40.0, n), v_side=rng.uniform(-3.0, 3.0, (n, 2)),
        w=rng.uniform(-300.0, 300.0, (n, 3)), vb=rng.uniform(-2.0, 2.0, (n, 3)),
        wb=rng.uniform(-20.0, 20.0, (n, 3)), mu=rng.uniform(0.0, 1.0, n),
        e=rng.uniform(0.0, 1.0, n))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    mix = random_mix(args.n)
    status = np.empty(args.n, np.int64)
    steps = np.empty(args.n, np.int64)
    small = {k: v[:100] for k, v in mix.items()}
    _solve_all(**small, out_status=status[:100], out_steps=steps[:100])  # compile / load
    timing = harness.median_time(
        lambda: _solve_all(**mix, out_status=status, out_steps=steps), args.repeats, warmup=0)
    times, med = timing.times, timing.median
    print(f"machine: {harness.machine_line()}")
    print(f"impacts: {args.n}, repeats: {args.repeats}, median {med:.3f} s "
          f"(min {min(times):.3f}, max {max(times):.3f})")
    print(f"single-thread kernel throughput: {args.n / med:,.0f} impacts/s")
    print(f"status ok: {np.mean(status == 0):.4f}, RK4 steps per impact: mean "
          f"{steps.mean():.1f}, max {steps.max()}")
    harness.record("kernel", {
        "impacts_per_s": args.n / med, "median_s": med, "times_s": list(times),
        "ok_fraction": float(np.mean(status == 0)), "steps_mean": float(steps.mean()),
    }, {"impacts": args.n, "repeats": args.repeats, "threads": 1,
        "mix": "uniform random, Sec. V bodies, seed 20261121"})


if __name__ == "__main__":
    main()
