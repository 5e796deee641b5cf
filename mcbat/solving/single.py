"""One impact, one contact history, one flight: the kernels' single-case calls, for the
single-case API (``mcbat.api``). SI units throughout; nothing is checked here.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from mcbat.core.cabo2012 import IMPACT_FIELDS, solve_impact
from mcbat.core.cabo2012.contact import Accuracy
from mcbat.core.cabo2012.impact import ImpactInputs
from mcbat.core.cabo2012.trajectory import contact_history
from mcbat.core.flight.trajectory import MAX_STEPS, Flight, FlightParams, fly, integrate
from mcbat.core.jit import await_group
from mcbat.solving.settings import SolverSettings

#: How many numbers ``solve_one_impact``'s ``physics`` holds.
IMPACT_INPUT_COUNT = len(ImpactInputs._fields)

__all__ = ["IMPACT_INPUT_COUNT", "fly_one", "fly_sampled", "impact_history", "solve_one_impact"]

Vector3 = tuple[float, ...]


def solve_one_impact(physics: tuple[float, ...], settings: SolverSettings) -> dict[str, Any]:
    """Solve one bat-frame impact (``mcbat.core.cabo2012.solve_impact``).

    Parameters
    ----------
    physics : tuple of float
        The fields of ``mcbat.core.cabo2012.impact.ImpactInputs`` in order (SI: kg, m,
        kg m^2, rad, m/s, rad/s; ``mu``, ``e``, ``e_x`` dimensionless). Python floats:
        an int would compile an integer specialisation of the kernel.
    settings : SolverSettings
        The solver's accuracy.

    Returns
    -------
    dict
        ``IMPACT_FIELDS`` -> value (SI), ``status`` among them (0 ok).
    """
    await_group("bat_frame")
    return dict(zip(IMPACT_FIELDS, solve_impact(ImpactInputs(*physics), Accuracy(
        int(settings.steps), float(settings.tolerance), int(settings.max_steps)))))


def impact_history(k: NDArray[np.float64], v0: NDArray[np.float64], mu: float,
                   impulses: NDArray[np.float64],
                   settings: SolverSettings) -> tuple[NDArray[np.float64], float]:
    """The contact as a function of the normal impulse
    (``mcbat.core.cabo2012.trajectory.contact_history``).

    Parameters
    ----------
    k : ndarray of float64, shape (3, 3)
        The Delassus matrix of the contact (1/kg).
    v0 : ndarray of float64, shape (3,)
        The initial relative contact velocity (m/s), contact frame.
    mu : float
        Coulomb friction coefficient.
    impulses : ndarray of float64, shape (m,)
        Sorted normal impulses ``>= 0`` (kg m/s).
    settings : SolverSettings
        Its ``tolerance`` sets the slip steps.

    Returns
    -------
    out : ndarray of float64, shape (m, 6)
        ``v1, v2, v_n`` (m/s), ``W_n``, ``W_fr`` (J) and the phase at each impulse.
    stick_impulse : float
        kg m/s (NaN if slip does not stop before the last impulse).
    """
    out, stick = contact_history(k[0, 0], k[0, 1], k[0, 2], k[1, 1], k[1, 2], k[2, 2],
                                 v0[0], v0[1], v0[2], mu, impulses, settings.tolerance)
    history: NDArray[np.float64] = out
    return history, float(stick)


def fly_one(params: FlightParams, start: Vector3, velocity: Vector3, spin: Vector3) -> Flight:
    """One flight to the landing (``mcbat.core.flight.fly``): position ``start`` (m),
    velocity (m/s), spin (rad/s), field frame; returns a ``Flight`` (SI)."""
    await_group("flight")
    flight: Flight = fly(params, start, velocity, spin)
    return flight


def fly_sampled(params: FlightParams, start: Vector3, velocity: Vector3, spin: Vector3,
                samples: NDArray[np.float64], dt: float) -> tuple[Flight, int]:
    """``fly_one``, also writing the position every ``dt`` s (> 0) into ``samples``
    (``float64[4, m]``: t (s), x, y, z (m)) up to the landing or ``m`` samples
    (``mcbat.core.flight.integrate``). Returns the ``Flight`` and the samples written."""
    await_group("flight")
    flight, count = integrate(params, start, velocity, spin, samples, dt, MAX_STEPS)
    return flight, int(count)
