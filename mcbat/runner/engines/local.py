"""The local engine: the chunks in this process."""

from __future__ import annotations

import contextlib
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace

from mcbat.runner.plan import ChunkJob, run_chunk, set_threads, warm_kernel, write_error

__all__ = ["LocalEngine"]


class LocalEngine:
    """Chunks in this process: numba threads solve, a writer thread writes the previous
    chunk meanwhile (at most one chunk in flight: bounded memory).

    Parameters
    ----------
    threads : int, optional
        Numba threads for the kernel (default: all of ``NUMBA_NUM_THREADS``).
    """

    name = "local"

    def __init__(self, threads=None):
        self.threads = set_threads(threads)

    def connect(self):
        """Nothing to start: a null context."""
        return contextlib.nullcontext()

    def ready(self):
        """Load the compiled kernel before the clock starts, as the Dask engine's workers
        do: the run's rows/s then measure the same thing for both engines."""
        warm_kernel()

    def run(self, study, job: ChunkJob, todo, display):
        """Compute the chunks ``todo`` in order; yield each one's summary, with its file's
        record, once its file is written (chunk k is written while chunk k+1 solves; a
        summary-only chunk, which writes nothing, at once)."""
        with ThreadPoolExecutor(max_workers=1, thread_name_prefix="mcbat-writer") as writer:
            writing = None  # (summary without its record, the write's future)
            submitted = []

            def write(function, *args):
                submitted.append(writer.submit(function, *args))

            for k in todo:
                submitted.clear()
                summary = run_chunk(study, job, k, write=write)
                if writing is not None:  # the previous chunk's file, written meanwhile
                    yield replace(writing[0], file=_finish(writing[1], display))
                    writing = None
                if submitted:
                    writing = (summary, submitted.pop())
                else:
                    yield summary
            if writing is not None:
                yield replace(writing[0], file=_finish(writing[1], display))

    def note(self, summaries):
        """No note: the local engine is the default."""
        return None


def _finish(pending, out) -> dict:
    """Wait for a chunk write and return its record; a full or unwritable disk is a clear
    error, not a crash."""
    try:
        return pending.result()
    except OSError as err:
        raise write_error(err, out) from None
