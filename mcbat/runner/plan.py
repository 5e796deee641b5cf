"""The plan of a run: its chunks, what they share, and the dataset's manifest.

A run's rows are split into chunks. ``plan_run`` fixes everything the chunks share (a
``mcbat.runner.job.ChunkJob``: where, how many, the seed, the hash of the config) and
the dataset's manifest; ``mcbat.runner.directory.prepare_directory`` checks and
prepares the output; ``mcbat.runner.chunk_run.run_chunk`` draws one chunk's inputs
(deterministic in the sample index), solves them with the parallel kernel and writes its
Parquet file atomically. The engines (``mcbat.runner.engines``) only decide where
``run_chunk`` runs. Those names are importable from here too.

Resumption: the manifest records a hash of everything that determines the data (study
config, seed, sample count). A rerun with the same hash keeps every complete chunk file and
computes only the missing ones; a different hash is refused unless the caller asks to
overwrite.

Errors name the Python parameters (``out``, ``samples``...); the CLI maps them to flags.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import numba

from mcbat.checks import positive_int
from mcbat.core import status as st
from mcbat.dataset import chunks, storage
from mcbat.dataset.load import units_of
from mcbat.dataset.schema import (
    COLUMNS,
    FLIGHT_COLUMNS,
    GAME_COLUMNS,
    MEASURED_SUFFIX,
    PITCH_SOURCE_COLUMNS,
    SCHEMA_VERSION,
    UNITS,
)
from mcbat.dataset.summary import check_summary_size, quantile_name
from mcbat.errors import InputError
from mcbat.runner.chunk_run import run_chunk, warm_kernel, write_error
from mcbat.runner.directory import chunks_to_compute, prepare_directory, remove_temporary_files
from mcbat.runner.job import ChunkJob, ChunkSummary

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


def plan_run(study, out, samples: int, seed: int, chunk_size: int, *,
             summary_only: bool = False) -> tuple[ChunkJob, dict]:
    """The ``ChunkJob`` and the dataset manifest of a run (validated arguments).

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
