"""Run a study: sample -> batch kernel -> Parquet chunks, resumable.

The flow is one-way: the validated study draws the inputs of each chunk (deterministic in
the sample index), the parallel kernel solves them, and the struct-of-arrays becomes one
Parquet file per chunk. :func:`run_chunk` is that whole step for one chunk; the engines
only decide where it runs:

* ``local`` (the default): in this process, numba threads for the kernel, and a writer
  thread that writes a chunk while the next one is being solved;
* ``dask``: one task per chunk on a Dask cluster (:mod:`mcbat.dask_engine`).

Resumption: the dataset manifest records a hash of everything that determines the data
(study config, seed, sample count). A rerun with the same hash keeps every complete chunk
file and computes only the missing ones; a different hash is refused unless the user asks
to overwrite. A re-run of a finished study changes nothing. Preparing the directory and
choosing the chunks to compute is shared by the engines.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import socket
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mcbat import dataset as ds
from mcbat.core import status as st
from mcbat.core.batch import INPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.errors import InputError

DEFAULT_CHUNK_SIZE = 250_000
ENGINES = ("local", "dask")


@dataclass
class RunSummary:
    """What a run did."""

    directory: Path
    rows: int
    chunks_total: int
    chunks_computed: int
    chunks_kept: int
    seconds: float
    status_counts: dict = field(default_factory=dict)
    engine_note: str | None = None

    @property
    def rows_per_second(self) -> float:
        computed_rows = self.rows * self.chunks_computed / max(self.chunks_total, 1)
        return computed_rows / self.seconds if self.seconds > 0 else float("nan")

    def lines(self) -> list[str]:
        failed = sum(v for k, v in self.status_counts.items() if k != "ok")
        out = [f"dataset: {self.directory}",
               f"rows: {self.rows:,} in {self.chunks_total} chunk file(s) "
               f"({self.chunks_computed} computed, {self.chunks_kept} kept from before)"]
        if self.chunks_computed:
            out.append(f"time: {self.seconds:.2f} s ({self.rows_per_second:,.0f} rows/s)")
        if self.engine_note:
            out.append(self.engine_note)
        if self.status_counts:
            parts = ", ".join(f"{k}: {v:,}" for k, v in self.status_counts.items())
            out.append(f"status of computed rows: {parts}"
                       + (f"  <- {failed:,} failed rows are flagged in 'status'" if failed
                          else ""))
        return out


def dataset_hash(study_config: dict, seed: int, samples: int) -> str:
    """Hash of everything that determines the rows of a dataset."""
    payload = {"schema": ds.SCHEMA_VERSION, "study": study_config, "seed": seed,
               "samples": samples}
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()


def _positive_int(value, name):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InputError(name, f"must be an integer >= 1, got {value!r}")
    return int(value)


def _prepare_directory(out, manifest: dict, chunk_size: int, overwrite: bool, *,
                       check_only: bool = False) -> None:
    """Create ``out`` or check that it holds this very dataset; never lose foreign data.

    With ``check_only`` nothing is written: only the checks that can refuse the run.
    """
    kind = ds.entry_type(out)
    if kind == "file":
        raise InputError("--out", "exists and is not a directory", str(out))
    names = ds.list_names(out) if kind == "dir" else []
    if names:
        existing = ds.read_manifest(out)
        if existing is None:
            raise InputError("--out", "is not empty and is not an mcbat dataset; choose "
                             "another directory", str(out))
        same = existing.get("config_hash") == manifest["config_hash"]
        if not same or existing.get("chunk_size") != chunk_size:
            if not overwrite:
                what = ("a different study config, seed or sample count" if not same else
                        f"chunk size {existing.get('chunk_size')}")
                raise InputError("--out", f"holds a dataset written with {what}; "
                                 "pass --overwrite to replace it, or choose another "
                                 "directory", str(out))
            foreign = [name for name in names
                       if name != ds.MANIFEST and not ds._CHUNK_RE.match(name)
                       and not name.startswith(".chunk-")]
            if foreign:
                raise InputError("--out", f"holds files mcbat did not write "
                                 f"({foreign[0]!r}); refusing to overwrite", str(out))
            if check_only:
                return
            for name in names:
                ds.remove(out, name)
    if check_only:
        return
    ds.make_dirs(out)
    # Leftover temporary files of a killed run are never trusted.
    remove_temporary_files(out)
    if ds.read_manifest(out) != manifest:
        ds.write_json_atomic(manifest, ds.join(out, ds.MANIFEST))


def remove_temporary_files(out) -> int:
    """Delete the temporary chunk files (``.chunk-*.tmp``) a killed writer left in
    ``out``; returns how many. Only safe when no writer of this dataset is running."""
    removed = 0
    for name in ds.list_names(out):
        if name.startswith(".chunk-") and name.endswith(".tmp"):
            ds.remove(out, name, missing_ok=True)
            removed += 1
    return removed


@dataclass(frozen=True)
class ChunkJob:
    """What every chunk of one run shares. Small and picklable: the Dask engine sends it,
    with the study's plain-data definition and a chunk index, to the workers.

    Attributes
    ----------
    out : str
        Dataset directory: an absolute local path or a URL.
    samples, seed, chunk_size : int
        The run's sample count, seed and rows per chunk.
    config_hash : str
        :func:`dataset_hash` of the run; stored in every chunk file.
    metadata : dict
        JSON-serialisable dataset metadata stored in every chunk file's schema.
    """

    out: str
    samples: int
    seed: int
    chunk_size: int
    config_hash: str
    metadata: dict

    @property
    def chunks(self) -> int:
        """Number of chunks of the dataset."""
        return -(-self.samples // self.chunk_size)

    def bounds(self, index: int) -> tuple[int, int]:
        """``(start, stop)``: the sample indices of chunk ``index``."""
        start = index * self.chunk_size
        return start, min(self.samples, start + self.chunk_size)

    def rows(self, index: int) -> int:
        """Number of rows of chunk ``index``."""
        start, stop = self.bounds(index)
        return stop - start

    def path(self, index: int):
        """Location of the Parquet file of chunk ``index``."""
        return ds.join(self.out, ds.chunk_name(index))


@dataclass(frozen=True)
class ChunkSummary:
    """What computing one chunk returns (small: no arrays).

    Attributes
    ----------
    index, rows : int
        The chunk and its number of rows.
    status_counts : tuple of int
        Rows per status code (:data:`mcbat.core.status.STATUS_NAMES`).
    threads : int
        Numba threads the kernel ran with.
    worker : str
        ``host:pid`` of the process that computed it.
    """

    index: int
    rows: int
    status_counts: tuple
    threads: int
    worker: str


def write_chunk(table_args, path) -> None:
    """Build a chunk's table and write it atomically (see :func:`run_chunk`)."""
    ds.write_atomic(ds.build_table(*table_args), path)


def run_chunk(study, job: ChunkJob, index: int, *, write=None,
              solve_lock=None) -> ChunkSummary:
    """Compute chunk ``index`` of a run and write its Parquet file atomically.

    The chunk's inputs are drawn from ``(seed, sample index)`` alone
    (:meth:`mcbat.study.Study.sample`), so the file is the same wherever and however
    often it is computed: a rerun overwrites it with identical content.

    Parameters
    ----------
    study : mcbat.study.Study
        The validated study (its solver settings are used).
    job : ChunkJob
        The run's output location, sample count, seed, chunk size and metadata.
    index : int
        The chunk.
    write : callable, optional
        ``write(write_chunk, table_args, path)`` writes the file. Default: write it now,
        before returning. The local engine hands it to its writer thread instead.
    solve_lock : context manager, optional
        Held while the kernel runs (the Dask engine serialises kernel calls of a worker's
        threads with it).

    Returns
    -------
    ChunkSummary
    """
    import numba

    start, stop = job.bounds(index)
    solver = study.solver
    columns = study.sample(start, stop, job.seed)
    inputs = np.stack([np.asarray(columns[name], np.float64) for name in INPUT_FIELDS])
    out_arr, status, end_state = allocate_outputs(stop - start)
    with solve_lock if solve_lock is not None else contextlib.nullcontext():
        threads = numba.get_num_threads()
        solve_batch(inputs, solver["steps"], solver["tolerance"], solver["max_steps"],
                    out_arr, status, end_state)
    counts = np.bincount(status, minlength=len(st.STATUS_NAMES))
    table_args = (start, index, inputs, out_arr, status, end_state,
                  {"impact_parameter": np.asarray(columns["impact_parameter"])},
                  job.metadata, study.measurement_noise(start, stop, job.seed))
    (write or _write_now)(write_chunk, table_args, job.path(index))
    return ChunkSummary(index, stop - start, tuple(int(c) for c in counts), threads,
                        f"{socket.gethostname()}:{os.getpid()}")


def _write_now(function, *args):
    function(*args)


def warm_kernel() -> None:
    """Load (or compile) the batch kernel by solving one impact: a worker does it once,
    before its first chunk."""
    row = {name: 0.0 for name in INPUT_FIELDS}
    row.update(ball_mass=0.145, ball_radius=0.036, ball_inertia_factor=0.4, bat_mass=0.989,
               bat_transverse_inertia=0.046, bat_axial_inertia=4.39e-4, axial=0.115,
               angle=0.00785, bat_radius=0.03335, ball_vx_in=-4.0, mu=0.5, e=0.8)
    inputs = np.array([[row[name]] for name in INPUT_FIELDS], np.float64)
    out_arr, status, end_state = allocate_outputs(1)
    from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE

    solve_batch(inputs, DEFAULT_STEPS, DEFAULT_TOLERANCE, DEFAULT_MAX_STEPS, out_arr, status,
                end_state)


class _LocalEngine:
    """Chunks in this process: numba threads solve, a writer thread writes the previous
    chunk meanwhile (at most one chunk in flight: bounded memory)."""

    name = "local"

    def connect(self):
        return contextlib.nullcontext()

    def ready(self):
        """Load the compiled kernel before the clock starts, as the Dask engine's workers
        do: the run's rows/s then measure the same thing for both engines."""
        warm_kernel()

    def run(self, study, job: ChunkJob, todo, display):
        with ThreadPoolExecutor(max_workers=1, thread_name_prefix="mcbat-writer") as writer:
            pending = None

            def write(function, *args):
                nonlocal pending
                if pending is not None:
                    _finish(pending, display)
                pending = writer.submit(function, *args)

            for k in todo:
                yield run_chunk(study, job, k, write=write)
            if pending is not None:
                _finish(pending, display)

    def note(self, summaries):
        return None


def run_study(study, out, *, samples=None, seed=None, threads=None, chunk_size=None,
              overwrite=False, progress=True, engine="local", scheduler=None,
              workers=None) -> RunSummary:
    """Run ``study`` into the dataset directory ``out`` (resuming if possible).

    Parameters
    ----------
    study : mcbat.study.Study
        A validated study.
    out : str or Path
        Dataset directory: a local path, or a URL (see :mod:`mcbat.dataset`).
    samples, seed, chunk_size : int, optional
        Override the study's defaults.
    threads : int, optional
        Numba threads for the batch kernel: of this process (``local``; default: all), or
        of each Dask worker (``dask``; see :class:`mcbat.dask_engine.DaskEngine`).
    overwrite : bool
        Replace an existing dataset of a different config.
    progress : bool
        Show a tqdm progress bar (impacts per second) on stderr.
    engine : {"local", "dask"}
        Where the chunks are computed. The data are identical either way.
    scheduler : str, optional
        ``dask``: address of a running Dask scheduler to join.
    workers : int, optional
        ``dask``: start a local cluster of this many worker processes (default: one per
        core, when no ``scheduler`` is given).
    """
    samples = _positive_int(study.samples if samples is None else samples, "--samples")
    seed = study.seed if seed is None else seed
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError("--seed", f"must be an integer >= 0, got {seed!r}")
    if chunk_size is None:
        chunk_size = getattr(study, "chunk_size", None) or DEFAULT_CHUNK_SIZE
    chunk_size = _positive_int(chunk_size, "--chunk-size")
    runner = _engine(engine, threads, scheduler, workers)

    display = ds.location(out)
    job, manifest = plan_run(study, display, samples, int(seed), chunk_size)
    n_chunks, config_hash = job.chunks, job.config_hash
    with _out_errors(display):
        # Everything that can refuse the run, before a cluster is started or joined.
        _prepare_directory(display, manifest, chunk_size, overwrite, check_only=True)
    with runner.connect():
        with _out_errors(display):
            _prepare_directory(display, manifest, chunk_size, overwrite)
            existing = ds.chunk_files(display)
        todo = [k for k in range(n_chunks)
                if existing.get(k) is None
                or not ds.chunk_is_complete(existing[k], job.rows(k), config_hash)]
        kept = n_chunks - len(todo)

        bar = None
        if progress and todo:
            from tqdm import tqdm

            total = sum(job.rows(k) for k in todo)
            bar = tqdm(total=total, unit=" impacts", unit_scale=True, file=sys.stderr,
                       desc=f"{study.name}", dynamic_ncols=True, smoothing=0.1)
        counts = np.zeros(len(st.STATUS_NAMES), np.int64)
        summaries = []
        if todo:
            runner.ready()
        t0 = time.perf_counter()
        try:
            for summary in runner.run(study, job, todo, display):
                counts += summary.status_counts
                summaries.append(summary)
                if bar is not None:
                    bar.update(summary.rows)
        finally:
            seconds = time.perf_counter() - t0
            if bar is not None:
                bar.close()
    status_counts = ({st.STATUS_NAMES[i]: int(c) for i, c in enumerate(counts) if c}
                     if todo else {})
    return RunSummary(display, samples, n_chunks, len(todo), kept, seconds, status_counts,
                      runner.note(summaries) if todo else None)


def plan_run(study, out, samples: int, seed: int, chunk_size: int) -> tuple[ChunkJob, dict]:
    """The :class:`ChunkJob` and the dataset manifest of a run (validated arguments).

    A local ``out`` becomes absolute in the job: workers may run in another working
    directory, or on another host where the same path names the same shared storage.
    """
    display = ds.location(out)
    where = display if not isinstance(display, Path) else Path(os.path.abspath(display))
    config = study.config()
    config_hash = dataset_hash(config, seed, samples)
    n_chunks = -(-samples // chunk_size)
    manifest = {"schema": ds.SCHEMA_VERSION, "config_hash": config_hash, "seed": seed,
                "samples": samples, "chunk_size": chunk_size, "chunks": n_chunks,
                "study": config, "study_name": study.name}
    metadata = {"config_hash": config_hash, "seed": seed, "samples": samples,
                "chunk_size": chunk_size, "study": config, "study_toml": study.source_text,
                "units": ds.UNITS, "versions": ds.package_versions(),
                "status_codes": st.STATUS_NAMES, "end_state_codes": st.END_STATE_NAMES,
                "schema": ds.SCHEMA_VERSION}
    return ChunkJob(str(where), samples, seed, chunk_size, config_hash, metadata), manifest


def _engine(engine, threads, scheduler, workers):
    """Validate the engine options (before anything is written) and build the engine."""
    import numba

    if engine not in ENGINES:
        raise InputError("--engine", f"must be one of {', '.join(ENGINES)}, got {engine!r}")
    if engine == "dask":
        from mcbat.dask_engine import DaskEngine

        return DaskEngine(scheduler=scheduler, workers=workers, threads=threads)
    for flag, value in (("--scheduler", scheduler), ("--workers", workers)):
        if value is not None:
            raise InputError(flag, "only with --engine dask")
    if threads is not None:
        threads = _positive_int(threads, "--threads")
        if threads > numba.config.NUMBA_NUM_THREADS:
            raise InputError("--threads", f"at most {numba.config.NUMBA_NUM_THREADS} on this "
                             f"machine, got {threads}")
        numba.set_num_threads(threads)
    return _LocalEngine()


@contextlib.contextmanager
def _out_errors(display):
    """An unwritable output location (or an unusable URL) is a clear error about
    ``--out``."""
    try:
        yield
    except OSError as err:
        raise InputError("--out", f"cannot write: {_reason(err)}", str(display)) from None
    except InputError as err:
        if err.field is not None:
            raise
        raise InputError("--out", err.message, str(display)) from None


def _reason(err: OSError) -> str:
    return os.strerror(err.errno) if err.errno else str(err)


def _finish(pending, out):
    """Wait for a chunk write; a full or unwritable disk is a clear error, not a crash."""
    try:
        pending.result()
    except OSError as err:
        raise write_error(err, out) from None


def write_error(err: OSError, out) -> InputError:
    """The error for a chunk file that could not be written."""
    return InputError("--out", f"cannot write a chunk file: {_reason(err)}; complete chunk "
                      "files are kept, free space (or fix permissions) and rerun to resume",
                      str(out))
