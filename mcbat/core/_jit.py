"""The one place for numba options used by every jitted function in mcbat.

``cache=True``
    compiled machine code is stored next to the sources, so warm starts skip LLVM.
    numba checks only the timestamp of the file that defines a cached function, not of the
    modules it calls: after editing ``mcbat/core`` in a checkout, delete the caches
    (``find mcbat -name __pycache__ -exec rm -rf {} +``). Installed releases are not
    affected (an upgrade rewrites every file).
``fastmath={"contract"}``
    only fused multiply-add contraction, which rounds once instead of twice (never less
    accurate; measured +5 % kernel throughput). No reassociation, no approximate
    reciprocals, no assumptions about NaN/inf: the status checks rely on IEEE semantics.
``error_model="numpy"``
    division by zero gives inf/NaN instead of raising, so kernels never raise inside
    ``prange``; the solvers check their inputs and report a status code instead.
``nogil=True``
    kernels can run in threads (the Dask engine, thread pools) concurrently.
"""

import numba

JIT_OPTIONS = {"cache": True, "fastmath": {"contract"}, "error_model": "numpy", "nogil": True}


def njit(*args, **overrides):
    """``numba.njit`` with the project's options (``overrides`` win)."""
    options = {**JIT_OPTIONS, **overrides}
    if args and callable(args[0]):
        return numba.njit(**options)(args[0])
    return numba.njit(*args, **options)
