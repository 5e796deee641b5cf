"""Game measurement tables simulated without mcbat's game machinery.

A game fit (``mcbat.stats.fit.estimate.fit`` with a game study) is only checked honestly against
tables it did not simulate itself. These tables are made without the game kernel
(``mcbat.core.swing``), the batch kernels, the study machinery or
``mcbat.stats.measurements.synthesize``: the true inputs of every row are drawn here
from the distributions of ``tests/stats/data/game_fit_independent.toml`` (written out in
``DISTRIBUTIONS``), the kinematics from the pitch and the swing to the bat frame and
back are written out here in numpy from the equations of ``mcbat/core/swing/README.md``
and ``docs/batting.md`` (``bat_frame_case``, ``batted_ball``), every impact is
solved by the scipy reference solver
``mcbat.testing.cabo2012_reference.reference_impact``, and the measurement errors are
added here.

The case is kept simple enough to write out: a right-handed batter (a left-handed one is
supported, as the mirror image in ``x``), a cylindrical bat with the R161's mass, inertias,
length and centre of mass and its barrel radius at the sweet spot (``BODIES``, numbers
written out), the speed form of ``e*`` without a location table, and contacts on the barrel.
Another bat can be passed in as data (``bat_bodies``: its mass properties and its
surface at a contact); the tests pass the R161 preset's mass properties and profile, to
exercise a tapered surface. This module imports nothing of mcbat but the reference solver
(the import contract of ``pyproject.toml`` holds it to that).

The table has the columns a game fit reads (``mcbat/stats/columns.py``): the measured
inputs ``pitch_speed``, ``bat_speed`` (mph), ``attack_angle`` (deg), ``undercut`` (m) and,
if asked for, ``from_barrel_end`` (m), each with an ``_err`` column when it has an error;
the observables ``launch_speed`` (mph), ``launch_angle``, ``spray_angle`` (deg) and
``spin_rate`` (rpm), each with its ``_err``. Errors are one per column, as a tracking
system states them: 1 % of the table's mean launch speed, 1 deg, and 10 % of the mean spin
rate with a floor of 50 rpm.
"""

import math

import numpy as np
import pandas as pd
from scipy import stats

from mcbat.core.units import M_PER_FT, M_PER_IN, M_S_PER_MPH, RAD_S_PER_RPM
from mcbat.testing.cabo2012_reference import reference_impact

__all__ = ["BODIES", "DISTRIBUTIONS", "INPUT_NAMES", "MEASURED", "OBSERVABLES", "RESTITUTION",
           "bat_bodies", "bat_frame_case", "batted_ball", "draw_inputs", "game_table",
           "mirrored", "reference_solver", "solve_row"]

MPH = M_S_PER_MPH
"""m/s per mph."""
RPM = RAD_S_PER_RPM
"""rad/s per rpm."""
INCH = M_PER_IN
"""m per inch."""
DEG = math.pi / 180.0
"""rad per degree."""

SWEET_SPOT = 6.0 * INCH
"""Statcast's sweet spot, 6 in from the barrel end, where ``bat_speed`` is measured (m)."""

BODIES = {
    # The baseball: 0.145 kg, radius 0.036 m, I = 0.4 m R^2 (a uniform sphere's factor).
    "ball_mass": 0.145, "ball_radius": 0.036, "ball_inertia_factor": 0.4,
    # A cylinder with the R161 wood bat's mass properties (uniform wood on the profile of
    # Nathan, Am. J. Phys. 68, 979 (2000), rounded): 0.865 kg, I_t 0.0468 kg m^2 about the
    # CM, I_3 3.16e-4 kg m^2, 0.84 m long, CM 0.2816 m from the barrel end; radius 0.0313 m,
    # the R161's barrel radius 6 in from its end.
    "bat_mass": 0.865, "bat_transverse_inertia": 0.0468, "bat_axial_inertia": 3.16e-4,
    "bat_length": 0.84, "bat_cm_from_barrel_end": 0.2816, "bat_radius": 0.0313,
    # The swing's pivot, 6 in from the knob (the bat-performance standards' pivot).
    "pivot": 6.0 * INCH,
}
"""The bodies and the pivot of the independent game (kg, m, kg m^2)."""

RESTITUTION = {"e_slope": 0.00165, "e_speed_ref": 85.0 * M_PER_FT}
"""The speed form of ``e*``: ``e* = clip(e - e_slope (|v_n| - e_speed_ref), 0, 1)`` with
``e_slope`` per m/s and ``e_speed_ref`` in m/s (85 ft/s), no location factor: the game
preset's slope and reference speed; ``e`` (the value at the reference speed) and ``e_x``
are the truth of a table."""

DISTRIBUTIONS = {
    # name: ("truncnormal", mean, std, low, high) or ("uniform", low, high) or
    # ("fixed", value); SI units (m/s, rad, rad/s, m). The same as the study file
    # tests/stats/data/game_fit_independent.toml (tests/testing/test_game_tables.py checks).
    "pitch_speed": ("truncnormal", 86.0 * MPH, 2.7 * MPH, 78.0 * MPH, 94.0 * MPH),
    "vertical_approach_angle": ("truncnormal", -4.9 * DEG, 1.1 * DEG, -8.0 * DEG, -2.0 * DEG),
    "horizontal_approach_angle": ("truncnormal", 1.3 * DEG, 1.2 * DEG, -3.0 * DEG, 5.0 * DEG),
    "spin_rate": ("truncnormal", 2300.0 * RPM, 100.0 * RPM, 1900.0 * RPM, 2700.0 * RPM),
    "spin_axis": ("truncnormal", 210.0 * DEG, 10.0 * DEG, 170.0 * DEG, 250.0 * DEG),
    "spin_efficiency": ("fixed", 0.9),
    "gyro_sign": ("fixed", 1.0),
    "bat_speed": ("truncnormal", 71.5 * MPH, 4.0 * MPH, 60.0 * MPH, 82.0 * MPH),
    "attack_angle": ("truncnormal", 10.0 * DEG, 5.0 * DEG, -10.0 * DEG, 30.0 * DEG),
    "attack_direction": ("truncnormal", 0.0, 8.0 * DEG, -30.0 * DEG, 30.0 * DEG),
    "vertical_bat_angle": ("truncnormal", -30.0 * DEG, 6.0 * DEG, -50.0 * DEG, -10.0 * DEG),
    "from_barrel_end": ("truncnormal", 6.0 * INCH, 2.0 * INCH, 2.0 * INCH, 12.0 * INCH),
    "undercut": ("uniform", -1.5 * INCH, 1.5 * INCH),
    "mu": ("truncnormal", 0.5, 0.05, 0.3, 0.7),
}
"""The distributions of every row's true inputs (SI)."""
INPUT_NAMES = tuple(DISTRIBUTIONS)
"""The inputs of a row, in the order they are drawn."""

MEASURED = {
    # table column: (input, factor from SI to the table's unit)
    "pitch_speed": ("pitch_speed", 1.0 / MPH),
    "bat_speed": ("bat_speed", 1.0 / MPH),
    "attack_angle": ("attack_angle", 1.0 / DEG),
    "undercut": ("undercut", 1.0),
    "from_barrel_end": ("from_barrel_end", 1.0),
}
"""The measured inputs a table can carry, and their units (mph, deg, m)."""
OBSERVABLES = ("launch_speed", "launch_angle", "spray_angle", "spin_rate")
"""The observables of a table (mph, deg, deg, rpm)."""


def _unit(v):
    return v / np.linalg.norm(v)


def draw_inputs(rows, rng):
    """The true inputs of ``rows`` rows (SI), drawn from ``DISTRIBUTIONS`` in the
    order of ``INPUT_NAMES`` (inverse CDFs of ``rng.uniform``).

    Returns
    -------
    dict of str to ndarray, (rows,)
    """
    out = {}
    for name in INPUT_NAMES:
        kind, *args = DISTRIBUTIONS[name]
        if kind == "fixed":
            out[name] = np.full(rows, float(args[0]))
            continue
        u = rng.uniform(size=rows)
        if kind == "uniform":
            low, high = args
            out[name] = low + (high - low) * u
        else:
            mean, std, low, high = args
            out[name] = stats.truncnorm.ppf(u, (low - mean) / std, (high - mean) / std,
                                            loc=mean, scale=std)
    return out


def bat_bodies(bat):
    """The bodies and the bat's surface of ``bat``: ``"cylinder"`` gives ``BODIES``
    and the cylinder's ``(radius, 0)``; a dict gives its own numbers (the keys of
    ``BODIES``) and its ``"surface"``, a callable ``surface(from_barrel_end)`` -> the
    bat's radius (m) and profile slope ``dr/dz`` at a contact that far from the barrel end
    (m). The caller builds such a dict from whatever data it trusts (the tests, from the
    R161 preset's mass properties and profile)."""
    if isinstance(bat, str) and bat == "cylinder":
        return dict(BODIES), lambda _: (BODIES["bat_radius"], 0.0)
    if not isinstance(bat, dict) or "surface" not in bat:
        raise ValueError(f"bat must be 'cylinder' or a dict of bodies with a 'surface', "
                         f"got {bat!r}")
    bodies = {name: float(bat[name]) for name in BODIES}
    return bodies, bat["surface"]


def bat_frame_case(row, bodies, surface, e, handedness=1.0):
    """One row's impact in the bat frame, from the equations of the swing README.

    Parameters
    ----------
    row : dict of str to float
        The row's inputs (SI, ``INPUT_NAMES``).
    bodies : dict
        ``BODIES`` or a bat's numbers of the same names.
    surface : callable
        ``surface(from_barrel_end)`` -> the bat's radius (m) and profile slope ``dr/dz``
        at the contact.
    e : float
        ``e*`` at the reference speed (``RESTITUTION``).
    handedness : float
        +1 a right-handed batter, -1 a left-handed one (the swing mirrored in ``x``).

    Returns
    -------
    dict
        ``basis`` (3 x 3, rows ``i, j, k``: the bat frame's axes in the field frame),
        ``axial`` (m from the bat CM), ``angle`` (rad), ``radius`` (m), ``slope``,
        ``impact_parameter`` (m), ``ball_v``, ``ball_w``, ``bat_v``, ``bat_w`` (bat frame,
        m/s and rad/s), ``approach`` (the contact points' relative velocity along the bat's
        outward normal, m/s, < 0 approaching), ``normal_speed`` (its magnitude) and
        ``e_star``; in the field frame
        ``pitch_v``, ``pitch_w``, ``bat_v_field``, ``bat_w_field``, ``axis_point_v``
        (the velocity of the bat axis's point at the contact).
    """
    # The pitch: d = (cos V sin H, -cos V cos H, sin V); the clock face seen from behind
    # the plate e1 = unit(z x d), e2 = d x e1; Magnus direction m = sin(theta) e1 -
    # cos(theta) e2; spin = eps w0 (d x m) + g w0 sqrt(1 - eps^2) d.
    up_z = np.array([0.0, 0.0, 1.0])
    vert, horiz = row["vertical_approach_angle"], row["horizontal_approach_angle"]
    d = np.array([math.cos(vert) * math.sin(horiz), -math.cos(vert) * math.cos(horiz),
                  math.sin(vert)])
    e1 = _unit(np.cross(up_z, d))
    e2 = np.cross(d, e1)
    theta = row["spin_axis"]
    magnus = math.sin(theta) * e1 - math.cos(theta) * e2
    w0, eps = row["spin_rate"], row["spin_efficiency"]
    pitch_v = row["pitch_speed"] * d
    pitch_w = (eps * w0 * np.cross(d, magnus)
               + row["gyro_sign"] * w0 * math.sqrt(1.0 - eps * eps) * d)

    # The swing: the sweet spot moves along u = (cos a sin p, cos a cos p, sin a); the axis
    # n = A P + B Q + sin(b) z with P = (cos p, -sin p, 0), Q = (sin p, cos p, 0),
    # B = -sin(b) tan(a), A = +sqrt(cos^2 b - B^2); a left-handed batter mirrors both in x.
    a, p, b = row["attack_angle"], row["attack_direction"], row["vertical_bat_angle"]
    u = np.array([math.cos(a) * math.sin(p), math.cos(a) * math.cos(p), math.sin(a)])
    big_b = -math.sin(b) * math.tan(a)
    big_a = math.sqrt(math.cos(b) ** 2 - big_b ** 2)
    n = (big_a * np.array([math.cos(p), -math.sin(p), 0.0])
         + big_b * np.array([math.sin(p), math.cos(p), 0.0]) + math.sin(b) * up_z)
    mirror = np.array([handedness, 1.0, 1.0])
    u, n = u * mirror, n * mirror
    # A rotation about the pivot (p_k from the knob): the sweet spot, L = length - 6 in -
    # p_k from the pivot, moves at v_s u, so Omega = (v_s / L) n x u, and a point of the
    # axis s from the knob moves at v_s (s - p_k) / L u.
    length, pivot = bodies["bat_length"], bodies["pivot"]
    lever = length - SWEET_SPOT - pivot
    v_s = row["bat_speed"]
    omega = v_s / lever * np.cross(n, u)
    cm_from_knob = length - bodies["bat_cm_from_barrel_end"]
    bat_v = v_s * (cm_from_knob - pivot) / lever * u
    contact_from_knob = length - row["from_barrel_end"]
    axis_point_v = v_s * (contact_from_knob - pivot) / lever * u

    # The bat frame: k = n; i = -unit(w_perp), w = the ball's velocity relative to the axis
    # point at the contact, w_perp its part across the axis; j = k x i.
    w = pitch_v - axis_point_v
    w_perp = w - (w @ n) * n
    i = -_unit(w_perp)
    j = np.cross(n, i)
    basis = np.array([i, j, n])
    # The contact: b = sign(j . z) D; its azimuth asin(b / (r + R / sqrt(1 + r'^2))).
    radius, slope = surface(row["from_barrel_end"])
    reach = radius + bodies["ball_radius"] / math.sqrt(1.0 + slope * slope)
    impact_parameter = math.copysign(1.0, j @ up_z) * row["undercut"]
    angle = math.asin(impact_parameter / reach)
    axial = bodies["bat_cm_from_barrel_end"] - row["from_barrel_end"]
    ball_v, ball_w = basis @ pitch_v, basis @ pitch_w
    bat_v_frame, bat_w_frame = basis @ bat_v, basis @ omega

    # e* from the normal approach speed of the contact points: the bat's outward normal
    # there is (cos t, sin t, -r') / sqrt(1 + r'^2) in the bat frame; the ball's spin moves
    # its contact point only across that normal.
    normal = np.array([math.cos(angle), math.sin(angle), -slope]) / math.sqrt(1 + slope ** 2)
    point = np.array([radius * math.cos(angle), radius * math.sin(angle), axial])
    approach = (ball_v - bat_v_frame - np.cross(bat_w_frame, point)) @ normal
    normal_speed = abs(approach)
    e_star = min(max(e - RESTITUTION["e_slope"] * (normal_speed - RESTITUTION["e_speed_ref"]),
                     0.0), 1.0)
    return {"basis": basis, "axial": axial, "angle": angle, "radius": radius, "slope": slope,
            "impact_parameter": impact_parameter, "ball_v": ball_v, "ball_w": ball_w,
            "bat_v": bat_v_frame, "bat_w": bat_w_frame, "normal_speed": normal_speed,
            "approach": approach, "e_star": e_star, "pitch_v": pitch_v, "pitch_w": pitch_w,
            "bat_v_field": bat_v, "bat_w_field": omega, "axis_point_v": axis_point_v}


def batted_ball(velocity, spin):
    """Statcast's batted-ball numbers of a field-frame velocity (m/s) and spin (rad/s):
    ``launch_speed`` (mph), ``launch_angle`` (deg, elevation), ``spray_angle`` (deg,
    ``atan2(v_x, v_y)``, positive towards right field), ``spin_rate`` (rpm)."""
    vx, vy, vz = velocity
    return {"launch_speed": math.sqrt(vx * vx + vy * vy + vz * vz) / MPH,
            "launch_angle": math.degrees(math.atan2(vz, math.hypot(vx, vy))),
            "spray_angle": math.degrees(math.atan2(vx, vy)),
            "spin_rate": float(np.linalg.norm(spin)) / RPM}


def solve_row(row, e, e_x, bat="cylinder", handedness=1.0, rtol=1e-8):
    """One row solved by the reference solver: the bat-frame case of
    ``bat_frame_case`` with ``"ball_velocity"``, ``"ball_spin"`` (field frame, m/s,
    rad/s) and the observables of ``batted_ball`` added."""
    bodies, surface = bat_bodies(bat)
    case = bat_frame_case(row, bodies, surface, e, handedness)
    r = reference_impact(
        bodies["ball_mass"], bodies["ball_radius"], bodies["ball_inertia_factor"],
        bodies["bat_mass"], bodies["bat_transverse_inertia"], bodies["bat_axial_inertia"],
        case["axial"], case["angle"], case["radius"], case["slope"], case["ball_v"],
        case["ball_w"], case["bat_v"], case["bat_w"], row["mu"], case["e_star"], e_x,
        rtol=rtol, atol=1e-12 * rtol)
    if r["status"] != "ok":
        raise RuntimeError(f"the reference solver returned {r['status']!r}")
    basis = case["basis"]  # bat frame -> field frame: v_field = basis.T @ v_bat
    case["ball_velocity"] = basis.T @ r["ball_v"]
    case["ball_spin"] = basis.T @ r["ball_w"]
    case.update(batted_ball(case["ball_velocity"], case["ball_spin"]))
    return case


def _row(inputs, k):
    return {name: float(values[k]) for name, values in inputs.items()}


def reference_solver(inputs, e, e_x, bat="cylinder", handedness=1.0, rtol=1e-8):
    """The observables of every row (``OBSERVABLES``, table units), each impact solved
    by ``mcbat.testing.cabo2012_reference.reference_impact``.

    Parameters
    ----------
    inputs : dict of str to ndarray
        The rows' true inputs (SI, ``INPUT_NAMES``).
    e, e_x : float
        ``e*`` at the reference speed and the tangential restitution.
    bat : str or dict
        ``"cylinder"`` (``BODIES``) or a bat of ``bat_bodies``.
    handedness : float
        +1 right-handed, -1 left-handed.
    rtol : float
        The reference solver's relative tolerance (1e-8: far below any measurement error).

    Returns
    -------
    ndarray, (rows, 4)
    """
    rows = len(inputs["pitch_speed"])
    out = np.empty((rows, len(OBSERVABLES)))
    for k in range(rows):
        r = solve_row(_row(inputs, k), e, e_x, bat, handedness, rtol)
        out[k] = [r[name] for name in OBSERVABLES]
    return out


def mirrored(inputs):
    """The inputs of the mirror image in ``x`` of a game (with the other handedness): the
    pitch's horizontal approach angle and spin axis negated (``2 pi - theta``), its gyro
    sense reversed; the swing's angles are measured from the batter's side and stay."""
    out = dict(inputs)
    out["horizontal_approach_angle"] = -np.asarray(inputs["horizontal_approach_angle"])
    out["spin_axis"] = 2.0 * math.pi - np.asarray(inputs["spin_axis"])
    out["gyro_sign"] = -np.asarray(inputs["gyro_sign"])
    return out


def game_table(rows, seed, *, e=0.5, e_x=0.3, input_errors=None,
               measured=("pitch_speed", "bat_speed", "attack_angle", "undercut"),
               speed_err=0.01, angle_err=1.0, spin_err=(0.10, 50.0), bat="cylinder",
               handedness=1.0, solver=reference_solver):
    """A game table of ``rows`` batted balls.

    Parameters
    ----------
    rows, seed : int
        Number of rows and the seed of every random number.
    e, e_x : float
        The truth: ``e*`` at the reference speed of ``RESTITUTION`` (the fit's ``e``)
        and the tangential restitution.
    input_errors : dict, optional
        1-sigma error of a measured input, in the table's unit (``{"undercut": 0.002}``,
        m, the default): the impact is solved at the true value, the table gets the true
        value plus noise and an ``_err`` column. Measured inputs without one are exact.
    measured : sequence of str
        The measured inputs the table carries (``MEASURED``); the rest are the fit's
        nuisance, drawn from the study.
    speed_err : float
        Error of the launch speed, relative to the table's mean launch speed.
    angle_err : float
        Error of the launch and spray angles (deg).
    spin_err : (float, float)
        Error of the spin rate relative to the table's mean spin rate, and its floor (rpm).
    bat : str or dict
        ``"cylinder"`` (``BODIES``, the study's bat) or a bat of ``bat_bodies``.
    handedness : float
        +1 a right-handed batter (the study's), -1 a left-handed one.
    solver : callable
        ``solver(inputs, e, e_x, bat, handedness)`` -> observables, (rows, 4):
        ``reference_solver`` by default (a solver by mcbat's own game kernel, for
        comparison and for fast validation runs, is
        ``validation.game_fit_validation.kernel_solver``). The random numbers do not depend
        on it, so two solvers give the same table up to their difference.

    Returns
    -------
    pandas.DataFrame
        The table; ``attrs["truth"]`` holds ``e``, ``e_x``, ``handedness``, the bodies,
        the true inputs (SI) and the true observables (table units, rows x 4).
    """
    errors = {"undercut": 0.002} if input_errors is None else dict(input_errors)
    unknown = [name for name in list(measured) + list(errors) if name not in MEASURED]
    if unknown:
        raise ValueError(f"{unknown[0]!r} is not a measured input (choose from "
                         f"{', '.join(MEASURED)})")
    rng = np.random.default_rng(seed)
    inputs = draw_inputs(rows, rng)
    noise = rng.standard_normal((len(OBSERVABLES) + len(MEASURED), rows))
    out = solver(inputs, e, e_x, bat, handedness)
    table = pd.DataFrame(index=range(rows))
    for n, (column, (name, factor)) in enumerate(MEASURED.items()):
        if column not in measured:
            continue
        true = inputs[name] * factor
        sigma = errors.get(column, 0.0)
        table[column] = true + sigma * noise[len(OBSERVABLES) + n]
        if sigma > 0:
            table[f"{column}_err"] = sigma
    sigmas = {"launch_speed": speed_err * float(np.mean(np.abs(out[:, 0]))),
              "launch_angle": angle_err, "spray_angle": angle_err,
              "spin_rate": max(spin_err[0] * float(np.mean(np.abs(out[:, 3]))), spin_err[1])}
    for n, column in enumerate(OBSERVABLES):
        table[column] = out[:, n] + sigmas[column] * noise[n]
        table[f"{column}_err"] = sigmas[column]
    table.attrs["truth"] = {"e": e, "e_x": e_x, "handedness": handedness,
                            "bodies": bat_bodies(bat)[0], "inputs": inputs,
                            "observables": out}
    return table
