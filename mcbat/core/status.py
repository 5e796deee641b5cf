"""Status and end-state codes returned by the jitted solvers.

Codes are small integers so they fit in ``int8`` columns and cross the numba boundary
without Python objects. ``STATUS_NAMES`` / ``END_STATE_NAMES`` give the public strings.

Python code compares with the named members of ``ImpactStatus`` and ``EndState``
(``IntEnum``: a member equals its integer, element-wise on arrays too); the jitted
kernels use the plain integer constants beside them (``OK``, ``SLIDING``, ...), which hold
the same values.
"""

from enum import IntEnum

__all__ = ["DEGENERATE", "END_STATE_NAMES", "INVALID_INPUT", "MAX_STEPS", "NOT_APPROACHING",
           "OK", "SLIDING", "STATUS_NAMES", "STUCK", "EndState", "ImpactStatus"]


class ImpactStatus(IntEnum):
    """Status of a solved impact (the ``status`` column; values as the constants below)."""

    OK = 0
    NOT_APPROACHING = 1
    MAX_STEPS = 2
    DEGENERATE = 3
    INVALID_INPUT = 4


class EndState(IntEnum):
    """State of the contact at separation (the ``end_state`` column)."""

    SLIDING = 0
    STUCK = 1


OK = int(ImpactStatus.OK)
"""The impact was solved."""
NOT_APPROACHING = int(ImpactStatus.NOT_APPROACHING)
"""The contact points are not approaching (v_n >= 0): there is no impact."""
MAX_STEPS = int(ImpactStatus.MAX_STEPS)
"""The slip integration hit its step limit before sliding ended or the bodies separated."""
DEGENERATE = int(ImpactStatus.DEGENERATE)
"""Degenerate mechanics: a non-positive effective normal compliance, or no re-slip direction."""
INVALID_INPUT = int(ImpactStatus.INVALID_INPUT)
"""A non-finite or out-of-range number reached the kernel, or finite inputs so extreme that
the result overflowed (it is then flagged rather than returned as ok)."""

STATUS_NAMES = {
    OK: "ok",
    NOT_APPROACHING: "not_approaching",
    MAX_STEPS: "max_steps",
    DEGENERATE: "degenerate",
    INVALID_INPUT: "invalid_input",
}

SLIDING = int(EndState.SLIDING)
"""The contact is slipping at separation (no stick, or re-slip after a failed stick)."""
STUCK = int(EndState.STUCK)
"""The contact points have zero relative tangential velocity at separation."""

END_STATE_NAMES = {SLIDING: "sliding", STUCK: "stuck"}
