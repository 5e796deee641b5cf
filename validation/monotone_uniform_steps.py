"""Why "monotone convergence in every case" is not a property of a step rule.

Run:  .venv/bin/python -m validation monotone_uniform_steps [--n 520] [--seed S]
          [--cache FILE] [--factors 0.5,0.3,0.15,0.07] [--jobs 2]

The criterion: for every case of the accuracy mix, tightening the tolerance 10-fold never
makes an error more than 2x worse (above 1e-13). The kernel violates it in about 0.6 % of
the cases, always with the same signature: the error at the looser tolerance is far below
its usual size, because parts of opposite sign nearly cancelled there.

This script shows that the same happens with the textbook step sequence: no error control
at all, and a smooth step function scaled uniformly with the tolerance,

    h = factor (T / 5e-9)^(1/4) / max(lambda, |turn|, stiffness)        (in tau, kg)

from the slip's own rates (``mcbat.core.cabo2012.slip_time.TauPoint``), with the kernel's
Lawson RK4 step, its impulse cap per step, its landing rule and its stop rule. Only the
stick impulse ``I_s`` is followed: slip from incidence to the landing on ``v_t = 0``,
events ignored, on the cases where the reference reports an ``I_s`` reached by sliding.
Such a sequence makes each case's error ``a h^4 + b h^5 + ...`` with the step ``h``
scaling exactly as the tolerance's 4th root; it still vanishes near ``h = -a/b``, and
some cases of a random mix put that point between two tested tolerances. Only when the
steps are small enough for ``a h^4`` to dominate at the loosest tolerance tested (the
asymptotic regime in every case) do the violations go, except where the answer is decided
by something other than the steps: a near miss of the slip speed stopped at a step's end
(see ``SLIP_RESOLUTION``), or the reference's own error. The factors in --factors show the
trade: the steps it takes, against the kernel's.

Printed, per step rule (the kernel's adaptive one, then each --factors): the cases
measured, the cases with a violation of the criterion in ``I_s`` between consecutive
tolerances 5e-7 ... 5e-11, the largest ``I_s`` error per tolerance and the mean steps.
The references come from the same cache as ``validation/kernel_accuracy.py``.
"""

import argparse
import math
import sys
import time

import numpy as np

from harness.accuracy_mix import (
    DEFAULT_SEED,
    MONOTONE_FACTOR,
    MONOTONE_FLOOR,
    contact_problem,
    draw_mix,
    kernel_errors,
)
from mcbat.core.cabo2012.contact import (
    DEFAULT_STEPS,
    DEFAULT_TOLERANCE,
    LAND_ACTION,
    STOP_ACTION,
    Contact,
    impulse_step_cap,
    slip_control,
    step_plan,
)
from mcbat.core.cabo2012.slip_time import tau_point, tau_step
from validation.kernel_accuracy import DEFAULT_TOLERANCES, load_or_compute_references

MAX_STEPS = 20_000


def uniform_step_stick_impulse(case, tolerance, factor):
    """``(I_s, steps)`` of one case with the uniformly scaled step function (module
    docstring); ``(nan, steps)`` if the slip does not reach its landing or stop."""
    _, _, k, v0 = contact_problem(case)
    c = Contact(k[0, 0], k[0, 1], k[0, 2], k[1, 1], k[1, 2], k[2, 2],
                v0[0], v0[1], v0[2], case["mu"])
    ctl = slip_control(c, tolerance, 1.0 / DEFAULT_STEPS)
    scale = factor * (tolerance / DEFAULT_TOLERANCE) ** 0.25
    w1, w2, imp, wfr = c.v01, c.v02, 0.0, 0.0
    for steps in range(MAX_STEPS):
        pt = tau_point(c, w1, w2)
        # The kernel's landing and stop rules; its step proposal is not used.
        action, _, _, _ = step_plan(ctl, pt, imp, math.inf, steps == 0)
        if action == STOP_ACTION:
            return imp, steps
        if action == LAND_ACTION:
            return imp + pt.s / (-pt.rate), steps  # the landing: v_t linear in I to zero
        lam = -pt.rate
        h = scale / max(abs(lam), abs(pt.turn), pt.stiffness, 1e-300)
        if not (lam >= 0.0 and pt.s * h <= ctl.impulse_max):
            h = min(h, impulse_step_cap(pt.s, lam, ctl.impulse_max))
        step = tau_step(c, w1, w2, imp, wfr, lam, h)
        w1, w2, imp, wfr = step.w1, step.w2, step.imp, step.wfr
    return math.nan, MAX_STEPS


def measured_cases(refs):
    """Indices of the cases whose reference reports an ``I_s > 0`` (slip that stops)."""
    return [i for i, r in enumerate(refs)
            if r["status"] == "ok" and r["stick_impulse"] > 0.0]


def violations(errors):
    """Cases (rows) where some 10-fold tightening (next column) makes the error more than
    ``MONOTONE_FACTOR`` worse, above ``MONOTONE_FLOOR``."""
    coarse, fine = errors[:, :-1], errors[:, 1:]
    bad = (fine > MONOTONE_FACTOR * coarse) & (fine > MONOTONE_FLOOR)
    return np.flatnonzero(bad.any(axis=1))


def report(label, errors, steps, cases_index):
    """One line per step rule: cases measured, cases in violation, max error per tolerance."""
    bad = violations(errors)
    worst = " ".join(f"{e:.1e}" for e in np.nanmax(errors, axis=0))
    mean_steps = " ".join(f"{s:.1f}" for s in steps.mean(axis=0))
    listed = ", ".join(str(cases_index[i]) for i in bad)
    print(f"{label:<28} {len(errors):>5} {len(bad):>4}   max I_s error {worst}   "
          f"steps {mean_steps}" + (f"\n{'':<28} cases: {listed}" if listed else ""))
    return len(bad)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=520, help="cases in the mix")
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED)
    parser.add_argument("--cache", metavar="FILE", help="pickle of the references")
    parser.add_argument("--factors", default="0.5,0.3,0.15,0.07",
                        help="factors of the uniform step function (comma-separated)")
    parser.add_argument("--jobs", type=int, default=2, help="processes for the references")
    args = parser.parse_args(argv)
    try:
        factors = [float(x) for x in args.factors.split(",")]
    except ValueError:
        print(f"--factors: not a list of numbers: {args.factors!r}", file=sys.stderr)
        return 2
    if args.n < 1 or not all(f > 0.0 for f in factors):
        print("--n and --factors must be positive", file=sys.stderr)
        return 2
    tolerances = DEFAULT_TOLERANCES
    cases = draw_mix(args.n, args.seed)
    refs, _, _ = load_or_compute_references(cases, args.seed, args.cache, args.jobs)
    index = measured_cases(refs)
    reference = np.array([refs[i]["stick_impulse"] for i in index])
    print(f"mix: n = {args.n}, seed = {args.seed}; I_s measured on {len(index)} cases "
          f"(reference slip that stops); tolerances "
          + ", ".join(f"{t:g}" for t in tolerances))
    print(f"{'step rule':<28} {'cases':>5} {'bad':>4}")

    kernel = [kernel_errors([cases[i] for i in index], [refs[i] for i in index], t)
              for t in tolerances]
    report("kernel (adaptive)", np.column_stack([e["stick_impulse"] for e in kernel]),
           np.column_stack([e["rk4_steps"] for e in kernel]), index)
    for factor in factors:
        t0 = time.perf_counter()
        values = np.empty((len(index), len(tolerances)))
        steps = np.empty_like(values)
        for j, tolerance in enumerate(tolerances):
            for row, i in enumerate(index):
                values[row, j], steps[row, j] = uniform_step_stick_impulse(
                    cases[i], tolerance, factor)
        errors = np.abs(values - reference[:, None]) / reference[:, None]
        errors[np.isnan(values)] = np.inf
        report(f"uniform steps, factor {factor:g}", errors, steps, index)
        print(f"{'':<28} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
