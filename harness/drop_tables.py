"""Drop-test measurement tables simulated by the independent reference solver.

A fit is only checked honestly against tables it did not simulate itself. These tables are
made without the kernel, the study machinery or ``mcbat.stats.measurements.synthesize``:
the geometry is written out here for the Cross & Nathan (2006) drop test (a ball dropped at
4 m/s across a cylindrical barrel at rest, onto its axis), every impact is solved by
``mcbat.testing.cabo2012_reference.reference_impact`` (``scipy.integrate.solve_ivp``),
and the measurement errors are added here. The table has the columns of a drop-test
measurement table (``docs/fitting.md``): ``impact_parameter`` (m, measured, with
``impact_parameter_err``), ``spin_in`` (rad/s, the nominal spin, exact), ``exit_speed`` (m/s),
``scattering_angle`` (deg), ``spin_out`` (rad/s), each observable with its ``_err``.
"""

import math

import numpy as np
import pandas as pd

from mcbat.testing.cabo2012_reference import reference_impact

__all__ = ["DROP_TEST", "design_stick_onset", "drop_table", "kernel_solver",
           "reference_solver", "stick_onset"]

DROP_TEST = {
    # The baseball and the Cross & Nathan (2006) bat of Sec. V of Cabo, Soler & Gonzalez
    # (docs/physics.md), written out here rather than read from mcbat's presets.
    "ball_mass": 0.145, "ball_radius": 0.036, "ball_inertia_factor": 0.4,
    "bat_mass": 0.989, "bat_transverse_inertia": 0.046, "bat_axial_inertia": 4.39e-4,
    "bat_radius": 0.03335, "cm_from_barrel_end": 0.265,
    "drop_speed": 4.0, "from_barrel_end": (0.14, 0.16),
}
"""The drop test's bodies (kg, m, kg m^2) and setup (m/s; contact range from the barrel
end, m)."""


def reference_solver(b, spin_in, axial, e, mu, e_x, rtol=1e-9):
    """Exit speed (m/s), scattering angle (deg) and outgoing spin (rad/s about the bat axis)
    of drops with true impact parameters ``b`` (m), incoming spins ``spin_in`` (rad/s) and
    contacts ``axial`` (m from the bat CM), each solved by the reference solver.

    Returns
    -------
    ndarray, (rows, 3)
    """
    d = DROP_TEST
    reach = d["ball_radius"] + d["bat_radius"]
    out = np.empty((len(b), 3))
    for i in range(len(b)):
        # The ball's centre line, along -x at offset b from the axis, touches the barrel
        # where the outward normal (cos a, sin a, 0) has sin a = b / (R + r).
        angle = math.asin(b[i] / reach)
        r = reference_impact(
            d["ball_mass"], d["ball_radius"], d["ball_inertia_factor"], d["bat_mass"],
            d["bat_transverse_inertia"], d["bat_axial_inertia"], axial[i], angle,
            d["bat_radius"], 0.0, (-d["drop_speed"], 0.0, 0.0), (0.0, 0.0, spin_in[i]),
            (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), mu, e, e_x, rtol=rtol, atol=1e-12 * rtol)
        v, w = r["ball_v"], r["ball_w"]
        out[i] = (math.sqrt(v @ v), math.degrees(math.atan2(v[1], v[0])), w[2])
    return out


def kernel_solver(b, spin_in, axial, e, mu, e_x):
    """As ``reference_solver``, solved by the kernel (the studies' default accuracy,
    agreeing with the reference to ~1e-9): the same tables thousands of times faster,
    for validation runs of many tables (``validation/drop_fit_checks.py --crosscheck``
    shows the two give the same tables)."""
    from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS, allocate_outputs, solve_batch
    from mcbat.core.status import ImpactStatus

    d = DROP_TEST
    n = len(b)
    values = {"ball_mass": d["ball_mass"], "ball_radius": d["ball_radius"],
              "ball_inertia_factor": d["ball_inertia_factor"], "bat_mass": d["bat_mass"],
              "bat_transverse_inertia": d["bat_transverse_inertia"],
              "bat_axial_inertia": d["bat_axial_inertia"], "axial": axial,
              "angle": np.arcsin(np.asarray(b) / (d["ball_radius"] + d["bat_radius"])),
              "bat_radius": d["bat_radius"], "bat_slope": 0.0, "ball_vx_in": -d["drop_speed"],
              "ball_wz_in": spin_in, "mu": mu, "e": e, "e_x": e_x}
    inputs = np.zeros((len(INPUT_FIELDS), n))
    for name, value in values.items():
        inputs[INPUT_FIELDS.index(name)] = value
    out, status, end = allocate_outputs(n)
    solve_batch(inputs, 8, 5e-9, 20000, out, status, end)  # the studies' default accuracy
    if (status != ImpactStatus.OK).any():
        raise RuntimeError(f"the kernel failed on {int((status != ImpactStatus.OK).sum())} drops")
    o = {name: out[i] for i, name in enumerate(OUTPUT_FIELDS)}
    v = np.stack([o["ball_vx"], o["ball_vy"], o["ball_vz"]], axis=1)
    return np.stack([np.linalg.norm(v, axis=1), np.degrees(np.arctan2(v[:, 1], v[:, 0])),
                     o["ball_wz"]], axis=1)


def drop_table(rows, seed, *, e=0.6, mu=0.18, e_x=0.0, impact_parameter=(-0.0254, 0.0254),
               impact_parameter_err=0.005, spins=(79.0, 0.0, -72.0), speed_err=0.03,
               angle_err=2.0, spin_err=(0.08, 2.0), edges=None, stated_errors="truth",
               solver=reference_solver):
    """A drop-test table of ``rows`` impacts.

    Parameters
    ----------
    rows, seed : int
        Number of rows and the seed of every random number.
    e, mu, e_x : float
        The truth: Stronge's ``e*``, the friction coefficient and the tangential
        restitution.
    impact_parameter : (float, float)
        Range (m) of the true impact parameters, drawn uniformly.
    edges : float, optional
        If given, the true impact parameters are drawn only within ``edges`` (m) of the
        ends of ``impact_parameter`` (half the rows at each end): tables at the edges of a
        study's range.
    impact_parameter_err : float
        1-sigma error (m) of the measured impact parameter; 0: exact, no ``_err`` column.
    spins : sequence of float
        Nominal incoming spins (rad/s about the bat axis), cycled over the rows.
    speed_err : float
        Relative error of the exit speed (of its true value, unless ``stated_errors`` is
        ``"constant"``).
    angle_err : float
        Error of the scattering angle (deg).
    spin_err : (float, float)
        Relative error of the outgoing spin and its floor (rad/s).
    stated_errors : {"truth", "measured", "constant"}
        The errors of the exit speed and the outgoing spin: relative to each row's true
        value, and stated as drawn (``"truth"``: an error that only a simulation knows,
        and that says something of the row's true value); relative to the true value, but
        stated relative to the measured one (``"measured"``, as a lab states it); or one
        error for all rows, the relative error of the rows' mean true value, drawn and
        stated (``"constant"``).
    solver : callable
        ``solver(b, spin_in, axial, e, mu, e_x)`` -> observables, (rows, 3):
        ``reference_solver`` by default. The random numbers do not depend on it, so two
        solvers give the same table up to their difference.

    Returns
    -------
    pandas.DataFrame
        The measurement table; ``attrs["truth"]`` holds the truth and the true impact
        parameters.
    """
    d = DROP_TEST
    rng = np.random.default_rng(seed)
    b_true = rng.uniform(*impact_parameter, rows)
    if edges is not None:
        lo, hi = impact_parameter
        near = rng.uniform(0.0, edges, rows)
        b_true = np.where(np.arange(rows) % 2 == 0, lo + near, hi - near)
    spin_in = np.resize(np.asarray(spins, float), rows)
    axial = d["cm_from_barrel_end"] - rng.uniform(*d["from_barrel_end"], rows)
    noise = rng.standard_normal((4, rows))
    out = solver(b_true, spin_in, axial, e, mu, e_x)
    speed_sd = speed_err * out[:, 0]
    spin_sd = np.maximum(spin_err[0] * np.abs(out[:, 2]), spin_err[1])
    table = pd.DataFrame({"impact_parameter": b_true})
    if impact_parameter_err > 0:
        table["impact_parameter"] = b_true + impact_parameter_err * noise[0]
        table["impact_parameter_err"] = impact_parameter_err
    table["spin_in"] = spin_in
    if stated_errors not in ("truth", "measured", "constant"):
        raise ValueError(f"stated_errors must be 'truth', 'measured' or 'constant', got "
                         f"{stated_errors!r}")
    if stated_errors == "constant":
        speed_sd = np.full(rows, speed_err * np.mean(out[:, 0]))
        spin_sd = np.full(rows, max(spin_err[0] * np.mean(np.abs(out[:, 2])), spin_err[1]))
    speed = out[:, 0] + speed_sd * noise[1]
    spin_out = out[:, 2] + spin_sd * noise[3]
    if stated_errors == "measured":
        speed_sd = speed_err * np.abs(speed)
        spin_sd = np.maximum(spin_err[0] * np.abs(spin_out), spin_err[1])
    table["exit_speed"] = speed
    table["exit_speed_err"] = speed_sd
    table["scattering_angle"] = out[:, 1] + angle_err * noise[2]
    table["scattering_angle_err"] = angle_err
    table["spin_out"] = spin_out
    table["spin_out_err"] = spin_sd
    table.attrs["truth"] = {"e": e, "mu": mu, "e_x": e_x, "impact_parameter": b_true,
                            "axial": axial}
    return table


def stick_onset(b, spin_in, axial, e, e_x, solver=kernel_solver, mu_max=2.0,
                spin_tolerance=1e-6, iterations=30):
    """The smallest friction coefficient at which each drop sticks: from there on its
    outgoing spin stays within ``spin_tolerance`` (rad/s) of its value at ``mu_max``
    (found by bisection).

    The spin is the mark of sticking: once the ball rolls, friction no longer sets it.
    The exit speed and angle still move a little with ``mu`` after that (by up to about
    1e-4 m/s and 2e-3 deg between the onset and ``mu = 2``: the ball's contact lies off
    the bat's centre of mass), a few thousandths of any measurement's error.

    Parameters
    ----------
    b, spin_in, axial : ndarray
        True impact parameters (m), incoming spins (rad/s) and contacts (m from the bat
        CM), as ``reference_solver`` takes them.
    e, e_x : float
        Stronge's ``e*`` and the tangential restitution.

    Returns
    -------
    ndarray
        Each drop's onset of sticking (to ``mu_max / 2**iterations``).
    """
    b, spin_in, axial = (np.asarray(x, float) for x in (b, spin_in, axial))
    stuck = solver(b, spin_in, axial, e, mu_max, e_x)
    lo, hi = np.zeros(len(b)), np.full(len(b), mu_max)
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        # The solver takes one mu: solve the rows at each of their own midpoints.
        out = np.stack([solver(b[i:i + 1], spin_in[i:i + 1], axial[i:i + 1], e, mid[i],
                               e_x)[0] for i in range(len(b))])
        sticks = np.abs(out[:, 2] - stuck[:, 2]) <= spin_tolerance
        hi = np.where(sticks, mid, hi)
        lo = np.where(sticks, lo, mid)
    return hi


def design_stick_onset(rows, seed, *, e=0.6, e_x=0.0, solver=kernel_solver, **design):
    """The onset of sticking of the table that ``drop_table`` draws for ``rows`` and
    ``seed`` (with the same ``impact_parameter``, ``edges`` and ``spins``): the largest of
    its drops' ``stick_onset``. With ``mu`` at this value every drop sticks, the
    last of them only just; the drops drawn do not depend on ``mu``."""
    drawn = {}

    def record(b, spin_in, axial, *_):
        drawn.update(b=b, spin_in=spin_in, axial=axial)
        return np.ones((len(b), 3))

    keep = {k: v for k, v in design.items() if k in ("impact_parameter", "edges", "spins")}
    drop_table(rows, seed, e=e, e_x=e_x, solver=record, **keep)
    return float(stick_onset(drawn["b"], drawn["spin_in"], drawn["axial"], e, e_x,
                             solver=solver).max())
