"""A hard random mix of impacts, drawn deterministically from a seed: the cases the
kernel's accuracy is stated on (``harness.accuracy_mix`` measures the kernel on
them against the reference).

The mix includes bats from 5 g to 5000 kg, spins up to 3000 rad/s, ``mu`` from 0 to 1,
creeping slip and re-slip (``MODES``). Like ``harness.accuracy_mix``, this
module imports the kernel's geometry: a case's contact frame and Delassus matrix are the
kernel's own formulas, checked in the tests against numpy's.
"""

import math

import numpy as np

from mcbat.core.batch import INPUT_FIELDS
from mcbat.core.geometry import contact_frame
from mcbat.core.rigid_bodies import delassus_matrix

__all__ = ["BASEBALL_BODIES", "BASEBALL_MODES", "CREEP_RATIO_OFFSET", "DEFAULT_SEED",
           "MAX_SPIN", "MODES", "SLIP_STYLES", "case_vector", "contact_problem", "draw_mix",
           "stick_rate"]

DEFAULT_SEED = 20130013
"""Seed of the mix that ``validation/kernel_accuracy.py`` measures by default."""

MODES = ("free", "small", "zero", "reslip", "light_bat", "heavy_bat", "high_spin", "creep")
"""Sampling modes, cycled over the cases (case ``i`` has mode ``MODES[i % len(MODES)]``).

``free``
    Sec. V bodies, random slip (slides through, or stops and sticks).
``small``
    Sec. V bodies, incoming slip 1e-3..0.3 of ``|v_n|``: mostly sticks.
``zero``
    Sec. V bodies, no incoming slip (a third re-slips straight from incidence).
``reslip``
    Sec. V bodies, ``mu`` below the stick rate ``|f|`` and a small slip against the drive
    ``K_tn``: slip stops, then re-slips.
``light_bat``, ``heavy_bat``
    Bats of 5-300 g and 5-5000 kg with the inertias of a rod (``I_t = m L^2/12``,
    ``L`` 0.3-0.9 m; ``I_3 = m r^2/2``, ``r`` 25-35 mm), any slip style.
``high_spin``
    Sec. V bodies, ball and/or bat spinning at 500-3000 rad/s.
``creep``
    Sec. V bodies, ``|f| / mu`` within ``CREEP_RATIO_OFFSET`` of 1 on either side and a
    small slip: the slip creeps to a stop (or, above 1, stops and creeps away in re-slip).
"""

BASEBALL_MODES = ("free", "small", "zero", "reslip", "high_spin", "creep")
"""The modes with the Sec. V ball and bat (``BASEBALL_BODIES``)."""

SLIP_STYLES = ("free", "small", "zero", "reslip", "creep")
"""How the incoming slip and ``mu`` are chosen; stored in each case as ``slip``."""

BASEBALL_BODIES = dict(
    ball_mass=0.145, ball_radius=0.036, ball_inertia_factor=0.4,
    bat_mass=0.989, bat_transverse_inertia=0.0460, bat_axial_inertia=4.39e-4,
)
"""The Sec. V ball and bat of ``docs/physics.md`` (kg, m, kg m^2)."""

BARREL_RADIUS = 0.03335  # m, the Sec. V barrel
LIGHT_BAT_MASS = (0.005, 0.3)  # kg, log-uniform
HEAVY_BAT_MASS = (5.0, 5000.0)  # kg, log-uniform
BAT_LENGTH = (0.3, 0.9)  # m, of the rod that gives a light or heavy bat its inertia
APPROACH_SPEED = (2.0, 40.0)  # m/s, -v_n at the contact
HIGH_SPIN = (500.0, 3000.0)  # rad/s, magnitude of a high spin
MAX_SPIN = 3000.0
"""Largest spin magnitude (rad/s) of the ``high_spin`` mode; adjusted spins above it are
resampled."""
CREEP_RATIO_OFFSET = (0.003, 0.03)
"""``| |f|/mu - 1 |`` of the ``creep`` style: within a few % of the stick/slide boundary."""
FRICTIONLESS_FRACTION = 0.05  # share of exact mu = 0 where mu is drawn from [0, 1]
TAPERED_FRACTION = 0.3  # share of contacts on the tapered part of the profile


def contact_problem(case):
    """The contact frame, Delassus matrix and incoming relative velocity of one case.

    Parameters
    ----------
    case : dict
        A case of ``draw_mix`` (the fields of ``INPUT_FIELDS``, SI units).

    Returns
    -------
    basis : numpy.ndarray
        (3, 3): rows ``t1, t2, t3`` (azimuthal and meridional tangents, outward normal).
    r_c : numpy.ndarray
        Contact point from the bat CM (m).
    k : numpy.ndarray
        (3, 3) Delassus matrix in the contact basis (1/kg).
    v0 : numpy.ndarray
        Relative contact velocity at incidence in the contact basis (m/s).
    """
    t1, t2, t3, r_c = (np.array(x) for x in contact_frame(
        case["axial"], case["angle"], case["bat_radius"], case["bat_slope"]))
    return (np.array([t1, t2, t3]), r_c, _delassus(case, t1, t2, t3, r_c),
            np.array([t1, t2, t3]) @ _relative_velocity(case, t3, r_c))


def stick_rate(k):
    """Stick rate ``f = -K_tt^-1 K_tn`` (2,), dimensionless: stick holds iff ``|f| <= mu``."""
    return -np.linalg.solve(k[:2, :2], k[:2, 2])


def _delassus(bodies, t1, t2, t3, r_c):
    k11, k12, k13, k22, k23, k33 = delassus_matrix(
        bodies["ball_mass"], bodies["ball_radius"], bodies["ball_inertia_factor"],
        bodies["bat_mass"], bodies["bat_transverse_inertia"], bodies["bat_axial_inertia"],
        tuple(t1), tuple(t2), tuple(t3), tuple(r_c))
    return np.array([[k11, k12, k13], [k12, k22, k23], [k13, k23, k33]])


def case_vector(case, prefix):
    """The case's vector ``prefix`` (``"ball_v"``, ...) at incidence, from its ``x, y, z``
    fields."""
    return np.array([case[prefix + "x_in"], case[prefix + "y_in"], case[prefix + "z_in"]])


def _relative_velocity(case, t3, r_c):
    """Velocity (m/s, lab) of the ball's contact point relative to the bat's."""
    rho = -case["ball_radius"] * t3
    return (case_vector(case, "ball_v") + np.cross(case_vector(case, "ball_w"), rho)
            - case_vector(case, "bat_v") - np.cross(case_vector(case, "bat_w"), r_c))


def _log_uniform(rng, low, high):
    return math.exp(rng.uniform(math.log(low), math.log(high)))


def _random_direction(rng):
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def _draw_bat(rng, mass_range):
    """A light or heavy bat: a rod of length ``L`` and radius ``r`` about its CM.

    ``I_t = m L^2 / 12`` and ``I_3 = m r^2 / 2`` (the Sec. V bat is close to such a rod:
    ``L`` = 0.75 m, ``r`` = 0.030 m). Returns the body fields and the rod length (m).
    """
    mass = _log_uniform(rng, *mass_range)
    length = rng.uniform(*BAT_LENGTH)
    rod_radius = rng.uniform(0.025, 0.035)
    bodies = dict(BASEBALL_BODIES, bat_mass=mass,
                  bat_transverse_inertia=mass * length ** 2 / 12.0,
                  bat_axial_inertia=0.5 * mass * rod_radius ** 2)
    return bodies, length


def _draw_contact(rng, slip, length):
    """Axial position, azimuth, radius and slope of the contact (m, rad, m, -).

    Re-slip and creep need a stick rate ``|f|`` clearly above 0, which grows with the
    distance from the bat CM: those styles stay away from it.
    """
    if slip in ("reslip", "creep"):
        axial = rng.uniform(0.2, 0.33) * length * rng.choice([-1.0, 1.0])
    else:
        axial = rng.uniform(-0.13, 0.33) * length
    if rng.random() < TAPERED_FRACTION:
        radius, slope = rng.uniform(0.025, 0.035), rng.uniform(-0.1, 0.1)
    else:
        radius, slope = BARREL_RADIUS, 0.0
    return axial, rng.uniform(-1.2, 1.2), radius, slope


def _slip_target(rng, slip, k, f, mu, speed):
    """Incoming tangential slip ``(v_1, v_2)`` (m/s, contact basis) for a slip style, or None
    to keep the drawn one.

    The stopping lengths use the impulse to the end of compression, ``~ |v_n| / K_33``.
    """
    i_c = speed / k[2, 2]
    k_tn = k[:2, 2]
    if slip == "small":
        phi = rng.uniform(0.0, 2.0 * math.pi)
        return speed * 10.0 ** rng.uniform(-3.0, -0.5) * np.array([math.cos(phi),
                                                                    math.sin(phi)])
    if slip == "zero":
        return np.zeros(2)
    if slip == "reslip":
        # Against the drive K_tn, which (with friction) brings it to 0 within |v_t| / |K_tn|:
        # a fraction of the impulse to the end of compression.
        return -rng.uniform(0.05, 0.5) * i_c * k_tn
    if slip == "creep":
        f_size = np.linalg.norm(f)
        f_unit = f / f_size
        # A slip across f makes the slip direction turn on its way to 0.
        across_fraction = rng.uniform(-0.3, 0.3)
        if f_size < mu:
            # Slip along -f falls at |K_tt f| (mu/|f| - 1), a few % of the usual rate.
            along, rate = -f_unit, np.linalg.norm(k[:2, :2] @ f) * (mu / f_size - 1.0)
        else:
            # Along -f it would grow; along +f it stops (fast), then creeps away in re-slip.
            # With a slip across f as well, |v_t| only nearly vanishes before it turns
            # into the re-slip direction (the reference's "near miss"): half of each.
            along, rate = f_unit, np.linalg.norm(k[:2, :2] @ f) * (1.0 + mu / f_size)
            if rng.random() < 0.5:
                across_fraction = 0.0
        size = rng.uniform(0.05, 0.5) * rate * i_c
        return size * (along + across_fraction * np.array([-along[1], along[0]]))
    return None


def _draw_mu(rng, slip, f_size):
    """Friction coefficient for a slip style, given the stick rate ``|f|``."""
    if slip == "reslip":
        return f_size * rng.uniform(0.3, 0.9)
    if slip == "creep":
        offset = rng.uniform(*CREEP_RATIO_OFFSET) * rng.choice([-1.0, 1.0])
        return f_size / (1.0 + offset)  # |f| / mu = 1 + offset
    if rng.random() < FRICTIONLESS_FRACTION:
        return 0.0
    return rng.uniform(0.0, 1.0)


def _draw_case(rng, mode):
    """One random approaching impact of the given mode (resampled until valid)."""
    while True:
        if mode == "light_bat":
            bodies, length = _draw_bat(rng, LIGHT_BAT_MASS)
        elif mode == "heavy_bat":
            bodies, length = _draw_bat(rng, HEAVY_BAT_MASS)
        else:
            bodies, length = dict(BASEBALL_BODIES), 0.75
        if mode in ("light_bat", "heavy_bat"):
            slip = SLIP_STYLES[rng.integers(len(SLIP_STYLES))]
        elif mode == "high_spin":
            slip = "small" if rng.random() < 0.3 else "free"
        elif mode == "zero":
            slip = "zero"
        else:
            slip = mode
        axial, angle, radius, slope = _draw_contact(rng, slip, length)
        t1, t2, t3, r_c = (np.array(x) for x in contact_frame(axial, angle, radius, slope))
        k = _delassus(bodies, t1, t2, t3, r_c)
        f = stick_rate(k)
        # A third of the slip-free incidences re-slip from incidence (mu below |f|).
        mu_style = "reslip" if (slip == "zero" and rng.random() < 0.3) else slip
        mu = min(_draw_mu(rng, mu_style, np.linalg.norm(f)), 1.0)
        e = rng.uniform(0.0, 1.0)
        speed = rng.uniform(*APPROACH_SPEED)

        # A bat's motion sets E_in, the scale of the work errors: a heavy bat keeps the
        # kinetic energy of the Sec. V bat's motion rather than burying the contact in it.
        bat_scale = min(1.0, math.sqrt(BASEBALL_BODIES["bat_mass"] / bodies["bat_mass"]))
        ball_v = -speed * t3 + rng.normal(0.0, 0.3 * speed, 3)
        ball_w = rng.normal(0.0, 150.0, 3)
        bat_v = rng.normal(0.0, 3.0 * bat_scale, 3)
        bat_w = rng.normal(0.0, 20.0 * bat_scale, 3)
        if mode == "high_spin":
            spinning = rng.choice(["ball", "bat", "both"])
            if spinning in ("ball", "both"):
                ball_w = rng.uniform(*HIGH_SPIN) * _random_direction(rng)
            if spinning in ("bat", "both"):
                bat_w = rng.uniform(*HIGH_SPIN) * _random_direction(rng)

        case = dict(bodies, axial=axial, angle=angle, bat_radius=radius, bat_slope=slope,
                    mu=mu, e=e, e_x=0.0)
        _set_motion(case, ball_v, ball_w, bat_v, bat_w)
        # Approach at exactly `speed`: move the ball along the normal (spins, however
        # large, then never decide whether there is an impact).
        v = _relative_velocity(case, t3, r_c)
        ball_v = ball_v - (v @ t3 + speed) * t3
        target = _slip_target(rng, slip, k, f, mu, speed)
        if target is not None:
            # The ball spin's tangential part sets v_t without touching v_n:
            # w x rho = R t3 x w, and R t3 x (a t1 + b t2) = R (a t2 - b t1).
            d = target[0] * t1 + target[1] * t2 - (v - (v @ t3) * t3)
            ball_w = ball_w + ((d @ t2) * t1 - (d @ t1) * t2) / bodies["ball_radius"]
        _set_motion(case, ball_v, ball_w, bat_v, bat_w)
        v = _relative_velocity(case, t3, r_c)
        if not v @ t3 < -0.5:
            continue  # not (clearly) approaching: resample
        if mode == "high_spin" and np.linalg.norm(ball_w) > MAX_SPIN:
            continue  # the slip adjustment spun the ball beyond the mode's range
        case = {name: float(case[name]) for name in INPUT_FIELDS}
        case.update(mode=mode, slip=slip)
        return case


def _set_motion(case, ball_v, ball_w, bat_v, bat_w):
    for prefix, vec in (("ball_v", ball_v), ("ball_w", ball_w), ("bat_v", bat_v),
                        ("bat_w", bat_w)):
        for axis, x in zip("xyz", vec):
            case[f"{prefix}{axis}_in"] = float(x)


def draw_mix(n=520, seed=DEFAULT_SEED):
    """Draw the random mix of approaching impacts.

    Parameters
    ----------
    n : int
        Number of cases; the modes of ``MODES`` are cycled.
    seed : int
        Seed of ``numpy.random.default_rng``: the same seed gives the same mix.

    Returns
    -------
    list of dict
        One dict per case with every field of ``mcbat.core.batch.INPUT_FIELDS`` (floats,
        SI units: kg, m, kg m^2, rad, m/s, rad/s; ``e_x`` = 0), plus ``mode`` (one of
        ``MODES``) and ``slip`` (one of ``SLIP_STYLES``). Each case approaches at
        2-40 m/s at the contact.
    """
    rng = np.random.default_rng(seed)
    return [_draw_case(rng, MODES[i % len(MODES)]) for i in range(n)]
