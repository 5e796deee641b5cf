"""Run a study into a dataset directory: ``run_study``.

The flow is one-way: the validated study draws the inputs of each chunk, the parallel
kernel solves them, and the struct-of-arrays becomes one Parquet file per chunk
(``mcbat.runner.plan``). This module validates the options, prepares the directory,
picks the chunks still to compute (resume), hands them to an engine
(``mcbat.runner.engines``) and reports what happened.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from mcbat.core import status as st
from mcbat.dataset import chunks, storage
from mcbat.dataset.lock import dataset_lock
from mcbat.dataset.summary import SUMMARY, SummaryState, shares, write_summary
from mcbat.errors import InputError
from mcbat.runner.batted_balls import (
    BATTED_BALL_COLUMNS,
    batted_ball_lines,
    batted_ball_summary,
)
from mcbat.runner.compiling import announce_compiling, kernels_for
from mcbat.runner.engines.dask import DaskEngine
from mcbat.runner.engines.local import LocalEngine
from mcbat.runner.memory import reuse_freed_memory
from mcbat.runner.pitches import load_pitches
from mcbat.runner.plan import (
    DEFAULT_CHUNK_SIZE,
    chunks_to_compute,
    plan_run,
    positive_int,
    prepare_directory,
    summary_metadata,
)
from mcbat.study import units as u

__all__ = ["ENGINES", "RunSummary", "make_engine", "run_study"]

ENGINES = ("local", "dask")
#: Most chunk files of one dataset: the manifest records each one, and a run's plan and
#: resume check list them all.
MAX_CHUNKS = 100_000
#: Largest seed: a study file's ``study.seed`` has the same bound.
MAX_SEED = 2**63 - 1


@dataclass
class RunSummary:
    """What a run did.

    Attributes
    ----------
    directory : Path or str
        The dataset directory (or its URL).
    rows : int
        Rows of the dataset.
    chunks_total, chunks_computed, chunks_kept : int
        Chunk files in all, computed by this run, and kept from an earlier one.
    seconds : float
        Time spent computing, from the first chunk with the kernel loaded.
    status_counts : dict
        Computed rows per status name.
    engine_note : str or None
        Where the chunks were computed (Dask engine).
    batted_ball : dict or None
        Game studies: ``batted_ball_summary``.
    redone : list of (int, str)
        Chunk files found on disk but recomputed, with the reason (changed, corrupted, or
        not recorded by a killed run).
    removed : list of str
        Stray chunk files (beyond the dataset's last chunk) the run removed.
    summary : dict or None
        With ``[summary]``: ``{"path", "bins", "outside", "summary_only",
        "share_above"}`` (the last: ``mcbat.dataset.summary.shares``, over every bin).
    pitches : dict or None
        With ``[pitches]``: the file and its rows selected, left out (reason -> count) and
        drawn from (the ``pitches`` entry of the study's config).
    """

    directory: Path | str
    rows: int
    chunks_total: int
    chunks_computed: int
    chunks_kept: int
    seconds: float
    status_counts: dict = field(default_factory=dict)
    engine_note: str | None = None
    batted_ball: dict | None = None
    redone: list = field(default_factory=list)
    removed: list = field(default_factory=list)
    summary: dict | None = None
    pitches: dict | None = None

    @property
    def rows_per_second(self) -> float:
        """Computed rows per second of the run."""
        computed_rows = self.rows * self.chunks_computed / max(self.chunks_total, 1)
        return computed_rows / self.seconds if self.seconds > 0 else float("nan")

    def lines(self) -> list[str]:
        """The run's closing report, one string per line."""
        failed = sum(v for k, v in self.status_counts.items() if k != "ok")
        out = [f"dataset: {self.directory}"]
        kept = f"{self.chunks_computed} computed, {self.chunks_kept} kept from before"
        if self.summary is not None and self.summary["summary_only"]:
            out.append(f"rows: {self.rows:,} in {self.chunks_total} chunk(s) ({kept}), "
                       "summarised only (no rows stored)")
        else:
            out.append(f"rows: {self.rows:,} in {self.chunks_total} chunk file(s) ({kept})")
        if self.summary is not None:
            out.append(f"summary: {self.summary['path']} ({self.summary['bins']:,} bins; "
                       f"{self.summary['outside']:,} rows outside every bin)")
            for share in self.summary.get("share_above", ()):
                out.append(_share_line(share))
        if self.pitches is not None:
            p = self.pitches
            left = "".join(f", {n:,} {reason}" for reason, n in p["excluded"].items())
            out.append(f"pitches: {p['drawn_from']:,} rows of {p['file']} drawn from "
                       f"({p['rows_in_file']:,} in the file, {p['selected']:,} selected by "
                       f"the filters{left}), about {self.rows / max(p['drawn_from'], 1):,.0f} "
                       "samples each")
            if "swing_plane_measured" in p:
                plane, rest = p["swing_plane_measured"], p["drawn_from"] - p["swing_plane_measured"]
                out.append(f"vertical bat angle from the measured swing plane on {plane:,} of "
                           f"those rows" + (f", [swing]'s on the other {rest:,}" if rest else ""))
            if "rows_moved" in p.get("player_levels", {}):
                out.append(_levels_line(p["player_levels"], p["drawn_from"]))
            if p.get("swing_shift"):
                out.append("what if: every drawn swing moved by " + ", ".join(
                    f"{key.split('.', 1)[1]} {_shift_text(key, value)}"
                    for key, value in p["swing_shift"].items()))
        for index, reason in self.redone:
            out.append(f"recomputed {chunks.chunk_name(index)}: {reason}")
        for name in self.removed:
            out.append(f"removed {name}: not part of this dataset (beyond its last chunk)")
        if self.chunks_computed:
            out.append(f"time: {self.seconds:.2f} s ({self.rows_per_second:,.0f} rows/s)")
        if self.engine_note:
            out.append(self.engine_note)
        if self.batted_ball:
            out.extend(batted_ball_lines(self.batted_ball))
        if self.status_counts:
            parts = ", ".join(f"{k}: {v:,}" for k, v in self.status_counts.items())
            out.append(f"status of computed rows: {parts}"
                       + (f"  <- {failed:,} failed rows are flagged in 'status'" if failed
                          else ""))
        return out

    def __repr__(self) -> str:
        return f"RunSummary({'; '.join(self.lines())})"


def _levels_line(levels, rows) -> str:
    """What ``[pitches.player_levels]`` found, for the run report."""
    players = " and ".join(f"{n:,} {key.split('_')[0][:-1]}{'s' if n != 1 else ''}"
                           for key, n in levels.items() if key.endswith("_with_level"))
    if "measured" in levels:
        return (f"player levels: none, {levels['measured']}; every row meets the league's "
                "contact")
    if not levels["rows_moved"]:
        return ("player levels: no player of the file has another game in it; every row "
                "meets the league's contact")
    low, high = levels["spread_range"]
    shift = [v / u.UNITS[u.LENGTH]["in"] for v in levels["undercut_shift_range"]]
    return (f"player levels, each from the player's other games in the file: {players} "
            f"with one; {levels['rows_moved']:,} of the {rows:,} rows met their players' "
            f"contact (spread along the bat {low:.2f}-{high:.2f} of the league's, undercut "
            f"{shift[0]:+.2f} to {shift[1]:+.2f} in)")


def _shift_text(key, value) -> str:
    """A ``[pitches.swing_shift]`` amount (SI) in Statcast's unit: ``+2.0 mph``."""
    if key == "swing.bat_speed":
        return f"{value / 0.44704:+.1f} mph"
    return f"{math.degrees(value):+.1f} deg"


def _share_line(share: dict) -> str:
    """``share above: hit_distance > 380 ft: 12.31 +- 0.52 % (1,234 of 10,021 values...)``."""
    unit = f" {share['unit']}" if share.get("unit") else ""
    head = f"share above: {share['column']} > {share['above']:g}{unit}: "
    if share["share"] is None:
        return head + "no values in the bins"
    return (head + f"{100 * share['share']:.2f} +- {100 * share['error']:.2f} % "
            f"({share['count']:,} of {share['n']:,} values in the bins)")


def make_engine(engine="local", threads=None, scheduler=None, workers=None):
    """Validate the engine options (before anything is written) and build the engine.

    Raises
    ------
    InputError
        Naming ``engine``, ``threads``, ``scheduler`` or ``workers``.
    """
    if engine not in ENGINES:
        raise InputError("engine", f"must be one of {', '.join(ENGINES)}, got {engine!r}")
    if engine == "dask":
        return DaskEngine(scheduler=scheduler, workers=workers, threads=threads)
    for name, value in (("scheduler", scheduler), ("workers", workers)):
        if value is not None:
            raise InputError(name, "only with {engine}", mentions={"engine": "dask"})
    return LocalEngine(threads)


def run_study(study, out, *, samples=None, seed=None, threads=None, chunk_size=None,
              overwrite=False, progress=True, engine="local", scheduler=None,
              workers=None, summary_only=False, tolerance=None) -> RunSummary:
    """Run ``study`` into the dataset directory ``out`` (resuming if possible).

    Parameters
    ----------
    study : mcbat.study.Study
        A validated study.
    out : str or Path
        Dataset directory: a local path, or a URL (see ``mcbat.dataset.storage``).
    samples, seed, chunk_size : int, optional
        Override the study's defaults.
    tolerance : float, optional
        Override the study's ``[solver] tolerance`` (the kernel's impulse error allowed per
        slip step, relative to ``I_scale``; ``0 < tolerance < 1``). It is part of the
        dataset's config: the manifest records it, and resuming a dataset with another
        tolerance is refused like any other change of config.
    threads : int, optional
        Numba threads for the batch kernel: of this process (``local``; default: all), or
        of each Dask worker (``dask``; see ``mcbat.runner.engines.dask.DaskEngine``).
    overwrite : bool
        Replace an existing dataset of a different config.
    progress : bool
        Show a progress bar (impacts per second): on stderr, or a widget in Jupyter.
    engine : {"local", "dask"}
        Where the chunks are computed. The data are identical either way.
    scheduler : str, optional
        ``dask``: address of a running Dask scheduler to join.
    workers : int, optional
        ``dask``: start a local cluster of this many worker processes (default: one per
        core, when no ``scheduler`` is given).
    summary_only : bool
        Compute the study's ``[summary]`` without storing the rows (read it with
        ``mcbat.load_summary``).

    Returns
    -------
    RunSummary

    Raises
    ------
    InputError
        A bad option or output location, named by its parameter; a ``[pitches]`` file
        that cannot be read or a filter that selects no row, named by its key; before
        anything is written.
    """
    if tolerance is not None:
        study = study.with_overrides(tolerance=tolerance)
    study = load_pitches(study)  # a [pitches] file: read, hashed and filtered first
    samples = positive_int(study.samples if samples is None else samples, "samples")
    seed = study.seed if seed is None else seed
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError("seed", f"must be an integer >= 0, got {seed!r}")
    if seed > MAX_SEED:
        raise InputError("seed", f"must be <= 2**63 - 1 = {MAX_SEED:,}, got {seed:,}")
    if chunk_size is None:
        chunk_size = getattr(study, "chunk_size", None) or DEFAULT_CHUNK_SIZE
    chunk_size = positive_int(chunk_size, "chunk_size")
    study.check_sample_count(samples, "samples")
    if -(-samples // chunk_size) > MAX_CHUNKS:
        raise InputError("chunk_size", f"{samples:,} samples in chunks of {chunk_size:,} make "
                         f"{-(-samples // chunk_size):,} chunk files, at most {MAX_CHUNKS:,}: "
                         "choose {chunk_size} or more",
                         mentions={"chunk_size": -(-samples // MAX_CHUNKS)})
    runner = make_engine(engine, threads, scheduler, workers)

    try:
        display = storage.location(out)
    except InputError as err:
        raise InputError("out", err.message, err.source) from None
    job, manifest = plan_run(study, display, samples, int(seed), chunk_size,
                             summary_only=summary_only)
    with _out_errors(display):
        # Everything that can refuse the run, before a cluster is started or joined.
        prepare_directory(display, manifest, chunk_size, overwrite, check_only=True)
    with dataset_lock(display), runner.connect(), reuse_freed_memory():
        # (the lock and the connection: refused before a cluster starts)
        with _out_errors(display):
            on_disk = prepare_directory(display, manifest, chunk_size, overwrite)
        try:
            todo, redone, stray, counts, summaries, seconds, state = _compute(
                study, job, display, on_disk, runner, progress)
        except BaseException:
            _forget_if_empty(display, on_disk)
            raise
        # The closing report reads the chunk files: still under the lock, so that a run
        # that takes the directory over next cannot remove them under it.
        batted = None
        if (getattr(study, "kind", "impact") == "game" and not job.summary_only
                and _stored(study, BATTED_BALL_COLUMNS)):
            with _out_errors(display):
                batted = batted_ball_summary(display, flight=study.flight is not None
                                             and _stored(study, ("hit_distance",
                                                                 "hang_time")))
    status_counts = ({st.STATUS_NAMES[i]: int(c) for i, c in enumerate(counts) if c}
                     if todo else {})
    summary = None if state is None else {
        "path": storage.join(display, SUMMARY), "bins": job.summary.n_bins,
        "outside": int(state.total.outside[0]), "summary_only": job.summary_only,
        "share_above": shares(job.summary, state)}
    return RunSummary(display, samples, job.chunks, len(todo), job.chunks - len(todo),
                      seconds, status_counts, runner.note(summaries) if todo else None,
                      batted, redone, stray, summary,
                      job.metadata["study"].get("pitches"))


def _compute(study, job, display, on_disk, runner, progress):
    """Pick the chunks to compute (resume), compute and record them; returns
    ``(todo, redone, stray, status counts, summaries, seconds, summary state)``."""
    with _out_errors(display):
        if job.summary_only:  # no rows: chunk files of an earlier run stay as they are
            todo, redone, stray = [], [], []
        else:
            todo, redone, stray = chunks_to_compute(display, job, on_disk["files"])
        for name in stray:
            storage.remove(display, name)
        state = None
        if job.summary is not None:
            state = SummaryState.resume(job.summary, display,
                                        (on_disk.get("summary") or {}).get("state"))
            # Chunks after the saved state are recomputed for their partials (their files,
            # if any, are rewritten with the same bytes).
            todo = sorted(set(todo) | set(range(state.merged, job.chunks)))
    job = replace(job, metadata={**job.metadata, "study_toml": on_disk["study_toml"]})
    if progress and todo:  # (a first run compiles for 20-30 s at 0 %: say so)
        announce_compiling(kernels_for(study))
    bar = _progress_bar(study.name, sum(job.rows(k) for k in todo)) \
        if progress and todo else None
    counts = np.zeros(len(st.STATUS_NAMES), np.int64)
    summaries = []
    if todo:
        runner.ready(study, job, display)
    recorder = _Recorder(display, on_disk, state)
    t0 = time.perf_counter()
    try:
        for summary in runner.run(study, job, todo, display):
            counts += summary.status_counts
            summaries.append(replace(summary, partial=None))  # (the state keeps the sums)
            recorder.add(summary)
            if bar is not None:
                bar.update(summary.rows)
    finally:
        seconds = time.perf_counter() - t0
        if bar is not None:
            bar.close()
        recorder.flush(final=True)
    missing = [] if job.summary_only else [
        k for k in range(job.chunks) if chunks.chunk_name(k) not in on_disk["files"]]
    if missing:  # an engine that did not deliver every chunk: never a silent hole
        raise RuntimeError(f"chunk {missing[0]} of {display} was not written "
                           f"({len(missing)} missing); rerun to complete the dataset")
    if state is not None:
        recorder.finish_summary(job)
    return todo, redone, stray, counts, summaries, seconds, state


def _forget_if_empty(out, on_disk: dict) -> None:
    """After a failed run that wrote no chunk (nor a summary state): remove its manifest,
    so that the directory does not block a corrected rerun ("holds a dataset of another
    config"). The lock then removes the directory if the run created it."""
    if on_disk["files"] or on_disk.get("summary") or chunks.chunk_files(out):
        return
    with contextlib.suppress(OSError):
        storage.remove(out, chunks.MANIFEST, missing_ok=True)


def _stored(study, names) -> bool:
    """True if the run stores every column of ``names`` (``[output] columns``)."""
    return study.output.columns is None or set(names) <= set(study.output.columns)


def _progress_bar(name: str, total: int):
    """A progress bar in impacts: a widget in Jupyter, text on stderr elsewhere."""
    from tqdm.auto import tqdm

    return tqdm(total=total, unit=" impacts", unit_scale=True, file=sys.stderr,
                desc=name, dynamic_ncols=True, smoothing=0.1)


class _Recorder:
    """Records written chunks in the manifest (rewritten atomically): from then on a chunk
    belongs to the dataset. At most one rewrite per ``INTERVAL`` seconds (a dataset of
    thousands of chunks would otherwise rewrite a growing manifest thousands of times), and
    a last one when the run ends, however it ends. A run killed in between loses the
    records of at most a second of chunks: a resume recomputes them.

    With ``[summary]`` it merges each chunk's partial into the run's
    ``mcbat.dataset.summary.SummaryState`` (in chunk order) and saves the state with
    the manifest, at most every ``STATE_INTERVAL`` seconds (it may be megabytes).
    """

    INTERVAL = 1.0
    STATE_INTERVAL = 10.0

    def __init__(self, out, manifest: dict, state=None):
        self.out, self.manifest, self.state = out, manifest, state
        self.dirty, self.last = False, -math.inf  # the first chunk is recorded at once
        self.state_saved = None if state is None else state.merged
        self.state_last = time.monotonic()

    def add(self, summary) -> None:
        if summary.file is not None:
            self.manifest["files"][chunks.chunk_name(summary.index)] = summary.file
            self.dirty = True
        if self.state is not None and summary.partial is not None:
            self.state.add(summary.index, summary.partial)
        if time.monotonic() - self.last >= self.INTERVAL:
            self.flush()

    def flush(self, final=False) -> None:
        state = self.state
        if state is not None and state.merged != self.state_saved and (
                final or time.monotonic() - self.state_last >= self.STATE_INTERVAL):
            with _out_errors(self.out):
                record = state.save(self.out)
            self.manifest.setdefault("summary", {})["state"] = record
            self.manifest["summary"].pop("table", None)
            self.state_saved, self.state_last, self.dirty = state.merged, time.monotonic(), True
        if self.dirty:
            with _out_errors(self.out):
                chunks.write_manifest(self.out, self.manifest)
            self.dirty, self.last = False, time.monotonic()

    def finish_summary(self, job) -> None:
        """Write ``_summary.parquet`` (all chunks merged) and record it."""
        record = self.manifest.get("summary") or {}
        table = record.get("table")
        if isinstance(table, dict) and _matches(storage.join(self.out, SUMMARY), table):
            return  # complete from before, and this run merged nothing new
        with _out_errors(self.out):
            written = write_summary(self.out, job.summary, self.state,
                                    summary_metadata(job))
        self.manifest.setdefault("summary", {})["table"] = written
        self.dirty = True
        self.flush()


def _matches(path, record: dict) -> bool:
    """Whether the file at ``path`` has the size and CRC-32 of its manifest record (a
    damaged file of the same size is rewritten, not kept)."""
    if storage.file_size(path) != record.get("bytes"):
        return False
    try:
        return chunks.checksum(storage.read_bytes(path)) == record.get("crc32")
    except OSError:
        return False


@contextlib.contextmanager
def _out_errors(display):
    """An unwritable output location (or an unusable URL) is a clear error about
    ``out``."""
    try:
        yield
    except OSError as err:
        reason = os.strerror(err.errno) if err.errno else str(err)
        raise InputError("out", f"cannot write: {reason}", str(display)) from None
    except InputError as err:
        if err.field is not None:
            raise
        raise InputError("out", err.message, str(display)) from None
