"""Parallel batch kernel: many impacts, struct-of-arrays in, struct-of-arrays out.

Inputs are the rows of one ``float64[len(INPUT_FIELDS), n]`` array (each row one field,
contiguous); outputs go to ``float64[len(OUTPUT_FIELDS), n]`` plus ``int8`` status and
end-state arrays. The loop is a ``numba.prange``: rows are independent, so the result does
not depend on the thread count. No Python objects and nothing raises inside the loop; a
row that cannot be solved gets a non-zero status and NaN outputs.
"""

import numba
import numpy as np

from mcbat.core.cabo2012.contact import Accuracy
from mcbat.core.cabo2012.impact import INPUT_FIELDS as IMPACT_INPUT_FIELDS
from mcbat.core.cabo2012.impact import ImpactInputs, solve_impact
from mcbat.core.jit import njit

__all__ = ["INPUT_FIELDS", "OUTPUT_FIELDS", "allocate_outputs", "solve_batch", "store_impact"]

INPUT_FIELDS = IMPACT_INPUT_FIELDS
"""Solver inputs: the fields of ``mcbat.core.cabo2012.impact.ImpactInputs`` (SI units)."""

OUTPUT_FIELDS = (
    "ball_vx", "ball_vy", "ball_vz", "ball_wx", "ball_wy", "ball_wz",
    "bat_vx", "bat_vy", "bat_vz", "bat_wx", "bat_wy", "bat_wz",
    "normal_impulse", "stick_impulse", "compression_impulse",
    "tangential_impulse_1", "tangential_impulse_2",
    "compression_work", "normal_work", "friction_work", "stick_criterion",
    "energy_in", "energy_out", "rk4_steps",
)
"""Float outputs, named as in ``mcbat.core.cabo2012.IMPACT_FIELDS`` (``status`` and
``end_state`` go to their own ``int8`` arrays)."""

_N_IN = len(INPUT_FIELDS)
_N_OUT = len(OUTPUT_FIELDS)


@njit(inline="always")
def store_impact(r, col, out, status, end_state):
    """Write the result ``r`` of ``solve_impact`` into column ``col`` of the batch
    outputs: ``status`` and ``end_state`` its codes, ``out`` its ``OUTPUT_FIELDS``.
    Inlined into the loops of ``solve_batch`` and the game kernel."""
    status[col] = r[0]
    end_state[col] = r[1]
    out[0, col] = r[2]
    out[1, col] = r[3]
    out[2, col] = r[4]
    out[3, col] = r[5]
    out[4, col] = r[6]
    out[5, col] = r[7]
    out[6, col] = r[8]
    out[7, col] = r[9]
    out[8, col] = r[10]
    out[9, col] = r[11]
    out[10, col] = r[12]
    out[11, col] = r[13]
    out[12, col] = r[14]
    out[13, col] = r[15]
    out[14, col] = r[16]
    out[15, col] = r[17]
    out[16, col] = r[18]
    out[17, col] = r[19]
    out[18, col] = r[20]
    out[19, col] = r[21]
    out[20, col] = r[22]
    out[21, col] = r[23]
    out[22, col] = r[24]
    out[23, col] = r[25]


@njit(parallel=True)
def solve_batch(inputs, steps, tolerance, max_steps, out, status, end_state):
    """Solve ``inputs.shape[1]`` impacts in parallel.

    Parameters
    ----------
    inputs : float64[len(INPUT_FIELDS), n]
        One row per field of ``INPUT_FIELDS``.
    steps, tolerance, max_steps
        Accuracy settings (see ``mcbat.core.cabo2012.contact.solve_contact``).
    out : float64[len(OUTPUT_FIELDS), n]
        Written: one row per field of ``OUTPUT_FIELDS``.
    status, end_state : int8[n]
        Written: codes from ``mcbat.core.status``.
    """
    n = inputs.shape[1]
    accuracy = Accuracy(steps, tolerance, max_steps)
    for i in numba.prange(n):
        r = solve_impact(ImpactInputs(
            inputs[0, i], inputs[1, i], inputs[2, i], inputs[3, i], inputs[4, i],
            inputs[5, i], inputs[6, i], inputs[7, i], inputs[8, i], inputs[9, i],
            inputs[10, i], inputs[11, i], inputs[12, i], inputs[13, i], inputs[14, i],
            inputs[15, i], inputs[16, i], inputs[17, i], inputs[18, i], inputs[19, i],
            inputs[20, i], inputs[21, i], inputs[22, i], inputs[23, i], inputs[24, i]),
            accuracy)
        store_impact(r, i, out, status, end_state)


def allocate_outputs(n):
    """Empty output arrays for ``solve_batch``: ``(out, status, end_state)``."""
    return (np.empty((_N_OUT, n), np.float64), np.empty(n, np.int8), np.empty(n, np.int8))
