"""Chunk files and the manifest of a dataset directory.

A dataset is a directory::

    DIR/_mcbat.json            manifest: config hash, seed, samples, chunk size, study,
                               and the record of every chunk written (rows, bytes, CRC-32)
    DIR/chunk-000000.parquet   rows [0, C)
    DIR/chunk-000001.parquet   rows [C, 2C) ...   (chunk-1000000.parquet: no digit limit)

Chunk files are written under a hidden temporary name and renamed into place
(:func:`mcbat.dataset.storage.write_atomic`), so a file with a final name is always
complete. Once a chunk file is in place, the run records it in the manifest (key
``files``: ``{name: {"rows", "bytes", "crc32"}}``, the CRC-32 of the file's bytes); only a
recorded chunk whose bytes match its record belongs to the dataset
(:mod:`mcbat.dataset.check`). Each file carries the schema-level metadata (key ``mcbat``):
units, the study config and its TOML text, seed, config hash and package versions. The
columns are those of :mod:`mcbat.dataset.schema`.
"""

from __future__ import annotations

import json
import platform
import re
import zlib
from importlib import metadata

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS
from mcbat.core.flight import FLIGHT_FIELDS
from mcbat.core.swing import GAME_INPUT_FIELDS, GAME_OUTPUT_FIELDS, bat_frame_columns
from mcbat.dataset import storage
from mcbat.dataset.schema import (
    COLUMNS,
    FLIGHT_COLUMNS,
    GAME_COLUMNS,
    MEASURED_SUFFIX,
    derive,
    derive_game,
)

__all__ = ["MANIFEST", "METADATA_KEY", "build_game_table", "build_table", "checksum",
           "chunk_files", "chunk_index", "chunk_is_complete", "chunk_name",
           "is_temporary_chunk_name", "package_versions", "read_manifest", "read_metadata",
           "read_table",
           "verify_chunk", "write_chunk", "write_manifest"]

MANIFEST = "_mcbat.json"
METADATA_KEY = b"mcbat"
_CHUNK_RE = re.compile(r"^chunk-(\d{6,})\.parquet$")


def chunk_name(index: int) -> str:
    """File name of chunk ``index``."""
    return f"chunk-{index:06d}.parquet"


def chunk_index(name: str) -> int | None:
    """The chunk index of a chunk file's name, or None for any other name."""
    match = _CHUNK_RE.match(name)
    if not match:
        return None
    index = int(match.group(1))
    # Only the canonical spelling: "chunk-0000001.parquet" is not chunk 1's file.
    return index if chunk_name(index) == name else None


def is_temporary_chunk_name(name: str) -> bool:
    """True for the temporary name of a chunk file being written."""
    return name.startswith(".chunk-") and storage.is_temporary_name(name)


def package_versions() -> dict:
    """Versions of Python and of the packages that determine the data (provenance)."""
    import numba
    import pandas
    import scipy

    return {"mcbat": metadata.version("mcbat"), "python": platform.python_version(),
            "numpy": np.__version__, "numba": numba.__version__, "scipy": scipy.__version__,
            "pandas": pandas.__version__, "pyarrow": pa.__version__}


_INT8_COLUMNS = ("status", "end_state", "flight_status")


def _arrow_arrays(names, cols, sample_id_start, chunk, n):
    """The Arrow arrays of columns ``names`` from ``cols`` (status codes as int8,
    ``rk4_steps`` as int32; ``sample_id`` and ``chunk`` generated)."""
    arrays = []
    for name in names:
        if name in _INT8_COLUMNS:
            arrays.append(pa.array(cols[name], pa.int8()))
        elif name == "rk4_steps":
            arrays.append(pa.array(np.nan_to_num(cols[name]).astype(np.int32)))
        elif name == "sample_id":
            arrays.append(pa.array(np.arange(sample_id_start, sample_id_start + n,
                                             dtype=np.int64)))
        elif name == "chunk":
            arrays.append(pa.array(np.full(n, chunk, np.int32)))
        else:
            arrays.append(pa.array(cols[name]))
    return arrays


def build_table(sample_id_start, chunk, inputs, out, status, end_state, extra_inputs,
                metadata, noise=None) -> pa.Table:
    """Assemble one chunk's table from the kernel's struct-of-arrays.

    Parameters
    ----------
    sample_id_start : int
        ``sample_id`` of the first row.
    chunk : int
        Chunk index.
    inputs : float64[len(INPUT_FIELDS), n]
        Kernel inputs.
    out, status, end_state
        Kernel outputs (see :func:`mcbat.core.batch.solve_batch`).
    extra_inputs : dict of str -> float64[n]
        Inputs not passed to the kernel (``impact_parameter``).
    metadata : dict or None
        JSON-serialisable dataset metadata stored in the schema.
    noise : dict of str -> float64[n], optional
        Simulated measurement errors: column ``<name>_measured`` = ``<name>`` + error,
        appended after the contract columns (the model value stays untouched).
    """
    n = inputs.shape[1]
    cols = {name: inputs[i] for i, name in enumerate(INPUT_FIELDS)}
    cols.update(extra_inputs)
    cols.update({name: out[i] for i, name in enumerate(OUTPUT_FIELDS)})
    derived = derive((cols["ball_vx"], cols["ball_vy"], cols["ball_vz"]),
                     (cols["ball_wx"], cols["ball_wy"], cols["ball_wz"]))
    arrays = _arrow_arrays(COLUMNS, {**cols, **derived, "status": status,
                                     "end_state": end_state}, sample_id_start, chunk, n)
    names = list(COLUMNS)
    for name, error in (noise or {}).items():
        value = derived[name] if name in derived else cols[name]
        arrays.append(pa.array(value + error))
        names.append(f"{name}{MEASURED_SUFFIX}")
    table = pa.Table.from_arrays(arrays, names=names)
    if metadata is None:
        return table
    return table.replace_schema_metadata(
        {METADATA_KEY: json.dumps(metadata, sort_keys=True).encode()})


_FT = 0.3048  # m per ft (Statcast reports distances in ft)


def build_game_table(sample_id_start, chunk, game_inputs, frame, out, game_out, status,
                     end_state, metadata, flight=None) -> pa.Table:
    """Assemble one chunk's table of a game study (:data:`~mcbat.dataset.schema.GAME_COLUMNS`)
    from the arrays of :func:`mcbat.core.swing.solve_game_batch`."""
    n = game_inputs.shape[1]
    cols = {name: game_inputs[i] for i, name in enumerate(GAME_INPUT_FIELDS)}
    cols.update(bat_frame_columns(game_inputs, frame))
    cols.update({name: game_out[i] for i, name in enumerate(GAME_OUTPUT_FIELDS)})
    cols.update({name: out[i] for i, name in enumerate(OUTPUT_FIELDS)})
    cols.update(derive((cols["ball_vx"], cols["ball_vy"], cols["ball_vz"]),
                       (cols["ball_wx"], cols["ball_wy"], cols["ball_wz"])))
    cols.update(derive_game(
        (cols["field_ball_vx"], cols["field_ball_vy"], cols["field_ball_vz"]),
        (cols["field_ball_wx"], cols["field_ball_wy"], cols["field_ball_wz"])))
    names = GAME_COLUMNS
    if flight is not None:  # (out, status) of mcbat.core.flight.fly_batch, SI
        flight_out, flight_status = flight
        row = {name: i for i, name in enumerate(FLIGHT_FIELDS)}
        for name in ("hit_distance", "landing_x", "landing_y", "apex"):
            cols[f"{name}_m"] = flight_out[row[name]]
            cols[name] = flight_out[row[name]] / _FT
        cols["hang_time"] = flight_out[row["hang_time"]]
        cols["flight_status"] = flight_status
        names = GAME_COLUMNS + FLIGHT_COLUMNS
    cols.update(status=status, end_state=end_state)
    arrays = _arrow_arrays(names, cols, sample_id_start, chunk, n)
    table = pa.Table.from_arrays(arrays, names=list(names))
    if metadata is None:
        return table
    return table.replace_schema_metadata(
        {METADATA_KEY: json.dumps(metadata, sort_keys=True).encode()})


def checksum(data) -> str:
    """CRC-32 of the bytes-like ``data``, as 8 hex digits. A checksum against accidents
    (bit rot, a truncated or overwritten file), fast enough to run on every chunk
    (~1 GB/s): not a defence against tampering."""
    return f"{zlib.crc32(data):08x}"


def write_chunk(table: pa.Table, path) -> dict:
    """Write a chunk's ``table`` to ``path`` (a local path or a URL), atomically.

    Returns
    -------
    dict
        The chunk's record for the manifest: ``{"rows", "bytes", "crc32"}``.
    """
    # Constant columns (most inputs of a typical study) cost nothing with dictionary + RLE;
    # dictionary-encoding random floats only wastes time before pyarrow falls back. LZ4:
    # doubles of physics barely compress, so the fastest codec wins (measured: zstd-1 is
    # 1.7x slower for a 7 % smaller file).
    constant = []
    for name, col in zip(table.column_names, table.columns, strict=True):
        values = col.to_numpy()
        if len(values) and values.min() == values.max():
            constant.append(name)
    sink = pa.BufferOutputStream()  # in memory first: the checksum is of these bytes
    pq.write_table(table, sink, compression="lz4", use_dictionary=constant,
                   write_statistics=["sample_id", "chunk"])
    data = sink.getvalue()
    record = {"rows": table.num_rows, "bytes": data.size, "crc32": checksum(data)}
    storage.write_bytes_atomic(data, path)
    return record


def verify_chunk(path, record) -> str | None:
    """Why the chunk file at ``path`` does not match its manifest ``record`` (None when it
    does): missing, another size, or other bytes (the CRC-32 is recomputed)."""
    if not isinstance(record, dict):
        return "not recorded in the manifest"
    size = storage.file_size(path)
    if size is None:
        return "missing"
    if size != record.get("bytes"):
        return f"{size} bytes, {record.get('bytes')} recorded"
    try:
        data = storage.read_bytes(path)
    except OSError as err:
        return f"unreadable ({err})"
    if checksum(data) != record.get("crc32"):
        return "checksum mismatch (the file was changed or corrupted)"
    return None


def write_manifest(directory, manifest: dict) -> None:
    """Write the dataset manifest of ``directory`` atomically."""
    storage.write_json_atomic(manifest, storage.join(directory, MANIFEST))


def read_manifest(directory) -> dict | None:
    """The dataset manifest, or None if ``directory`` (a path or URL) has none."""
    return storage.read_json(storage.join(directory, MANIFEST), what="dataset manifest")


def chunk_files(directory) -> dict:
    """Final-named chunk files in ``directory``, by chunk index (paths, or URLs for a
    URL)."""
    found = {}
    for name in storage.list_names(directory):
        index = chunk_index(name)
        if index is not None:
            found[index] = storage.join(directory, name)
    return found


def chunk_is_complete(path, expected_rows: int, config_hash: str) -> bool:
    """True if ``path`` is a readable chunk of this dataset with the expected rows."""
    try:
        meta = read_metadata(path)
        info = json.loads(meta.metadata[METADATA_KEY])
    except Exception:  # noqa: BLE001 - any unreadable file is redone, not trusted
        return False
    return meta.num_rows == expected_rows and info.get("config_hash") == config_hash


def read_metadata(path) -> pq.FileMetaData:
    """The Parquet footer of one chunk file."""
    path = storage.location(path)
    if isinstance(path, str):
        fs, fs_path = storage.resolve(path)
        return pq.read_metadata(fs_path, filesystem=fs)
    return pq.read_metadata(path)


def read_table(path, columns=None) -> pa.Table:
    """One chunk file as an Arrow table (only ``columns``, if given)."""
    path = storage.location(path)
    if isinstance(path, str):
        fs, fs_path = storage.resolve(path)
        return pq.read_table(fs_path, columns=columns, filesystem=fs)
    return pq.read_table(path, columns=columns)
