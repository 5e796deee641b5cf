"""Status and end-state codes returned by the jitted solvers.

Codes are small integers so they fit in ``int8`` columns and cross the numba boundary
without Python objects. ``STATUS_NAMES`` / ``END_STATE_NAMES`` give the public strings.
"""

__all__ = ["DEGENERATE", "END_STATE_NAMES", "INVALID_INPUT", "MAX_STEPS", "NOT_APPROACHING",
           "OK", "SLIDING", "STATUS_NAMES", "STUCK"]

OK = 0
"""The impact was solved."""
NOT_APPROACHING = 1
"""The contact points are not approaching (v_n >= 0): there is no impact."""
MAX_STEPS = 2
"""The slip integration hit its step limit before sliding ended or the bodies separated."""
DEGENERATE = 3
"""Degenerate mechanics: a non-positive effective normal compliance, or no re-slip direction."""
INVALID_INPUT = 4
"""A non-finite or out-of-range number reached the kernel, or finite inputs so extreme that
the result overflowed (it is then flagged rather than returned as ok)."""

STATUS_NAMES = {
    OK: "ok",
    NOT_APPROACHING: "not_approaching",
    MAX_STEPS: "max_steps",
    DEGENERATE: "degenerate",
    INVALID_INPUT: "invalid_input",
}

SLIDING = 0
"""The contact is slipping at separation (no stick, or re-slip after a failed stick)."""
STUCK = 1
"""The contact points have zero relative tangential velocity at separation."""

END_STATE_NAMES = {SLIDING: "sliding", STUCK: "stuck"}
