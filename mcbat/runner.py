"""Run a study: sample -> batch kernel -> Parquet chunks, resumable.

The flow is one-way: the validated study draws the inputs of each chunk (deterministic in
the sample index), the parallel kernel solves them, and a writer thread turns the
struct-of-arrays into a Parquet file while the next chunk is being solved.

Resumption: the dataset manifest records a hash of everything that determines the data
(study config, seed, sample count). A rerun with the same hash keeps every complete chunk
file and computes only the missing ones; a different hash is refused unless the user asks
to overwrite. A re-run of a finished study changes nothing.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
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


def _prepare_directory(out: Path, manifest: dict, chunk_size: int, overwrite: bool) -> None:
    """Create ``out`` or check that it holds this very dataset; never lose foreign data."""
    if out.exists() and not out.is_dir():
        raise InputError("--out", "exists and is not a directory", str(out))
    if out.is_dir() and any(out.iterdir()):
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
            foreign = [p.name for p in out.iterdir()
                       if p.name != ds.MANIFEST and not ds._CHUNK_RE.match(p.name)
                       and not p.name.startswith(".chunk-")]
            if foreign:
                raise InputError("--out", f"holds files mcbat did not write "
                                 f"({foreign[0]!r}); refusing to overwrite", str(out))
            for path in out.iterdir():
                path.unlink() if path.is_file() else shutil.rmtree(path)
    out.mkdir(parents=True, exist_ok=True)
    # Leftover temporary files of a killed run are never trusted.
    for path in out.glob(".chunk-*.tmp"):
        path.unlink(missing_ok=True)
    if ds.read_manifest(out) != manifest:
        ds.write_json_atomic(manifest, out / ds.MANIFEST)


def run_study(study, out, *, samples=None, seed=None, threads=None, chunk_size=None,
              overwrite=False, progress=True) -> RunSummary:
    """Run ``study`` into the dataset directory ``out`` (resuming if possible).

    Parameters
    ----------
    study : mcbat.study.Study
        A validated study.
    out : str or Path
        Dataset directory.
    samples, seed, chunk_size : int, optional
        Override the study's defaults.
    threads : int, optional
        Numba threads for the batch kernel (default: all).
    overwrite : bool
        Replace an existing dataset of a different config.
    progress : bool
        Show a tqdm progress bar (impacts per second) on stderr.
    """
    import numba

    samples = _positive_int(study.samples if samples is None else samples, "--samples")
    seed = study.seed if seed is None else seed
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError("--seed", f"must be an integer >= 0, got {seed!r}")
    if chunk_size is None:
        chunk_size = getattr(study, "chunk_size", None) or DEFAULT_CHUNK_SIZE
    chunk_size = _positive_int(chunk_size, "--chunk-size")
    if threads is not None:
        threads = _positive_int(threads, "--threads")
        if threads > numba.config.NUMBA_NUM_THREADS:
            raise InputError("--threads", f"at most {numba.config.NUMBA_NUM_THREADS} on this "
                             f"machine, got {threads}")
        numba.set_num_threads(threads)
    out = Path(out)
    solver = study.solver
    config = study.config()
    config_hash = dataset_hash(config, int(seed), samples)
    n_chunks = -(-samples // chunk_size)
    manifest = {"schema": ds.SCHEMA_VERSION, "config_hash": config_hash, "seed": int(seed),
                "samples": samples, "chunk_size": chunk_size, "chunks": n_chunks,
                "study": config, "study_name": study.name}
    try:
        _prepare_directory(out, manifest, chunk_size, overwrite)
    except OSError as err:
        reason = os.strerror(err.errno) if err.errno else str(err)
        raise InputError("--out", f"cannot write: {reason}", str(out)) from None

    metadata = {"config_hash": config_hash, "seed": int(seed), "samples": samples,
                "chunk_size": chunk_size, "study": config, "study_toml": study.source_text,
                "units": ds.UNITS, "versions": ds.package_versions(),
                "status_codes": st.STATUS_NAMES, "end_state_codes": st.END_STATE_NAMES,
                "schema": ds.SCHEMA_VERSION}
    existing = ds.chunk_files(out)
    todo = []
    for k in range(n_chunks):
        rows = min(chunk_size, samples - k * chunk_size)
        path = existing.get(k)
        if path is not None and ds.chunk_is_complete(path, rows, config_hash):
            continue
        todo.append(k)
    kept = n_chunks - len(todo)

    bar = None
    if progress and todo:
        from tqdm import tqdm

        total = sum(min(chunk_size, samples - k * chunk_size) for k in todo)
        bar = tqdm(total=total, unit=" impacts", unit_scale=True, file=sys.stderr,
                   desc=f"{study.name}", dynamic_ncols=True, smoothing=0.1)
    counts = np.zeros(len(st.STATUS_NAMES), np.int64)
    t0 = time.perf_counter()
    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="mcbat-writer") as writer:
        pending = None
        for k in todo:
            start = k * chunk_size
            stop = min(samples, start + chunk_size)
            columns = study.sample(start, stop, int(seed))
            inputs = np.stack([np.asarray(columns[name], np.float64) for name in INPUT_FIELDS])
            out_arr, status, end_state = allocate_outputs(stop - start)
            solve_batch(inputs, solver["steps"], solver["tolerance"], solver["max_steps"],
                        out_arr, status, end_state)
            counts += np.bincount(status, minlength=len(counts))
            if pending is not None:
                _finish(pending, out)  # at most one chunk in flight: bounded memory
            table_args = (start, k, inputs, out_arr, status, end_state,
                          {"impact_parameter": np.asarray(columns["impact_parameter"])},
                          metadata, study.measurement_noise(start, stop, int(seed)))
            pending = writer.submit(_write_chunk, table_args, out / ds.chunk_name(k))
            if bar is not None:
                bar.update(stop - start)
        if pending is not None:
            _finish(pending, out)
    seconds = time.perf_counter() - t0
    if bar is not None:
        bar.close()
    status_counts = ({st.STATUS_NAMES[i]: int(c) for i, c in enumerate(counts) if c}
                     if todo else {})
    return RunSummary(out, samples, n_chunks, len(todo), kept, seconds, status_counts)


def _finish(pending, out):
    """Wait for a chunk write; a full or unwritable disk is a clear error, not a crash."""
    try:
        pending.result()
    except OSError as err:
        reason = os.strerror(err.errno) if err.errno else str(err)
        raise InputError("--out", f"cannot write a chunk file: {reason}; complete chunk "
                         "files are kept, free space (or fix permissions) and rerun to "
                         "resume", str(out)) from None


def _write_chunk(table_args, path):
    ds.write_atomic(ds.build_table(*table_args), path)
