"""The accuracy settings of the impact solver: one type for every caller.

A study's ``[solver]`` table, ``mcbat impact --tolerance``, ``mcbat.solve_frame``, the
single-case API, the fits and the spin inference all give the kernels their accuracy as a
``SolverSettings``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from mcbat.checks import check_real as _real
from mcbat.checks import check_tolerance
from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE

__all__ = ["DEFAULT_MAX_STEPS", "DEFAULT_STEPS", "DEFAULT_TOLERANCE", "SolverSettings"]


@dataclass(frozen=True)
class SolverSettings:
    """Accuracy settings of the kernel (see ``mcbat.core.cabo2012.contact``).

    ``steps`` is the number of RK4 steps of each stick or re-slip phase (``int``),
    ``max_steps`` the most adaptive slip steps allowed (``int``; beyond, status
    ``max_steps``). ``tolerance`` is the local error allowed per slip step, relative to
    ``|v0|`` in the slip velocity and to ``I_scale`` in the impulse (dimensionless;
    default 5e-9; ``solve_contact``); it must be finite with ``0 < tolerance < 1``: the
    one rule of a study's ``[solver] tolerance``, ``mcbat impact --tolerance`` and
    ``mcbat.solve_frame`` (``mcbat.checks.check_tolerance``); ``mcbat.errors.InputError``
    names ``tolerance`` otherwise.

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

    def __post_init__(self) -> None:
        object.__setattr__(self, "tolerance",
                           check_tolerance(_real(self.tolerance, "tolerance"), "tolerance"))

    @classmethod
    def from_config(cls, config: Mapping[str, float]) -> SolverSettings:
        """The settings of a study's checked ``[solver]`` table (``{"steps",
        "tolerance", "max_steps"}``, as ``mcbat.study.Study.solver``)."""
        return cls(steps=int(config["steps"]), tolerance=float(config["tolerance"]),
                   max_steps=int(config["max_steps"]))

    def config(self) -> dict[str, float]:
        """``{"steps", "tolerance", "max_steps"}``: the ``[solver]`` table of a study."""
        return {"steps": self.steps, "tolerance": self.tolerance,
                "max_steps": self.max_steps}
