"""The one place for numba options used by every jitted function in mcbat.

``cache=True``
    compiled machine code is stored next to the sources, so warm starts skip LLVM.
``fastmath=False``
    the stick location and event root-finding rely on IEEE semantics (no reassociation,
    NaN checks must stay); accuracy against the reference integrator is a tested contract.
``error_model="numpy"``
    division by zero gives inf/NaN instead of raising, so kernels never raise inside
    ``prange``; the solvers check their inputs and report a status code instead.
"""

import numba

JIT_OPTIONS = {"cache": True, "fastmath": {"contract"}, "error_model": "numpy", "nogil": True}


def njit(*args, **overrides):
    """``numba.njit`` with the project's options (``overrides`` win)."""
    options = {**JIT_OPTIONS, **overrides}
    if args and callable(args[0]):
        return numba.njit(**options)(args[0])
    return numba.njit(*args, **options)
