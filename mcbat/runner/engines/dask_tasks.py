"""What runs on a Dask worker for ``mcbat run --engine dask``.

Imported by the workers when they unpickle a chunk task or the warm-up plugin (both are
pickled by reference to this module), so every worker needs mcbat installed, in the same
environment as the client (checked: ``check_worker``).

A task gets the study as plain data (``mcbat.study.Study.definition``), the run's
``mcbat.runner.plan.ChunkJob`` and a chunk index. It rebuilds the study once per worker
process (cached by the run's config hash), draws the chunk's inputs from (seed, sample
index), solves them with the numba kernel and writes the chunk's Parquet file atomically
itself; it returns only a ``mcbat.runner.plan.ChunkSummary``. Arrays never travel.
"""

from __future__ import annotations

import asyncio
import socket
import threading

import numba
from distributed.diagnostics.plugin import WorkerPlugin

from mcbat.dataset import chunks
from mcbat.errors import InputError
from mcbat.runner.memory import set_run_allocation
from mcbat.runner.pitches import load_pitches
from mcbat.runner.plan import ChunkJob, ChunkSummary, dataset_hash, run_chunk, warm_kernel
from mcbat.study import Study

__all__ = ["WarmUp", "WorkerSetupError", "check_worker", "chunk_task", "set_numba_threads",
           "warm_study", "warm_up"]

# Per worker process: the studies rebuilt so far (config hash -> Study) and the runs
# (config hash, output location) whose environment and output location were checked.
_STUDIES: dict = {}
_CHECKED: set = set()
_CACHE_LOCK = threading.Lock()
# One kernel call at a time per process: numba's workqueue threading layer must not be
# entered from two threads at once; with --nthreads 1 (the recommended setup) the lock is
# never contended. Writing other threads' chunks still overlaps with it.
_KERNEL_LOCK = threading.Lock()


class WorkerSetupError(RuntimeError):
    """A worker cannot compute chunks: another environment, or no access to the output.

    ``field`` names the parameter the user should look at (``out`` or ``scheduler``).
    """

    def __init__(self, field, message):
        super().__init__(field, message)
        self.field = field
        self.message = message

    def __str__(self):
        return self.message


def _host() -> str:
    return socket.gethostname()


def set_numba_threads(threads: int) -> int:
    """Give the calling thread a numba budget of ``threads`` (at most the worker's
    ``NUMBA_NUM_THREADS``); returns the budget. Numba's setting is per thread, so every
    task sets it in the thread it runs in."""
    budget = max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS))
    numba.set_num_threads(budget)
    return budget


def check_worker(job: ChunkJob) -> None:
    """Refuse to compute on a worker whose data could differ from the client's, or that
    cannot see the dataset directory. Checked once per run and worker process."""
    if (job.config_hash, job.out) in _CHECKED:
        return
    mine = chunks.package_versions()
    theirs = job.metadata.get("versions", {})
    for name in sorted(set(mine) | set(theirs)):
        if mine.get(name) != theirs.get(name):
            raise WorkerSetupError(
                "scheduler", f"worker on {_host()} has {name} {mine.get(name)}, the client "
                f"{theirs.get(name)}: every worker needs the client's environment (same "
                f"package versions), or the data would not be reproducible")
    try:
        manifest = chunks.read_manifest(job.out)
    except Exception:  # noqa: BLE001 - reported below as not visible
        manifest = None
    if manifest is None or manifest.get("config_hash") != job.config_hash:
        raise WorkerSetupError(
            "out", f"the worker on {_host()} does not see this dataset at {job.out}: "
            "the output must be on storage every worker shares (the same path on every host, "
            "or a URL)")
    _CHECKED.add((job.config_hash, job.out))


def _study(definition: dict, job: ChunkJob):
    """The run's study, rebuilt from its definition once per worker process."""
    with _CACHE_LOCK:
        study = _STUDIES.get(job.config_hash)
        if study is None:
            meta = job.metadata
            study = Study.from_dict(definition, text=meta.get("study_toml"))
            try:  # (a [pitches] file: read on the worker, which must see it)
                study = load_pitches(study)
            except InputError as err:
                raise WorkerSetupError(err.field, f"the worker on {_host()} cannot use "
                                       f"the [pitches] file: {err.message}") from None
            config = study.config()
            if dataset_hash(config, job.seed, job.samples, job.summary_only) != job.config_hash:
                theirs = (meta.get("study") or {}).get("pitches") or {}
                if "pitches" in config and config["pitches"]["sha256"] != theirs.get("sha256"):
                    raise WorkerSetupError(
                        "pitches.file", f"the worker on {_host()} reads another "
                        f"{study.pitches.path} than the client (its content differs): the "
                        "file must be the same on every host")
                raise WorkerSetupError(
                    "scheduler", f"the study rebuilt on the worker on {_host()} differs "
                    "from the client's (another mcbat version?)")
            _STUDIES[job.config_hash] = study
        return study


def chunk_task(index: int, definition: dict, job: ChunkJob, threads: int) -> ChunkSummary:
    """One chunk on a worker: rebuild the study, solve with ``threads`` numba threads,
    write the Parquet file atomically, return the summary.

    Idempotent: a rerun (a retried task, or the task of a worker that was lost after
    writing) replaces the file with identical content.
    """
    check_worker(job)
    set_numba_threads(threads)
    return run_chunk(_study(definition, job), job, index, solve_lock=_KERNEL_LOCK)


def warm_study(definition: dict, job: ChunkJob, threads: int) -> None:
    """Load (or compile) the kernels of the run's study in this worker, by drawing and
    solving its first sample as a chunk does, nothing written (``DaskEngine.ready``).
    Checks the worker first, as a chunk task does."""
    check_worker(job)
    set_numba_threads(threads)
    study = _study(definition, job)
    with _KERNEL_LOCK:
        warm_kernel(study, job.seed)


def warm_up(threads: int) -> dict:
    """Load the libraries a chunk needs (pandas for the version check, Parquet) in this
    worker, once, instead of in its first chunk. The kernels depend on the study: the
    engine loads them when a run starts (``warm_study``)."""
    budget = set_numba_threads(threads)
    set_run_allocation()  # a worker runs chunk after chunk: keep their buffers
    chunks.package_versions()
    return {"threads": budget, "numba_num_threads": numba.config.NUMBA_NUM_THREADS,
            "threading_layer": numba.threading_layer()}


class WarmUp(WorkerPlugin):
    """Worker plugin: set up every worker once (also one that joins or is restarted
    later), in the worker's own task thread, before it gets a chunk (``warm_up``)."""

    name = "mcbat-warm-up"

    def __init__(self, threads: int):
        self.threads = threads

    async def setup(self, worker):
        """Set up ``worker`` (called by Dask when the worker joins)."""
        # In the worker's task executor, not the event loop: importing the libraries may
        # take seconds, and the worker must keep answering the scheduler.
        executor = worker.executors.get("default")
        loop = asyncio.get_running_loop()
        await loop.run_in_executor(executor, warm_up, self.threads)
