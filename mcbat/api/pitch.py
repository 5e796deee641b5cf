"""A pitch's speed at the plate from its release speed: the pitch flown from the release
point to the front of home plate with Nathan's drag (the flight kernel of
``mcbat.core.flight``, the one batted balls fly with).

An analyst's "94 mph fastball" is a release speed: Statcast's ``release_speed``, measured
where the ball leaves the hand, ``extension`` ft in front of the rubber (``60.5 -
extension`` ft from the back tip of the plate). A game case's ``pitch.speed`` is the speed
at the front of the plate (17/12 ft from the back tip), where the bat meets the ball; the
air takes about 8 % of it away on the way. ``plate_speed`` converts one to the other;
a game case's ``pitch.release_speed`` (``docs/batting.md``) uses it.

The flight: from the release point, ``release_height`` above the ground, straight towards
the plate (the sideways part of the path, a few inches over 55 ft, is left out), aimed so
that it crosses the front of the plate at ``plate_height``; the pitch's spin (rate, axis,
efficiency) enters the drag as in Nathan's model, ``C_D = 0.3008 + 0.0292 (spin / 1000
rpm)``, and the lift bends the path (which the aim takes back). Air: the calculator's
standard conditions unless ``settings`` says otherwise.

Example
-------
>>> from mcbat.api.pitch import plate_speed
>>> from mcbat.core.units import M_S_PER_MPH as mph
>>> 85.0 < plate_speed(94 * mph, spin_rate=2300 * 0.10471975511965977) / mph < 88.0
True
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from mcbat.bodies import BALL_PRESETS, DEFAULT_BALL, Ball
from mcbat.checks import check_real as _real
from mcbat.core.units import M_PER_FT, M_S_PER_MPH
from mcbat.errors import InputError
from mcbat.solving import FlightParams, fly_sampled
from mcbat.solving.derived import launch_vectors
from mcbat.study.flight import FlightSettings

__all__ = ["DEFAULT_EXTENSION", "DEFAULT_PLATE_HEIGHT", "DEFAULT_RELEASE_HEIGHT",
           "MAX_RELEASE_SPEED", "PLATE_FRONT", "RUBBER", "plate_speed"]

#: The front of the pitching rubber from the back tip of home plate: 60 ft 6 in (m).
RUBBER = 60.5 * M_PER_FT
#: The front of home plate from its back tip, where Statcast's plate speed is taken:
#: 17 in (m).
PLATE_FRONT = 17.0 / 12.0 * M_PER_FT
#: The league's typical extension, 6.3 ft (m): the MLB average of 2021 (Statcast's
#: ``release_extension``, as reported by Purple Row, "Investigating average release
#: extension", 2022-02-02); the 2,507 pitches of ``data/statcast_2020-09-03.csv`` have a
#: median of 6.2 ft.
DEFAULT_EXTENSION = 6.3 * M_PER_FT
#: The release height, 5.85 ft (m): the median ``release_pos_z`` of the pitches of
#: ``data/statcast_2020-09-03.csv``.
DEFAULT_RELEASE_HEIGHT = 5.85 * M_PER_FT
#: Where the pitch crosses the front of the plate, 2.22 ft up (m): the median ``plate_z``
#: of the same pitches.
DEFAULT_PLATE_HEIGHT = 2.22 * M_PER_FT
#: The fastest release speed converted, 150 m/s (336 mph): the flight model is made for a
#: baseball's speeds.
MAX_RELEASE_SPEED = 150.0
_DT = 1e-3          # s: the flight's samples, fitted near the plate for its velocity
_MAX_TIME = 4.0     # s: a pitch slower than ~10 mph does not reach the plate in this time


def _crossing(params: FlightParams, height: float, speed: float, elevation: float,
              spin: tuple[float, float, float],
              distance: float) -> tuple[NDArray[np.float64], float] | None:
    """Velocity (m/s, 3-vector) and height (m) where a pitch launched from ``(0, 0,
    height)`` towards ``+y`` crosses ``y = distance``; None if it does not get there."""
    v, w = launch_vectors(speed, elevation, 0.0, *spin)
    samples = np.empty((4, int(_MAX_TIME / _DT) + 2))
    _, count = fly_sampled(params, (0.0, 0.0, height), tuple(float(c) for c in v),
                           tuple(float(c) for c in w), samples, _DT)
    t, y = samples[0, :count], samples[2, :count]
    after = np.flatnonzero(y >= distance)
    if after.size == 0 or after[0] == 0:
        return None
    i = int(after[0])
    window = slice(max(0, i - 3), min(count, i + 3))
    if window.stop - window.start < 4 or not np.isfinite(samples[:, window]).all():
        return None
    ts = t[window] - t[i]
    fits = [np.polynomial.Polynomial.fit(ts, samples[k, window], 3) for k in (1, 2, 3)]
    roots = (fits[1] - distance).roots()
    real = [r.real for r in roots if abs(r.imag) < 1e-9 and ts[0] <= r.real <= ts[-1]]
    if not real:
        return None
    tc = min(real, key=abs)
    velocity = np.array([f.deriv()(tc) for f in fits])
    return velocity, float(fits[2](tc))


def plate_speed(release_speed: float, extension: float = DEFAULT_EXTENSION,
                spin_rate: float = 0.0, *, spin_axis: float = math.pi,
                spin_efficiency: float = 1.0, gyro_sign: float = 1.0,
                release_height: float = DEFAULT_RELEASE_HEIGHT,
                plate_height: float = DEFAULT_PLATE_HEIGHT,
                ball: Ball | None = None, settings: FlightSettings | None = None) -> float:
    """The pitch's speed at the front of the plate (m/s).

    Parameters
    ----------
    release_speed : float
        The speed at release, m/s (Statcast's ``release_speed`` is in mph: times ``M_S_PER_MPH``).
    extension : float
        The release point's distance in front of the rubber, m (default 6.3 ft,
        ``DEFAULT_EXTENSION``).
    spin_rate : float
        The pitch's spin, rad/s (default 0).
    spin_axis, spin_efficiency, gyro_sign : float
        Statcast's spin axis (rad; pi backspin, 0 topspin), the transverse fraction of the
        spin and the sense of its gyro part, as a game case's ``pitch`` gives them.
    release_height, plate_height : float
        Heights above the ground at release and at the front of the plate, m (defaults
        the medians of the pitches of ``data/statcast_2020-09-03.csv``: 5.85 ft, 2.22 ft).
    ball : Ball, optional
        Default the ``baseball`` preset.
    settings : FlightSettings, optional
        The air and the flight model (default the calculator's standard conditions:
        70 degF, 29.92 inHg, 50 % humidity, sea level; Nathan's model).

    Returns
    -------
    float
        m/s.

    Raises
    ------
    InputError
        Naming ``release_speed`` for a pitch too slow to reach the plate, ``extension``
        for a release point outside the mound's 60.5 ft.
    """
    speed = _real(release_speed, "release_speed")
    if not 0.0 < speed <= MAX_RELEASE_SPEED:
        raise InputError("release_speed", f"must be > 0 and at most "
                         f"{MAX_RELEASE_SPEED / M_S_PER_MPH:.4g} mph (the flight model is made "
                         f"for a baseball's speeds), got {speed / M_S_PER_MPH:.6g} mph")
    extension = _real(extension, "extension", minimum=0.0)
    distance = RUBBER - extension - PLATE_FRONT
    if not distance > 0.0:
        raise InputError("extension", f"must leave the release point in front of the "
                         f"plate (< {(RUBBER - PLATE_FRONT) / M_PER_FT:.4g} ft), got "
                         f"{extension / M_PER_FT:.6g} ft")
    for name, height in (("release_height", release_height),
                         ("plate_height", plate_height)):
        if not _real(height, name) >= 0.0:
            raise InputError(name, f"must be >= 0 (above the ground), got {height!r} m")
    spin_rate = _real(spin_rate, "spin_rate", minimum=0.0)
    ball = BALL_PRESETS[DEFAULT_BALL] if ball is None else ball
    params = (FlightSettings() if settings is None else settings).params(ball.mass,
                                                                         ball.radius)
    transverse = spin_rate * _real(spin_efficiency, "spin_efficiency", minimum=0.0,
                                   maximum=1.0)
    gyro = gyro_sign * math.sqrt(max(spin_rate * spin_rate - transverse * transverse, 0.0))
    # Statcast's spin axis: pi pure backspin, 0 pure topspin, the rest sideways (its sense
    # only turns the path left or right: the speed at the plate does not depend on it).
    spin = (-transverse * math.cos(spin_axis), transverse * math.sin(spin_axis), gyro)
    # Aim: the elevation that would fall to the plate's height in a vacuum, then the
    # secant method on the height where the pitch crosses the front of the plate.

    def miss(aim: float) -> tuple[NDArray[np.float64], float] | None:
        crossing = _crossing(params, release_height, speed, aim, spin, distance)
        return None if crossing is None else (crossing[0], crossing[1] - plate_height)

    fall = 0.5 * params.gravity * (distance / speed) ** 2  # a first guess: vacuum
    a0 = math.atan2(plate_height - release_height + fall, distance)
    first = miss(a0)
    while first is None and a0 < 1.2:  # short of the plate: the air slows it more
        a0 += 0.05
        first = miss(a0)
    if first is None:
        raise InputError("release_speed", f"a pitch released at {speed / M_S_PER_MPH:.4g} mph "
                         f"does not reach the plate ({distance / M_PER_FT:.4g} ft away)")
    m0 = first[1]
    a1 = a0 + 0.01
    velocity, m1 = miss(a1) or first
    for _ in range(12):
        if abs(m1) < 1e-5 or m1 == m0:
            break
        a0, a1 = a1, a1 - m1 * (a1 - a0) / (m1 - m0)
        m0 = m1
        step = miss(a1)
        if step is None:
            break
        velocity, m1 = step
    return float(np.linalg.norm(velocity))
