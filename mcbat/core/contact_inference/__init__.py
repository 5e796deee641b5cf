"""The contact behind a measured batted ball: the game model run backwards by a damped
Newton iteration (equations, identification and assumptions in ``README.md``)."""

from mcbat.core.contact_inference.solver import (
    CONVERGED,
    INFER_BAT_SPEED,
    INFER_FROM_BARREL_END,
    INFER_NEAREST_BAT_SPEED,
    INFERENCE_STATUS_NAMES,
    INVALID_INPUT,
    MAX_ITERATIONS,
    NO_SOLUTION,
    OBSERVED_FIELDS,
    SOLUTION_FIELDS,
    InferenceSettings,
    InferenceStatus,
    allocate_inference_outputs,
    infer_contact_batch,
)

__all__ = ["CONVERGED", "INFERENCE_STATUS_NAMES", "INFER_BAT_SPEED", "INFER_FROM_BARREL_END",
           "INFER_NEAREST_BAT_SPEED", "INVALID_INPUT", "MAX_ITERATIONS", "NO_SOLUTION",
           "OBSERVED_FIELDS", "SOLUTION_FIELDS", "InferenceSettings", "InferenceStatus",
           "allocate_inference_outputs", "infer_contact_batch"]
