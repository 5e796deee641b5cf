"""The local engine: the chunks in this process."""

from __future__ import annotations

import contextlib
from collections import deque
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace

from mcbat.runner.plan import ChunkJob, run_chunk, set_threads, warm_kernel, write_error

__all__ = ["LocalEngine"]


class LocalEngine:
    """Chunks in this process: numba threads solve, writer threads write the previous
    chunks meanwhile (at most ``IN_FLIGHT`` chunks in flight: bounded memory).

    Parameters
    ----------
    threads : int, optional
        Numba threads for the kernel (default: all of ``NUMBA_NUM_THREADS``).
    """

    name = "local"
    #: Chunk files being written while the next chunk solves. Two (a second writer thread
    #: while the first waits in fsync) were no faster within the noise of the 2-core
    #: machine (medians of 5 runs of throughput.toml: 439k against 421k rows/s) for one
    #: more chunk of memory.
    IN_FLIGHT = 1

    def __init__(self, threads=None):
        self.threads = set_threads(threads)

    def connect(self):
        """Nothing to start: a null context."""
        return contextlib.nullcontext()

    def ready(self, study, job: ChunkJob, display=None):
        """Load (or compile) the study's kernels before the clock starts, as the Dask
        engine's workers do: the run's rows/s then measure the same thing for both
        engines."""
        warm_kernel(study, job.seed)

    def run(self, study, job: ChunkJob, todo, display):
        """Compute the chunks ``todo`` in order; yield each one's summary, with its file's
        record, once its file is written, in chunk order.

        Up to ``IN_FLIGHT`` chunk files are written by writer threads while the next
        chunk solves; a chunk is yielded as soon as its write is seen done. A summary-only
        chunk, which writes nothing, is yielded at once.
        """
        with ThreadPoolExecutor(max_workers=self.IN_FLIGHT,
                                thread_name_prefix="mcbat-writer") as writer:
            writing = deque()  # (summary without its record, the write's future), in order
            submitted = []

            def write(function, *args):
                submitted.append(writer.submit(function, *args))

            for k in todo:
                submitted.clear()
                summary = run_chunk(study, job, k, write=write)
                writing.append((summary, submitted.pop() if submitted else None))
                # Record what is written, in order; wait only with too many in flight.
                while writing and (len(writing) > self.IN_FLIGHT or writing[0][1] is None
                                   or writing[0][1].done()):
                    done, future = writing.popleft()
                    yield done if future is None else replace(done, file=_finish(
                        future, display))
            while writing:
                done, future = writing.popleft()
                yield done if future is None else replace(done, file=_finish(future, display))

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
