"""A hard random mix of impacts and the kernel's errors on it against the reference.

The kernel's accuracy is stated on a mix of at least 500 random impacts that includes
bats from 5 g to 5000 kg, spins up to 3000 rad/s, ``mu`` from 0 to 1, creeping slip and
re-slip. This module is the measuring instrument for that statement:

* ``harness.impact_mix.draw_mix`` draws the mix, deterministically from a seed
  (``harness.impact_mix``; its names are importable from here too);
* ``reference_for`` solves one case with the independent scipy integrator
  ``mcbat.testing.cabo2012_reference.reference_impact`` and keeps what the errors need;
* ``kernel_errors`` runs the batch kernel on the mix at a given tolerance and returns the
  per-case errors in the targets' units (``ERROR_COLUMNS``, ``TARGETS``).

``validation/kernel_accuracy.py`` prints the tables; ``tests/core/test_impact_mix.py`` checks
the mix and ``tests/core/test_accuracy_mix.py`` the measure. Unlike the reference solvers in
this package, this module imports the kernel: it exists to run it.

Error measures (per case; NaN where the column does not apply or the reference failed, inf
where the kernel failed or only one of the two solvers has a value):

``velocity``
    Largest of the six ball components ``|v - v_ref|`` and ``R |w - w_ref|`` (m/s), over
    ``|v_ball_out - v_ball_in|`` of the reference (the ball's velocity change).
``stick_impulse``
    ``|I_s - I_s,ref| / I_s,ref``, where the reference's slip stops (stick or re-slip). For
    an incidence without slip (``I_s,ref = 0``) the difference is taken relative to the
    normal impulse ``I_f,ref`` instead.
``normal_work``, ``friction_work``, ``stick_criterion``
    ``|W_n - W_n,ref|``, ``|W_fr - W_fr,ref|`` and ``|C - C_ref|`` over the incoming kinetic
    energy ``E_in``; ``C = -W_n(I_s)`` (the paper's stick criterion; NaN without stick).
"""

import math
import time

import numpy as np

from harness.impact_mix import (
    BASEBALL_BODIES,
    BASEBALL_MODES,
    CREEP_RATIO_OFFSET,
    DEFAULT_SEED,
    MAX_SPIN,
    MODES,
    SLIP_STYLES,
    case_vector,
    contact_problem,
    draw_mix,
    stick_rate,
)
from mcbat.core import status as kernel_status
from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS
from mcbat.testing.cabo2012_reference import reference_impact

__all__ = ["BASEBALL_BODIES", "BASEBALL_MODES", "CREEP_RATIO_OFFSET", "DEFAULT_SEED",
           "ERROR_COLUMNS", "MAX_SPIN", "MODES", "MONOTONE_FACTOR", "MONOTONE_FLOOR",
           "SLIP_STYLES", "TARGETS", "contact_problem", "draw_mix", "kernel_errors",
           "monotone_violations", "output_errors", "reference_for", "run_kernel",
           "stick_rate"]

ERROR_COLUMNS = ("velocity", "stick_impulse", "normal_work", "friction_work",
                 "stick_criterion")
"""Names of the per-case errors of ``kernel_errors`` (module docstring)."""

TARGETS = dict(velocity=1e-8, stick_impulse=1e-7, normal_work=1e-8, friction_work=1e-8,
               stick_criterion=1e-8)
"""The targets: bounds on the largest error of each column at the default tolerance."""

MONOTONE_FACTOR = 2.0
"""Monotone convergence: tightening the tolerance 10-fold may not make an error
more than this factor worse ..."""
MONOTONE_FLOOR = 1e-13
"""... unless the tighter error stays below this floor (rounding)."""

_OUT = {name: i for i, name in enumerate(OUTPUT_FIELDS)}


def reference_for(case, rtol=1e-12, slip_stop_fraction=None, stop_definition_fraction=None):
    """Solve one case with the independent reference integrator.

    Parameters
    ----------
    case : dict
        A case of ``draw_mix``.
    rtol : float
        Relative tolerance of the reference's DOP853 integration.
    slip_stop_fraction : float, optional
        Slip speed (relative to ``|v(0)|``) at which the reference's integration in ``I``
        hands over to the slip-scaled time; None for its default. With ``rtol``, the knob
        of the reference's own resolution.
    stop_definition_fraction : float, optional
        Slip speed (relative to ``|v(0)|``) below which a minimum of the slip speed is a
        stop; None for the definition shared with the kernel.

    Returns
    -------
    dict
        ``status`` ("ok", "not_approaching", or "failed" if the reference raised, with the
        exception in ``message``), ``ball_v``, ``ball_w`` (m/s, rad/s), ``ball_v_in`` (m/s),
        ``normal_impulse``, ``stick_impulse`` (kg m/s; NaN when slip never stops),
        ``normal_work``, ``friction_work``, ``normal_work_at_stick``, ``energy_in`` (J),
        ``end_state``, ``phases``, ``near_misses`` (minima of the slip speed that stayed
        above the reference's stick threshold) and the reference's wall time ``seconds``.
    """
    t0 = time.perf_counter()
    try:
        r = reference_impact(
            case["ball_mass"], case["ball_radius"], case["ball_inertia_factor"],
            case["bat_mass"], case["bat_transverse_inertia"], case["bat_axial_inertia"],
            case["axial"], case["angle"], case["bat_radius"], case["bat_slope"],
            case_vector(case, "ball_v"), case_vector(case, "ball_w"), case_vector(case, "bat_v"),
            case_vector(case, "bat_w"), case["mu"], case["e"], e_x=case["e_x"], rtol=rtol,
            slip_stop_fraction=slip_stop_fraction,
            stop_definition_fraction=stop_definition_fraction)
    except Exception as exc:  # a failure of the reference is an outcome to report
        nan = math.nan
        return dict(status="failed", message=f"{type(exc).__name__}: {exc}",
                    ball_v=np.full(3, nan), ball_w=np.full(3, nan),
                    ball_v_in=case_vector(case, "ball_v"), normal_impulse=nan, stick_impulse=nan,
                    normal_work=nan, friction_work=nan, normal_work_at_stick=nan,
                    energy_in=nan, end_state="", phases=[], near_misses=0,
                    seconds=time.perf_counter() - t0)
    stick = r["stick_impulse"]
    return dict(status=r["status"], message="", ball_v=r["ball_v"], ball_w=r["ball_w"],
                ball_v_in=case_vector(case, "ball_v"), normal_impulse=r["normal_impulse"],
                stick_impulse=math.nan if stick is None else float(stick),
                normal_work=r["normal_work"], friction_work=r["friction_work"],
                normal_work_at_stick=r["normal_work_at_stick"], energy_in=r["energy_in"],
                end_state=r["end_state"], phases=list(r["phases"]),
                near_misses=len(r["slip_near_misses"]), seconds=time.perf_counter() - t0)


def run_kernel(cases, tolerance, steps=DEFAULT_STEPS, max_steps=DEFAULT_MAX_STEPS):
    """Run the batch kernel on the cases.

    Parameters
    ----------
    cases : list of dict
        Cases of ``draw_mix``.
    tolerance : float
        The kernel's accuracy knob (impulse error per slip step relative to ``I_scale``).
    steps, max_steps : int
        The kernel's step cap per ``I_scale`` and its bound on RK4 steps.

    Returns
    -------
    out : numpy.ndarray
        float64[len(OUTPUT_FIELDS), n], rows named by ``mcbat.core.batch.OUTPUT_FIELDS``.
    status, end_state : numpy.ndarray
        int8[n] codes of ``mcbat.core.status``.
    """
    inputs = np.array([[float(c[name]) for c in cases] for name in INPUT_FIELDS],
                      dtype=np.float64).reshape(len(INPUT_FIELDS), len(cases))
    out, status, end_state = allocate_outputs(len(cases))
    solve_batch(inputs, steps, tolerance, max_steps, out, status, end_state)
    return out, status, end_state


def _difference(kernel, reference):
    """``|kernel - reference|``; NaN if both are NaN (not applicable), inf if only one is."""
    kernel = np.asarray(kernel, dtype=float)
    reference = np.asarray(reference, dtype=float)
    diff = np.abs(kernel - reference)
    return np.where(np.isnan(kernel) != np.isnan(reference), np.inf, diff)


def output_errors(cases, refs, out, status):
    """Per-case errors of kernel outputs against the references (module docstring).

    Parameters
    ----------
    cases : list of dict
        Cases of ``draw_mix``.
    refs : list of dict
        ``reference_for`` of each case.
    out : numpy.ndarray
        float64[len(OUTPUT_FIELDS), n] kernel outputs (rows named by ``OUTPUT_FIELDS``).
    status : numpy.ndarray
        int[n] kernel status codes.

    Returns
    -------
    dict of numpy.ndarray
        float64[n] per column of ``ERROR_COLUMNS`` (dimensionless).
    """
    n = len(cases)
    row = {name: out[_OUT[name]] for name in OUTPUT_FIELDS}
    errors = {name: np.full(n, np.nan) for name in ERROR_COLUMNS}
    for i, (case, ref) in enumerate(zip(cases, refs)):
        if ref["status"] != "ok":
            continue  # no reference: nothing is measured
        if status[i] != kernel_status.OK:
            for name in ERROR_COLUMNS:
                errors[name][i] = np.inf
            continue
        ball_v = np.array([row["ball_vx"][i], row["ball_vy"][i], row["ball_vz"][i]])
        ball_w = np.array([row["ball_wx"][i], row["ball_wy"][i], row["ball_wz"][i]])
        components = np.concatenate([
            _difference(ball_v, ref["ball_v"]),
            case["ball_radius"] * _difference(ball_w, ref["ball_w"])])
        change = np.linalg.norm(np.asarray(ref["ball_v"]) - np.asarray(ref["ball_v_in"]))
        errors["velocity"][i] = components.max() / change

        stick = _difference(row["stick_impulse"][i], ref["stick_impulse"])
        if ref["stick_impulse"] > 0.0:
            errors["stick_impulse"][i] = stick / ref["stick_impulse"]
        else:  # incidence without slip (or NaN: the NaN/inf of the difference carries)
            errors["stick_impulse"][i] = stick / ref["normal_impulse"]

        energy_in = ref["energy_in"]
        errors["normal_work"][i] = _difference(row["normal_work"][i],
                                               ref["normal_work"]) / energy_in
        errors["friction_work"][i] = _difference(row["friction_work"][i],
                                                 ref["friction_work"]) / energy_in
        errors["stick_criterion"][i] = _difference(
            row["stick_criterion"][i], -ref["normal_work_at_stick"]) / energy_in
    return errors


def kernel_errors(cases, refs, tolerance, steps=DEFAULT_STEPS, max_steps=DEFAULT_MAX_STEPS):
    """The kernel's per-case errors on the mix at one tolerance.

    Parameters
    ----------
    cases : list of dict
        Cases of ``draw_mix``.
    refs : list of dict
        ``reference_for`` of each case.
    tolerance : float
        The kernel's accuracy knob (see ``run_kernel``).
    steps, max_steps : int
        The kernel's step cap per ``I_scale`` and its bound on RK4 steps.

    Returns
    -------
    dict of numpy.ndarray
        float64[n] per column of ``ERROR_COLUMNS`` (module docstring), plus
        ``rk4_steps`` (RK4 steps per impact) and ``status`` (int8 kernel status codes).
    """
    out, status, _ = run_kernel(cases, tolerance, steps, max_steps)
    errors = output_errors(cases, refs, out, status)
    errors["rk4_steps"] = out[_OUT["rk4_steps"]].copy()
    errors["status"] = status
    return errors


def monotone_violations(coarse, fine):
    """Where tightening the tolerance made an error worse than monotone convergence allows.

    Parameters
    ----------
    coarse, fine : dict of numpy.ndarray
        ``kernel_errors`` at a tolerance ``T`` and at ``T / 10``.

    Returns
    -------
    dict of numpy.ndarray
        bool[n] per column of ``ERROR_COLUMNS``: ``fine > MONOTONE_FACTOR * coarse`` and
        ``fine > MONOTONE_FLOOR``. A column that does not apply (NaN) never counts; an
        error that becomes inf does.
    """
    return {name: (fine[name] > MONOTONE_FACTOR * coarse[name])
            & (fine[name] > MONOTONE_FLOOR) for name in ERROR_COLUMNS}
