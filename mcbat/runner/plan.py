"""The plan of a run, and the one step every engine executes: :func:`run_chunk`.

A run's rows are split into chunks. :func:`plan_run` fixes everything the chunks share (a
:class:`ChunkJob`: where, how many, the seed, the hash of the config) and the dataset's
manifest; :func:`prepare_directory` checks and prepares the output; :func:`run_chunk`
draws one chunk's inputs (deterministic in the sample index), solves them with the
parallel kernel and writes its Parquet file atomically. The engines
(:mod:`mcbat.runner.engines`) only decide where :func:`run_chunk` runs.

Resumption: the manifest records a hash of everything that determines the data (study
config, seed, sample count). A rerun with the same hash keeps every complete chunk file and
computes only the missing ones; a different hash is refused unless the caller asks to
overwrite.

Errors name the Python parameters (``out``, ``samples``...); the CLI maps them to flags.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import socket
from dataclasses import dataclass
from pathlib import Path

import numba
import numpy as np

from mcbat.bodies.presets import ball_preset, bat_preset
from mcbat.checks import positive_int
from mcbat.core import status as st
from mcbat.core.batch import INPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE
from mcbat.core.flight import allocate_flight_outputs, fly_batch, pack_params
from mcbat.core.swing import GAME_OUTPUT_FIELDS, allocate_game_outputs, solve_game_batch
from mcbat.dataset import chunks, storage
from mcbat.dataset.check import chunk_mismatch
from mcbat.dataset.load import units_of
from mcbat.dataset.lock import LOCK_NAME
from mcbat.dataset.schema import (
    COLUMNS,
    FLIGHT_COLUMNS,
    GAME_COLUMNS,
    MEASURED_SUFFIX,
    PITCH_SOURCE_COLUMNS,
    SCHEMA_VERSION,
    UNITS,
)
from mcbat.dataset.summary import (
    STATE,
    SUMMARY,
    check_summary_size,
    quantile_name,
    summarise,
)
from mcbat.errors import InputError
from mcbat.study.output import OutputSpec, SummarySpec

__all__ = ["DEFAULT_CHUNK_SIZE", "ChunkJob", "ChunkSummary", "chunks_to_compute",
           "dataset_columns", "dataset_hash", "plan_run", "positive_int", "prepare_directory",
           "remove_temporary_files", "run_chunk", "set_threads", "summary_metadata",
           "warm_kernel", "write_error"]

#: Rows per chunk by default: 2**17, two LHS blocks (LHS_BLOCK = 65,536), so that a chunk of an
#: LHS study draws no design it uses only in part; ~50 MB of rows with every column. Its
#: arrays (~30 MB each) stay under glibc's mmap threshold, so the heap reuses them from chunk
#: to chunk: 2**18 rows took fresh pages (page faults) for every chunk, and ran summary-only
#: scans ~5 % slower.
DEFAULT_CHUNK_SIZE = 131_072


def set_threads(threads):
    """Validate ``threads`` (None: leave numba's setting) and give numba that many kernel
    threads; returns it."""
    if threads is not None:
        threads = positive_int(threads, "threads")
        if threads > numba.config.NUMBA_NUM_THREADS:
            raise InputError("threads", f"at most {numba.config.NUMBA_NUM_THREADS} on "
                             f"this machine, got {threads}")
        numba.set_num_threads(threads)
    return threads


def dataset_hash(study_config: dict, seed: int, samples: int,
                 summary_only: bool = False) -> str:
    """Hash of everything that determines what a dataset holds on disk: the rows (study
    config with its ``[output]`` columns and precision, seed, sample count) and whether
    they are stored at all (``summary_only``; in the hash only when set, so the datasets
    that store their rows keep their hashes)."""
    payload = {"schema": SCHEMA_VERSION, "study": study_config, "seed": seed,
               "samples": samples}
    if summary_only:
        payload["summary_only"] = True
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()


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
    output : mcbat.study.output.OutputSpec
        The columns written and their precision (``[output]``).
    summary : mcbat.study.output.SummarySpec or None
        The binned statistics each chunk contributes (``[summary]``), names checked and
        bounds in the columns' stored units.
    summary_only : bool
        Compute the summary without writing the rows.
    """

    out: str
    samples: int
    seed: int
    chunk_size: int
    config_hash: str
    metadata: dict
    output: OutputSpec = OutputSpec()
    summary: SummarySpec | None = None
    summary_only: bool = False

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
        return storage.join(self.out, chunks.chunk_name(index))


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
    file : dict or None
        The chunk file's manifest record (``{"rows", "bytes", "crc32"}``,
        :func:`mcbat.dataset.chunks.write_chunk`) once it is written; None while the
        local engine's writer thread still writes it, and in a summary-only run.
    partial : mcbat.core.binned_stats.SummaryPartial or None
        The chunk's share of the ``[summary]`` statistics.
    """

    index: int
    rows: int
    status_counts: tuple
    threads: int
    worker: str
    file: dict | None = None
    partial: object = None


def plan_run(study, out, samples: int, seed: int, chunk_size: int, *,
             summary_only: bool = False) -> tuple[ChunkJob, dict]:
    """The :class:`ChunkJob` and the dataset manifest of a run (validated arguments).

    A local ``out`` becomes absolute in the job: workers may run in another working
    directory, or on another host where the same path names the same shared storage.
    The ``[output]`` and ``[summary]`` column names are checked against the dataset's
    columns here (the study does not know the schema).
    """
    display = storage.location(out)
    where = display if not isinstance(display, Path) else Path(os.path.abspath(display))
    names = dataset_columns(study)
    output = study.output
    for name in output.columns or ():
        if name not in names:
            raise InputError(study.output_field, f"{name!r} is not a column of this "
                             "study's dataset (see mcbat.dataset.schema)")
    summary = study.summary_spec(units_of(names)) if study.summary is not None else None
    if summary_only and summary is None:
        raise InputError("summary_only", "needs a [summary] section in the study (what to "
                         "bin and which columns to summarise)")
    if summary is not None:
        check_summary_size(summary)
    config = study.config()
    config_hash = dataset_hash(config, seed, samples, bool(summary_only))
    n_chunks = -(-samples // chunk_size)
    manifest = {"schema": SCHEMA_VERSION, "config_hash": config_hash, "seed": seed,
                "samples": samples, "chunk_size": chunk_size, "chunks": n_chunks,
                "study": config, "study_name": study.name, "study_toml": study.source_text,
                "summary_only": bool(summary_only), "files": {}}
    metadata = {"config_hash": config_hash, "seed": seed, "samples": samples,
                "chunk_size": chunk_size, "study": config, "study_toml": study.source_text,
                "units": UNITS, "versions": chunks.package_versions(),
                "status_codes": st.STATUS_NAMES, "end_state_codes": st.END_STATE_NAMES,
                "schema": SCHEMA_VERSION}
    job = ChunkJob(str(where), samples, seed, chunk_size, config_hash, metadata, output,
                   summary, bool(summary_only))
    return job, manifest


def summary_metadata(job: ChunkJob) -> dict:
    """The metadata of a run's ``_summary.parquet``: the dataset's identity, the
    ``[summary]`` section and the unit of every column of the table."""
    spec = job.summary
    stored = units_of(spec.columns)
    units = {"count": "1"}
    for axis in spec.by:
        units[f"{axis.name}_low"] = units[f"{axis.name}_high"] = axis.unit
    for name in spec.columns:
        units[f"{name}_count"] = "1"
        for stat in ("mean", "std", "min", "max"):
            units[f"{name}_{stat}"] = stored.get(name)
        for q in spec.quantiles:
            units[quantile_name(name, q)] = stored.get(name)
    meta = job.metadata
    return {"config_hash": job.config_hash, "seed": job.seed, "samples": job.samples,
            "study": meta["study"], "study_toml": meta.get("study_toml"),
            "schema": SCHEMA_VERSION, "versions": meta.get("versions"), "units": units}


def dataset_columns(study) -> list:
    """The columns of ``study``'s dataset, in file order (before an ``[output]``
    selection)."""
    if getattr(study, "kind", "impact") == "game":
        return (list(GAME_COLUMNS) + (list(FLIGHT_COLUMNS) if study.flight is not None
                                      else [])
                + (list(PITCH_SOURCE_COLUMNS) if study.pitches is not None else []))
    return list(COLUMNS) + [f"{name}{MEASURED_SUFFIX}" for name in study.noise]


def prepare_directory(out, manifest: dict, chunk_size: int, overwrite: bool, *,
                      check_only: bool = False) -> dict | None:
    """Create ``out`` or check that it holds this very dataset; never lose foreign data.

    With ``check_only`` nothing is written: only the checks that can refuse the run.

    Returns
    -------
    dict or None
        The manifest now on disk (None with ``check_only``): ``manifest`` itself, or, when
        ``out`` already holds this dataset, its manifest, with the records of the chunks
        written so far and the study text it was first run with.

    Raises
    ------
    InputError
        Naming ``out``: a file, a directory that is not an mcbat dataset, or a dataset of
        another config (unless ``overwrite``) or holding files mcbat did not write.
    """
    kind = storage.entry_type(out)
    if kind == "file":
        raise InputError("out", "exists and is not a directory", str(out))
    # The lock, and the temporary files of a run killed before its first manifest was in
    # place (they are removed below), do not make a directory a foreign one.
    entries = {name: what for name, what in
               (storage.list_entries(out) if kind == "dir" else {}).items()
               if name != LOCK_NAME and not _leftover(name)}
    names = list(entries)
    existing = None
    if names:
        existing = chunks.read_manifest(out)
        if not isinstance(existing, dict):
            raise InputError("out", "is not empty and is not an mcbat dataset; choose "
                             "another directory", str(out))
        same = existing.get("config_hash") == manifest["config_hash"]
        # Nothing a run did not write is ever deleted: an overwrite refuses it, and so does a
        # resume when a Parquet reader of the directory would read it as rows.
        foreign = [name for name in names if not _ours(name, entries[name])]
        if not same or existing.get("chunk_size") != chunk_size:
            if not overwrite:
                what = (f"dataset schema version {existing.get('schema')} (this version "
                        f"of mcbat writes version {manifest['schema']})"
                        if existing.get("schema") != manifest["schema"] else
                        "a different study config, seed or sample count (or rows "
                        "stored where this run is --summary-only, or the reverse)"
                        if not same else
                        f"chunk size {existing.get('chunk_size')}")
                raise InputError("out", f"holds a dataset written with {what}; "
                                 "pass {overwrite} to replace it, or choose another "
                                 "directory", str(out), mentions={"overwrite": True})
            if foreign:
                raise InputError("out", f"holds files mcbat did not write "
                                 f"({foreign[0]!r}); refusing to overwrite", str(out))
            if check_only:
                return None
            for name in names:
                storage.remove(out, name)
            existing = None
        else:
            visible = [name for name in foreign if chunks.is_reader_visible(name)]
            visible += _foreign_strays(out, manifest)
            if visible:
                raise InputError("out", f"holds {visible[0]!r}, which mcbat did not write "
                                 "and which Parquet readers of the directory would read as "
                                 "rows; move it out of the directory and rerun", str(out))
    if check_only:
        return None
    storage.make_dirs(out)
    # Leftover temporary files of a killed run are never trusted.
    remove_temporary_files(out)
    # The same dataset: keep its chunk records and the study text it was started with (an
    # edit of the study's comments does not change the data, nor the files' metadata). A
    # manifest without usable records (an older mcbat's) keeps none: every chunk is then
    # recomputed and recorded, which upgrades it.
    if existing is not None:
        files = existing.get("files")
        text = existing.get("study_toml")
        kept = {"files": files if isinstance(files, dict) else {},
                "study_toml": text if isinstance(text, str) else manifest.get("study_toml"),
                "summary": existing.get("summary")}
    else:
        kept = {}
    if not isinstance(kept.get("summary"), dict):
        kept.pop("summary", None)
    on_disk = {**manifest, **kept}
    if existing != on_disk:
        chunks.write_manifest(out, on_disk)
    return on_disk


def _foreign_strays(out, manifest) -> list:
    """Chunk files beyond the dataset's last chunk whose footer is not of this dataset (a
    resume removes only copies of its own chunks)."""
    found = []
    for index, path in sorted(chunks.chunk_files(out).items()):
        if index >= manifest["chunks"] and not _footer_is_ours(path, manifest["config_hash"]):
            found.append(chunks.chunk_name(index))
    return found


def _footer_is_ours(path, config_hash) -> bool:
    try:
        info = json.loads(chunks.read_metadata(path).metadata[chunks.METADATA_KEY])
    except Exception:  # noqa: BLE001 - any unreadable footer is not ours
        return False
    return isinstance(info, dict) and info.get("config_hash") == config_hash


def _ours(name: str, kind: str = "file") -> bool:
    """True for a file a run writes in a dataset directory (a directory never is)."""
    if kind != "file":
        return False
    if name in (chunks.MANIFEST, SUMMARY, STATE) or chunks.chunk_index(name) is not None:
        return True
    return chunks.is_temporary_chunk_name(name) or any(
        name.startswith(f".{ours}.") and storage.is_temporary_name(name)
        for ours in (chunks.MANIFEST, SUMMARY, STATE))


def _leftover(name: str) -> bool:
    """A temporary file a killed run of ours left behind (never trusted, removed)."""
    return storage.is_temporary_name(name) and _ours(name)


def chunks_to_compute(out, job: ChunkJob, records: dict) -> tuple[list, list, list]:
    """Which chunks a run computes: ``(todo, redone, stray)``.

    A chunk is kept only if its file matches its manifest record (size and CRC-32 of the
    bytes, :func:`mcbat.dataset.chunks.verify_chunk`). ``redone`` lists ``(index, reason)``
    for the files that exist but are not kept (changed, corrupted, or written by a run
    killed before it recorded them): they are recomputed, and the run says so. ``stray``
    lists the names of chunk files beyond the dataset's last chunk (copies): the run
    removes them, and says so.
    """
    present = chunks.chunk_files(out)
    todo, redone = [], []
    identity = {"config_hash": job.config_hash}
    for k in range(job.chunks):
        name = chunks.chunk_name(k)
        record = records.get(name)
        if k not in present:
            todo.append(k)
            continue
        # The bytes against the record, and the footer against this chunk of this dataset:
        # a chunk copied in with its record from another dataset (or from another index)
        # matches its record but not its place.
        reason = ("not recorded in the manifest" if not isinstance(record, dict) else
                  chunk_mismatch(present[k], k, job.rows(k), job.chunk_size, identity,
                                 record, checksums=True))
        if reason is None and record.get("rows") != job.rows(k):
            reason = f"{record.get('rows')} rows recorded, {job.rows(k)} expected"
        if reason is not None:
            todo.append(k)
            redone.append((k, reason))
    stray = [chunks.chunk_name(k) for k in sorted(present) if k >= job.chunks]
    return todo, redone, stray


def remove_temporary_files(out) -> int:
    """Delete the temporary files a killed writer left in ``out``; returns how many.
    Only safe when no writer of this dataset is running."""
    removed = 0
    for name in storage.list_names(out):
        if _leftover(name):
            storage.remove(out, name, missing_ok=True)
            removed += 1
    return removed


def write_columns(table_args, path, compression="none") -> dict:
    """Build a chunk's table from its columns and write it atomically (see
    :func:`run_chunk`); returns its manifest record."""
    return chunks.write_chunk(chunks.to_table(*table_args), path, compression)


def run_chunk(study, job: ChunkJob, index: int, *, write=None,
              solve_lock=None) -> ChunkSummary:
    """Compute chunk ``index`` of a run: write its Parquet file atomically (unless the run
    is summary-only) and compute its share of the ``[summary]`` statistics.

    The chunk's inputs are drawn from ``(seed, sample index)`` alone
    (:meth:`mcbat.study.Study.sample`), so the file is the same wherever and however
    often it is computed: a rerun overwrites it with identical content.

    Parameters
    ----------
    study : mcbat.study.Study
        The validated study (its solver settings are used).
    job : ChunkJob
        The run's output location, sample count, seed, chunk size, metadata, columns and
        summary.
    index : int
        The chunk.
    write : callable, optional
        ``write(write_columns, table_args, path, compression)`` writes the file and
        returns its record. Default: write it now, before returning. The local engine
        hands it to its writer thread instead (and returns None: the record comes with the
        write's result).
    solve_lock : context manager, optional
        Held while the chunk is sampled and solved (the Dask engine serialises kernel calls
        of a worker's threads with it).

    Returns
    -------
    ChunkSummary
    """
    start, stop = job.bounds(index)
    solve = _solve_game_chunk if getattr(study, "kind", "impact") == "game" else _solve_chunk
    with solve_lock if solve_lock is not None else contextlib.nullcontext():
        threads = numba.get_num_threads()
        names, cols = solve(study, start, stop, job.seed, _derived_needed(job))
        partial = None if job.summary is None else summarise(job.summary, cols)
    counts = np.bincount(cols["status"], minlength=len(st.STATUS_NAMES))
    record = None
    if not job.summary_only:
        table_args = (names, cols, start, index, job.output, job.metadata)
        record = (write or _write_now)(write_columns, table_args, job.path(index),
                                       job.output.compression)
    return ChunkSummary(index, stop - start, tuple(int(c) for c in counts), threads,
                        f"{socket.gethostname()}:{os.getpid()}", record, partial)


def _derived_needed(job: ChunkJob):
    """The derived columns a chunk must compute: a summary-only run stores no rows, so it
    needs only those its ``[summary]`` reads (None: every one)."""
    if not job.summary_only:
        return None
    return {*job.summary.columns, *(axis.name for axis in job.summary.by)}


def _solve_chunk(study, start, stop, seed, derived=None):
    """Sample and solve an impact chunk; ``(names, cols)`` of
    :func:`mcbat.dataset.chunks.impact_columns` (``derived``: as there)."""
    solver = study.solver
    columns = study.sample(start, stop, seed)
    inputs = study_inputs(columns)
    out_arr, status, end_state = allocate_outputs(stop - start)
    solve_batch(inputs, solver["steps"], solver["tolerance"], solver["max_steps"], out_arr,
                status, end_state)
    barrel = study.bat.cm_from_barrel_end
    extra = {"impact_parameter": columns["impact_parameter"],
             "from_barrel_end": (np.full(stop - start, np.nan) if barrel is None
                                 else barrel - columns["axial"])}
    return chunks.impact_columns(inputs, out_arr, status, end_state, extra,
                                 study.measurement_noise(start, stop, seed), derived)


def study_inputs(columns) -> np.ndarray:
    """The kernel's input array from :meth:`mcbat.study.Study.sample`'s columns: the first
    rows of the array they are views of (no copy), else a stacked copy."""
    n_fields = len(INPUT_FIELDS)
    base = columns[INPUT_FIELDS[0]].base
    if (isinstance(base, np.ndarray) and base.ndim == 2 and base.dtype == np.float64
            and base.shape[0] >= n_fields and base.flags.c_contiguous
            and all(columns[name].ctypes.data == base[i].ctypes.data
                    and columns[name].shape == base[i].shape
                    for i, name in enumerate(INPUT_FIELDS))):
        return base[:n_fields]
    return np.stack([np.asarray(columns[name], np.float64) for name in INPUT_FIELDS])


def _solve_game_chunk(study, start, stop, seed, derived=None):
    """Sample and solve a game chunk (and fly it, with ``[flight]``); ``(names, cols)`` of
    :func:`mcbat.dataset.chunks.game_columns` (``derived``: as there)."""
    solver = study.solver
    game_inputs = study.sample_inputs(start, stop, seed)  # rows: GAME_INPUT_FIELDS
    frame, out_arr, game_out, status, end_state = allocate_game_outputs(stop - start)
    solve_game_batch(game_inputs, solver["steps"], solver["tolerance"], solver["max_steps"],
                     frame, out_arr, game_out, status, end_state)
    flight = None if study.flight is None else _fly(study, game_out)
    return chunks.game_columns(game_inputs, frame, out_arr, game_out, status, end_state,
                               flight, derived, study.pitch_identifiers(start, stop, seed))


def _fly(study, game_out):
    """The flight of a game chunk's batted balls (``[flight]``): ``(out, status)`` of
    :func:`mcbat.core.flight.fly_batch`."""
    row = {name: i for i, name in enumerate(GAME_OUTPUT_FIELDS)}
    v = np.stack([game_out[row[f"field_ball_v{c}"]] for c in "xyz"])
    w = np.stack([game_out[row[f"field_ball_w{c}"]] for c in "xyz"])
    n = v.shape[1]
    start = np.repeat(np.asarray(study.flight.start, np.float64)[:, None], n, axis=1)
    out, status = allocate_flight_outputs(n)
    fly_batch(pack_params(study.flight.params(study.ball.mass, study.ball.radius)), start, v,
              w, out, status)
    return out, status


def _write_now(function, *args):
    return function(*args)


def warm_kernel() -> None:
    """Load (or compile) the batch kernel by solving one impact: a worker does it once,
    before its first chunk."""
    ball, bat = ball_preset("baseball"), bat_preset("cross_nathan_2006")
    row = {name: 0.0 for name in INPUT_FIELDS}
    row.update(ball_mass=ball.mass, ball_radius=ball.radius,
               ball_inertia_factor=ball.inertia_factor, bat_mass=bat.mass,
               bat_transverse_inertia=bat.transverse_inertia,
               bat_axial_inertia=bat.axial_inertia, axial=0.1, angle=0.01,
               bat_radius=bat.radius, ball_vx_in=-4.0, mu=0.5, e=0.8)
    inputs = np.array([[row[name]] for name in INPUT_FIELDS], np.float64)
    out_arr, status, end_state = allocate_outputs(1)
    solve_batch(inputs, DEFAULT_STEPS, DEFAULT_TOLERANCE, DEFAULT_MAX_STEPS, out_arr, status,
                end_state)


def write_error(err: OSError, out) -> InputError:
    """The error for a chunk file that could not be written (names ``out``)."""
    reason = os.strerror(err.errno) if err.errno else str(err)
    return InputError("out", f"cannot write a chunk file: {reason}; complete chunk "
                      "files are kept, free space (or fix permissions) and rerun to resume",
                      str(out))
