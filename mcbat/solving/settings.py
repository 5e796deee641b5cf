"""The accuracy settings of the kernels: one type for every caller.

A study's ``[solver]`` table, ``mcbat impact --tolerance``, ``mcbat.solve_frame``, the
single-case API, the fits and the spin inference all give the impact kernel its accuracy
as a ``SolverSettings``; the flight integrator's tolerance (a study's or a ``mcbat flight``
case's ``[flight] tolerance``) travels in the same type, as the ``solver`` of a
``mcbat.study.flight.FlightSettings``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from mcbat.checks import check_real as _real
from mcbat.checks import check_tolerance
from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE
from mcbat.solving.names import FLIGHT_TOLERANCE

__all__ = ["DEFAULT_MAX_STEPS", "DEFAULT_STEPS", "DEFAULT_TOLERANCE", "FLIGHT_TOLERANCE",
           "FLIGHT_TOLERANCE_RANGE", "SolverSettings"]

#: The flight integrator's tolerances allowed (the kernel's error control is tested
#: over this range: ``tests/core/test_flight.py``).
FLIGHT_TOLERANCE_RANGE = (1e-12, 1e-3)


@dataclass(frozen=True)
class SolverSettings:
    """Accuracy settings of the kernels (see ``mcbat.core.cabo2012.contact`` and
    ``mcbat.core.flight``).

    ``steps`` is the number of RK4 steps of each stick or re-slip phase (``int``),
    ``max_steps`` the most adaptive slip steps allowed (``int``; beyond, status
    ``max_steps``). ``tolerance`` is the local error allowed per slip step, relative to
    ``|v0|`` in the slip velocity and to ``I_scale`` in the impulse (dimensionless;
    default 5e-9; ``solve_contact``); it must be finite with ``0 < tolerance < 1``: the
    one rule of a study's ``[solver] tolerance``, ``mcbat impact --tolerance`` and
    ``mcbat.solve_frame`` (``mcbat.checks.check_tolerance``); ``mcbat.errors.InputError``
    names ``tolerance`` otherwise. ``flight_tolerance`` is the flight integrator's local
    error tolerance (dimensionless, in ``FLIGHT_TOLERANCE_RANGE``; default
    ``FLIGHT_TOLERANCE``, 1e-5), which a study or a flight case gives as ``[flight]
    tolerance``.

    >>> SolverSettings(tolerance=1e-10).tolerance
    1e-10
    >>> SolverSettings(tolerance=2.0)
    Traceback (most recent call last):
    ...
    mcbat.errors.InputError: tolerance: must be > 0 and < 1, got 2.0
    """

    steps: int = DEFAULT_STEPS
    tolerance: float = DEFAULT_TOLERANCE
    max_steps: int = DEFAULT_MAX_STEPS
    flight_tolerance: float = FLIGHT_TOLERANCE

    def __post_init__(self) -> None:
        object.__setattr__(self, "tolerance",
                           check_tolerance(_real(self.tolerance, "tolerance"), "tolerance"))
        low, high = FLIGHT_TOLERANCE_RANGE
        object.__setattr__(self, "flight_tolerance",
                           _real(self.flight_tolerance, "flight_tolerance", minimum=low,
                                 maximum=high))

    @classmethod
    def from_config(cls, config: Mapping[str, float],
                    flight_tolerance: float = FLIGHT_TOLERANCE) -> SolverSettings:
        """The settings of a study's checked ``[solver]`` table (``{"steps",
        "tolerance", "max_steps"}``, as ``mcbat.study.Study.solver``), with the flight's
        ``flight_tolerance``."""
        return cls(steps=int(config["steps"]), tolerance=float(config["tolerance"]),
                   max_steps=int(config["max_steps"]), flight_tolerance=flight_tolerance)

    def config(self) -> dict[str, float]:
        """``{"steps", "tolerance", "max_steps"}``: the ``[solver]`` table of a study."""
        return {"steps": self.steps, "tolerance": self.tolerance,
                "max_steps": self.max_steps}
