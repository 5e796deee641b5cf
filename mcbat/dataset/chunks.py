"""Chunk files and the manifest of a dataset directory.

A dataset is a directory::

    DIR/_mcbat.json            manifest: config hash, seed, samples, chunk size, study,
                               and the record of every chunk written (rows, bytes, CRC-32)
    DIR/chunk-000000.parquet   rows [0, C)
    DIR/chunk-000001.parquet   rows [C, 2C) ...   (chunk-1000000.parquet: no digit limit)

Chunk files are written under a hidden temporary name and renamed into place
(``mcbat.dataset.storage.write_atomic``), so a file with a final name is always
complete. Once a chunk file is in place, the run records it in the manifest (key
``files``: ``{name: {"rows", "bytes", "crc32"}}``, the CRC-32 of the file's bytes); only a
recorded chunk whose bytes match its record belongs to the dataset
(``mcbat.dataset.check``). Each file carries the schema-level metadata (key ``mcbat``):
units, the study config and its TOML text, seed, config hash and package versions. The
columns are those of ``mcbat.dataset.schema``.
"""

from __future__ import annotations

import json
import os
import platform
import re
import threading
import zlib
from importlib import metadata

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from mcbat.core.units import M_PER_FT
from mcbat.dataset import storage
from mcbat.dataset.schema import (
    COLUMNS,
    FLIGHT_COLUMNS,
    GAME_COLUMNS,
    GAME_INPUT_COLUMNS,
    INPUT_COLUMNS,
    MEASURED_SUFFIX,
    PITCH_SOURCE_COLUMNS,
    statcast_units,
)
from mcbat.solving import (
    FLIGHT_FIELDS,
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
    INPUT_FIELDS,
    OUTPUT_FIELDS,
)
from mcbat.solving.derived import derive, derive_game
from mcbat.solving.names import bat_frame_columns

__all__ = ["MANIFEST", "METADATA_KEY", "build_game_table", "build_table", "checksum",
           "chunk_files", "chunk_index", "chunk_is_complete", "chunk_name", "foreign_entries",
           "game_columns", "is_reader_visible",
           "impact_columns", "is_temporary_chunk_name", "numpy_to_arrow", "package_versions",
           "read_manifest", "read_metadata", "read_table", "to_table", "verify_chunk",
           "write_chunk", "write_manifest"]

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
    """Versions of Python and of the packages that determine the data (provenance), from
    their installed metadata (importing pandas and scipy only to ask would cost a run
    ~0.5 s of start-up)."""
    return {"mcbat": metadata.version("mcbat"), "python": platform.python_version(),
            "numpy": np.__version__, "numba": metadata.version("numba"),
            "scipy": metadata.version("scipy"), "pandas": metadata.version("pandas"),
            "pyarrow": pa.__version__}


_INT8_COLUMNS = ("status", "end_state", "flight_status")
#: Columns that keep their type whatever ``[output] precision`` says: the inputs (enough to
#: re-solve a row) and the bookkeeping.
_FULL_PRECISION = frozenset(INPUT_COLUMNS) | frozenset(GAME_INPUT_COLUMNS) | {
    "sample_id", "chunk", "rk4_steps", *_INT8_COLUMNS, *PITCH_SOURCE_COLUMNS}


_ARROW_TYPES = {np.dtype(np.float64): pa.float64(), np.dtype(np.float32): pa.float32(),
                np.dtype(np.int64): pa.int64(), np.dtype(np.int32): pa.int32(),
                np.dtype(np.int8): pa.int8()}
_NUMPY_TYPES = {arrow: numpy for numpy, arrow in _ARROW_TYPES.items()}


def _numpy_view(column: pa.ChunkedArray) -> np.ndarray:
    """The values of a column of one primitive chunk without nulls, viewed in place
    (pyarrow's ``to_numpy`` imports pandas, ~0.2 s of a run's start-up); else a copy."""
    if column.num_chunks == 1:
        array = column.chunk(0)
        dtype = _NUMPY_TYPES.get(array.type)
        if dtype is not None and array.null_count == 0:
            return np.frombuffer(array.buffers()[1], dtype, count=len(array),
                                 offset=array.offset * dtype.itemsize)
    return column.to_numpy()


def numpy_to_arrow(values, dtype=None) -> pa.Array:
    """An Arrow array viewing the numpy values (converted to ``dtype`` if given), with no
    null bitmap (NaN stays a value): what ``pa.array`` gives, built from the buffer
    because ``pa.array`` imports pandas (~0.2 s of start-up) to ask whether the values
    are a Series. float64, float32, int64, int32 or int8."""
    values = np.ascontiguousarray(values, dtype=dtype)
    return pa.Array.from_buffers(_ARROW_TYPES[values.dtype], values.size,
                                 [None, pa.py_buffer(values)])


def _arrow_array(name, values, sample_id_start, chunk, n, float32):
    """The Arrow array of column ``name`` (status codes int8, ``rk4_steps`` int32,
    ``sample_id`` and ``chunk`` generated; outputs float32 if ``float32``)."""
    if name in _INT8_COLUMNS:
        return numpy_to_arrow(values, np.int8)
    if name == "rk4_steps":
        return numpy_to_arrow(np.nan_to_num(values).astype(np.int32))
    if name == "sample_id":
        return numpy_to_arrow(np.arange(sample_id_start, sample_id_start + n, dtype=np.int64))
    if name == "chunk":
        return numpy_to_arrow(np.full(n, chunk, np.int32))
    if name in PITCH_SOURCE_COLUMNS:
        return numpy_to_arrow(values, np.int64)
    if float32 and name not in _FULL_PRECISION:
        return numpy_to_arrow(values, np.float32)
    return numpy_to_arrow(values, np.float64)


def impact_columns(inputs, out, status, end_state, extra_inputs, noise=None, derived=None):
    """Every column of an impact chunk as arrays, from the kernel's struct-of-arrays.

    Parameters
    ----------
    inputs : float64[len(INPUT_FIELDS), n]
        Kernel inputs.
    out, status, end_state
        Kernel outputs (see ``mcbat.core.batch.solve_batch``).
    extra_inputs : dict of str -> float64[n]
        Inputs not passed to the kernel (``impact_parameter``, ``from_barrel_end``;
        ``from_barrel_end`` is NaN when absent).
    noise : dict of str -> float64[n], optional
        Simulated measurement errors: column ``<name>_measured`` = ``<name>`` + error,
        after the contract columns (the model value stays untouched).
    derived : collection of str, optional
        Compute only these derived columns (``mcbat.solving.derived.derive``; a
        summary-only run, which writes no file, needs only the ones it summarises).

    Returns
    -------
    names : list of str
        The columns in file order (``mcbat.dataset.schema.COLUMNS``, then the
        measured ones); ``sample_id`` and ``chunk`` are generated when written.
    cols : dict of str -> ndarray
    """
    n = inputs.shape[1]
    cols = {name: inputs[i] for i, name in enumerate(INPUT_FIELDS)}
    cols.update(extra_inputs)
    if "from_barrel_end" not in cols:
        cols["from_barrel_end"] = np.full(n, np.nan)
    cols.update({name: out[i] for i, name in enumerate(OUTPUT_FIELDS)})
    if derived is not None:
        derived = {*derived, *(noise or {})}  # (a measured column needs its model value)
    cols.update(derive((cols["ball_vx"], cols["ball_vy"], cols["ball_vz"]),
                       (cols["ball_wx"], cols["ball_wy"], cols["ball_wz"]), derived))
    cols.update(status=status, end_state=end_state)
    names = list(COLUMNS)
    for name, error in (noise or {}).items():
        cols[f"{name}{MEASURED_SUFFIX}"] = cols[name] + error
        names.append(f"{name}{MEASURED_SUFFIX}")
    return names, cols




def game_columns(game_inputs, frame, out, game_out, status, end_state, flight=None,
                 derived=None, pitch_source=None):
    """Every column of a game chunk as arrays (``mcbat.dataset.schema.GAME_COLUMNS``,
    plus ``mcbat.dataset.schema.FLIGHT_COLUMNS`` with ``flight`` and
    ``mcbat.dataset.schema.PITCH_SOURCE_COLUMNS`` with ``pitch_source``, the int64
    columns of ``mcbat.study.game.GameStudy.pitch_identifiers``), from the arrays of
    ``mcbat.core.swing.solve_game_batch``; returns ``(names, cols)`` as
    ``impact_columns`` (``derived``: the bat-frame derived columns to compute, as
    there; the field-frame ones are always computed)."""
    cols = statcast_units({name: game_inputs[i] for i, name in enumerate(GAME_INPUT_FIELDS)})
    cols.update(bat_frame_columns(game_inputs, frame))
    cols.update({name: game_out[i] for i, name in enumerate(GAME_OUTPUT_FIELDS)})
    cols.update({name: out[i] for i, name in enumerate(OUTPUT_FIELDS)})
    cols.update(derive((cols["ball_vx"], cols["ball_vy"], cols["ball_vz"]),
                       (cols["ball_wx"], cols["ball_wy"], cols["ball_wz"]), derived))
    cols.update(derive_game(
        (cols["field_ball_vx"], cols["field_ball_vy"], cols["field_ball_vz"]),
        (cols["field_ball_wx"], cols["field_ball_wy"], cols["field_ball_wz"])))
    names = list(GAME_COLUMNS)
    if flight is not None:  # (out, status) of mcbat.core.flight.fly_batch, SI
        flight_out, flight_status = flight
        row = {name: i for i, name in enumerate(FLIGHT_FIELDS)}
        for name in ("hit_distance", "landing_x", "landing_y", "apex"):
            cols[f"{name}_m"] = flight_out[row[name]]
            cols[name] = flight_out[row[name]] / M_PER_FT
        cols["hang_time"] = flight_out[row["hang_time"]]
        cols["flight_status"] = flight_status
        names += FLIGHT_COLUMNS
    if pitch_source:
        cols.update(pitch_source)
        names += PITCH_SOURCE_COLUMNS
    cols.update(status=status, end_state=end_state)
    return names, cols


def to_table(names, cols, sample_id_start, chunk, output=None, metadata=None) -> pa.Table:
    """The Arrow table of a chunk's columns ``names`` (file order) from ``cols``.

    Parameters
    ----------
    names, cols
        From ``impact_columns`` or ``game_columns``.
    sample_id_start, chunk : int
        ``sample_id`` of the first row; the chunk index.
    output : mcbat.study.output.OutputSpec, optional
        The columns to keep (``sample_id`` always) and the outputs' precision.
    metadata : dict, optional
        JSON-serialisable dataset metadata stored in the schema.
    """
    n = len(cols["status"])
    float32 = output is not None and output.precision == "float32"
    if output is not None and output.columns is not None:
        keep = set(output.columns) | {"sample_id"}
        names = [name for name in names if name in keep]
    arrays = [_arrow_array(name, cols.get(name), sample_id_start, chunk, n, float32)
              for name in names]
    # Every field is declared non-nullable (Parquet REQUIRED): no column ever holds a null
    # (a failed row's outputs are NaN, a value), and a REQUIRED column is written without
    # definition levels, which took ~30 % of the encoding time (schema version 6).
    table = pa.Table.from_arrays(arrays, schema=pa.schema(
        [pa.field(name, array.type, nullable=False)
         for name, array in zip(names, arrays, strict=True)]))
    if metadata is None:
        return table
    return table.replace_schema_metadata(
        {METADATA_KEY: json.dumps(metadata, sort_keys=True).encode()})


def build_table(sample_id_start, chunk, inputs, out, status, end_state, extra_inputs,
                metadata, noise=None, output=None) -> pa.Table:
    """One impact chunk's table (``impact_columns``, then ``to_table``)."""
    names, cols = impact_columns(inputs, out, status, end_state, extra_inputs, noise)
    return to_table(names, cols, sample_id_start, chunk, output, metadata)


def build_game_table(sample_id_start, chunk, game_inputs, frame, out, game_out, status,
                     end_state, metadata, flight=None, output=None) -> pa.Table:
    """One game chunk's table (``game_columns``, then ``to_table``)."""
    names, cols = game_columns(game_inputs, frame, out, game_out, status, end_state, flight)
    return to_table(names, cols, sample_id_start, chunk, output, metadata)


def checksum(data) -> str:
    """CRC-32 of the bytes-like ``data``, as 8 hex digits. A checksum against accidents
    (bit rot, a truncated or overwritten file), fast enough to run on every chunk
    (~1 GB/s): not a defence against tampering."""
    return f"{zlib.crc32(data):08x}"


def _is_constant(values) -> bool:
    """Whether every value equals the first (False with a NaN); the ends are compared
    first, so a column of random values costs nothing."""
    return (len(values) > 0 and values[0] == values[-1]
            and not np.any(values != values[0]))


_buffers = threading.local()  # one reusable encoding buffer per writing thread


def _capacity(table: pa.Table) -> int:
    """Bytes of buffer to encode ``table`` into: plain pages need little beyond the data."""
    return int(table.nbytes * 1.05) + (4 << 20)


def _encode(table: pa.Table, options: dict):
    """The Parquet bytes of ``table``, written into this thread's reusable buffer (a fresh
    100 MB buffer per chunk costs its page faults again: ~30 % of the encoding time).

    The bytes returned are valid until this thread's next call."""
    capacity = _capacity(table)
    buffer = getattr(_buffers, "buffer", None)
    if buffer is None or buffer.size < capacity:
        # Page-aligned, so that the file can be written from it directly (storage).
        raw = np.empty(capacity + storage.DIRECT_ALIGNMENT, np.uint8)
        start = -raw.ctypes.data % storage.DIRECT_ALIGNMENT
        buffer = _buffers.buffer = pa.py_buffer(raw[start:start + capacity])
    sink = pa.FixedSizeBufferWriter(buffer)
    try:
        pq.write_table(table, sink, **options)
    except OSError:  # "Write out of bounds": it did not fit (compressed pages can grow)
        sink = pa.BufferOutputStream()
        pq.write_table(table, sink, **options)
        return sink.getvalue()
    return buffer.slice(0, sink.tell())


def write_chunk(table: pa.Table, path, compression="none") -> dict:
    """Write a chunk's ``table`` to ``path`` (a local path or a URL), atomically.

    ``compression`` is the codec of the float columns (``"none"``, ``"lz4"``, ``"zstd"``,
    ``"snappy"``); integer columns always use LZ4. Doubles of physics barely compress:
    LZ4 saves ~12 % of a ``studies/throughput.toml`` chunk for 2-3 times the writing
    time, so they are stored plain by default.

    Returns
    -------
    dict
        The chunk's record for the manifest: ``{"rows", "bytes", "crc32"}``.
    """
    # Constant columns (most inputs of a typical study) cost nothing with dictionary + RLE;
    # dictionary-encoding random floats only wastes time before pyarrow falls back.
    constant, codecs = [], {}
    for name, col in zip(table.column_names, table.columns, strict=True):
        if _is_constant(_numpy_view(col)):
            constant.append(name)
        codecs[name] = compression if pa.types.is_floating(col.type) else "lz4"
    options = {"compression": codecs, "use_dictionary": constant,
               "write_statistics": [n for n in ("sample_id", "chunk") if n in table.column_names]}
    data = _encode(table, options)  # in memory first: the checksum is of these bytes
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
    URL). Only files: a directory with a chunk's name is not one (``foreign_entries``
    names it)."""
    found = {}
    for name, kind in storage.list_entries(directory).items():
        index = chunk_index(name)
        if index is not None and kind == "file":
            found[index] = storage.join(directory, name)
    return found


def is_reader_visible(name: str) -> bool:
    """Whether a Parquet reader of the directory (``pandas.read_parquet(DIR)``,
    ``pyarrow.dataset``) reads this entry as data: it skips names starting with ``_`` or
    ``.``, and reads every other file and directory."""
    return not name.startswith(("_", "."))


def foreign_entries(directory) -> list:
    """Entries of ``directory`` a Parquet reader would read as data that are not chunk
    files (``chunk-000002 (copy).parquet``, a directory named like a chunk, any other
    file): sorted names."""
    return sorted(name for name, kind in storage.list_entries(directory).items()
                  if is_reader_visible(name)
                  and not (kind == "file" and chunk_index(name) is not None))


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
    # An explicit local file system: given a string, pyarrow would read "run:1/x" as a URL.
    return pq.read_metadata(os.path.abspath(path), filesystem=storage.LOCAL)


def read_table(path, columns=None) -> pa.Table:
    """One chunk file as an Arrow table (only ``columns``, if given).

    Read with Parquet's file reader: ``pq.read_table`` runs Arrow's dataset scanner,
    whose thread pool can abort the interpreter at exit (apache/arrow#34314), and one
    file needs no scanner."""
    path = storage.location(path)
    if isinstance(path, str):
        fs, fs_path = storage.resolve(path)
    else:
        fs, fs_path = storage.LOCAL, os.path.abspath(path)
    with fs.open_input_file(fs_path) as handle:
        return pq.ParquetFile(handle).read(columns=columns)
