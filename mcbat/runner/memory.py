"""Keep a run's freed chunk buffers in the process instead of giving them back to the OS.

Every chunk allocates the same large arrays (the sampled inputs, the kernel's outputs: ~30
MB each at the default 2**17 rows) and frees them at its end. glibc's default is to return
freed memory at the top of the heap to the OS as soon as 128 kB of it are free, and to map
arrays past its (adaptive) mmap threshold afresh, so every chunk paid page faults on
first touch, inside the parallel sampler and kernel: 7-13 ms of a 150 ms chunk on a
2-core VM (``mcbat run --summary-only`` on ``studies/throughput.toml``).

``reuse_freed_memory`` raises the trim threshold to 1 GiB and pins the mmap threshold
at its 32 MiB maximum for the duration of a run, then restores glibc's defaults and trims.
Elsewhere than glibc (macOS, musl) it does nothing.
"""

from __future__ import annotations

import contextlib
import ctypes

__all__ = ["reuse_freed_memory", "set_run_allocation"]

# mallopt(3) parameters and glibc's defaults.
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3
_DEFAULT_TRIM_THRESHOLD = 128 * 1024
_DEFAULT_MMAP_THRESHOLD = 128 * 1024
_RUN_TRIM_THRESHOLD = 1 << 30
_RUN_MMAP_THRESHOLD = 32 << 20  # glibc's largest on 64-bit systems


def _glibc():
    """The C library, when it is glibc (it has ``mallopt`` and ``malloc_trim``)."""
    try:
        libc = ctypes.CDLL(None)
        if not (hasattr(libc, "mallopt") and hasattr(libc, "malloc_trim")
                and hasattr(libc, "gnu_get_libc_version")):
            return None
    except OSError:
        return None
    return libc


def set_run_allocation(libc=None) -> bool:
    """Keep freed memory for reuse from now on (a Dask worker's whole life); returns
    whether the C library took the settings."""
    libc = _glibc() if libc is None else libc
    if libc is None:
        return False
    return bool(libc.mallopt(_M_MMAP_THRESHOLD, _RUN_MMAP_THRESHOLD)
                and libc.mallopt(_M_TRIM_THRESHOLD, _RUN_TRIM_THRESHOLD))


@contextlib.contextmanager
def reuse_freed_memory():
    """For the duration of the block, keep freed heap memory for reuse (see the module's
    docstring); afterwards glibc's default thresholds are restored and the heap trimmed."""
    libc = _glibc()
    if libc is None or not set_run_allocation(libc):
        yield
        return
    try:
        yield
    finally:
        libc.mallopt(_M_TRIM_THRESHOLD, _DEFAULT_TRIM_THRESHOLD)
        libc.mallopt(_M_MMAP_THRESHOLD, _DEFAULT_MMAP_THRESHOLD)
        libc.malloc_trim(0)
