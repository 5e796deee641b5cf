"""Convergence order of the kernel under step refinement.

* A 3D impact that ends while sliding: fixed-step RK4 in I, error ~ steps^-4.
* The paper's Sec. V case: the stick impulse I_s, located by the zero-slip detection,
  converges at >= 3rd order in the step count (a naive RK4 converges at first order there).
"""

import math

import numpy as np

from tests.conftest import kernel

SLIDING_CASE = dict(ball_v=(-4.0, 0.5, 1.0), ball_w=(60.0, -40.0, 150.0), bat_v=(0.5, 0.0, 0.2),
                    bat_w=(0.0, 3.0, 1.0), angle=0.4, mu=0.05, e=0.6)


def _order(steps, errors):
    """Least-squares slope of -log(error) against log(steps)."""
    slope, _ = np.polyfit(np.log(steps), np.log(errors), 1)
    return -slope


def _ball_velocity(r):
    return np.array([r["ball_vx"], r["ball_vy"], r["ball_vz"]])


def test_fourth_order_while_sliding():
    # slip_resolution is coarse so the fixed I-step (steps per impact impulse) is what refines.
    ref = kernel(settings=(8192, 0.5, 10**6), **SLIDING_CASE)
    assert ref["end_state"] == 0 and math.isnan(ref["stick_impulse"])
    rows = []
    for n in (4, 8, 16, 32, 64):
        r = kernel(settings=(n, 0.5, 10**6), **SLIDING_CASE)
        assert r["end_state"] == 0
        err = np.max(np.abs(_ball_velocity(r) - _ball_velocity(ref)))
        rows.append((n, r["rk4_steps"], err))
    nominal, taken, errors = np.array(rows).T
    # The step is h = I_scale / n; the impact ends at I_f < I_scale, so fewer are taken.
    order = _order(nominal, errors)
    print(f"\nsliding case: steps per I_scale {nominal.astype(int).tolist()}, taken "
          f"{taken.astype(int).tolist()}, errors {errors.tolist()}, order {order:.2f}")
    assert 3.5 <= order <= 4.5
    assert np.all(np.diff(errors) < 0)


def test_stick_impulse_high_order_on_paper_case():
    ref = kernel(mu=0.5, e=1.0, settings=(16, 0.003, 10**6))["stick_impulse"]
    rows = []
    for resolution in (0.1, 0.05, 0.025, 0.0125):
        r = kernel(mu=0.5, e=1.0, settings=(16, resolution, 10**6))
        rows.append((r["rk4_steps"], abs(r["stick_impulse"] - ref)))
    steps, errors = np.array(rows).T
    order = _order(steps, errors)
    print(f"\npaper case I_s: steps {steps.astype(int).tolist()}, errors {errors.tolist()}, "
          f"order {order:.2f}")
    assert order >= 3.0
    # The default resolution already locates I_s far better than the paper did (4e-4).
    default = kernel(mu=0.5, e=1.0)["stick_impulse"]
    assert abs(default - ref) / ref < 1e-7
