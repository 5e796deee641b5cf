"""Parquet datasets of impacts: the column contract, atomic chunk files, loading.

A dataset is a directory::

    DIR/_mcbat.json            manifest: config hash, seed, samples, chunk size, study
    DIR/chunk-000000.parquet   rows [0, C)
    DIR/chunk-000001.parquet   rows [C, 2C) ...

Chunk files are written under a hidden temporary name and renamed into place, so a file
with a final name is always complete. Each file carries the schema-level metadata (key
``mcbat``): units, the study config and its TOML text, seed, config hash and package
versions. Every solver input is a column, so each row is a self-contained case.

Column contract (SI units; see ``UNITS``), used by tools outside the package:

* inputs: ``mu``, ``e`` (energetic e*), ``axial``, ``angle``, ``impact_parameter``,
  ``ball_mass``, ``ball_radius``, ``ball_inertia_factor``, ``bat_mass``, ``bat_radius``,
  ``bat_slope``, ``bat_transverse_inertia``, ``bat_axial_inertia``, ``ball_vx_in`` ...
  ``ball_wz_in``, ``bat_vx_in`` ... ``bat_wz_in``;
* outputs: ``ball_vx`` ... ``ball_wz``, ``bat_vx`` ... ``bat_wz``, ``normal_impulse``,
  ``stick_impulse`` (NaN if none), ``compression_impulse``, ``tangential_impulse_1/2``,
  ``compression_work``, ``normal_work``, ``friction_work``, ``stick_criterion``,
  ``energy_in``, ``energy_out``, ``rk4_steps``, ``end_state`` (int8: 0 sliding, 1 stuck),
  ``status`` (int8: 0 ok, see ``mcbat.core.status``);
* derived: ``exit_speed``, ``scattering_angle`` (degrees, ``atan2(v_y, v_x)``),
  ``spin_axial`` (ball spin about the bat axis), ``spin`` (magnitude);
* bookkeeping: ``sample_id`` (int64), ``chunk`` (int32);
* optional simulated measurements (a study's ``[noise]``): ``exit_speed_measured``,
  ``scattering_angle_measured``, ``spin_axial_measured``, ``spin_measured`` (the model
  value plus a Gaussian error; the model columns are never altered).

A row whose status is not 0 has NaN outputs: it is flagged, never passed off as a result.

Locations: a dataset directory is a local path (also written ``file:///abs/path``), or a
URL of a file system that pyarrow can write: one ``pyarrow.fs.FileSystem.from_uri``
understands (``s3://``, ``gs://``, ``hdfs://``, ...) or, failing that, any fsspec URL
(wrapped with ``pyarrow.fs.FSSpecHandler``). Local paths use plain ``os`` calls (fsync, an
atomic ``os.replace``); URLs write the temporary file and then ``move`` it, which is a
rename on POSIX-like file systems and a copy (atomic per object) on object stores.
"""

from __future__ import annotations

import functools
import json
import os
import platform
import re
import shutil
import uuid
from pathlib import Path
from urllib.parse import unquote, urlparse

import numpy as np
import pyarrow as pa
import pyarrow.fs as pafs
import pyarrow.parquet as pq

from mcbat.core import status as st
from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS
from mcbat.errors import InputError

SCHEMA_VERSION = 2
MANIFEST = "_mcbat.json"
METADATA_KEY = b"mcbat"
_CHUNK_RE = re.compile(r"^chunk-(\d{6})\.parquet$")

_LINEAR = {"v": "m/s", "w": "rad/s"}
UNITS = {
    "mu": "1", "e": "1", "e_x": "1", "axial": "m", "angle": "rad", "impact_parameter": "m",
    "ball_mass": "kg", "ball_radius": "m", "ball_inertia_factor": "1",
    "bat_mass": "kg", "bat_radius": "m", "bat_slope": "1",
    "bat_transverse_inertia": "kg m^2", "bat_axial_inertia": "kg m^2",
    **{f"{body}_{q}{c}_in": _LINEAR[q] for body in ("ball", "bat") for q in "vw" for c in "xyz"},
    **{f"{body}_{q}{c}": _LINEAR[q] for body in ("ball", "bat") for q in "vw" for c in "xyz"},
    "normal_impulse": "kg m/s", "stick_impulse": "kg m/s", "compression_impulse": "kg m/s",
    "tangential_impulse_1": "kg m/s", "tangential_impulse_2": "kg m/s",
    "compression_work": "J", "normal_work": "J", "friction_work": "J",
    "stick_criterion": "J", "energy_in": "J", "energy_out": "J", "rk4_steps": "1",
    "end_state": "code", "status": "code",
    "exit_speed": "m/s", "scattering_angle": "deg", "spin_axial": "rad/s", "spin": "rad/s",
    "sample_id": "1", "chunk": "1",
    "exit_speed_measured": "m/s", "scattering_angle_measured": "deg",
    "spin_axial_measured": "rad/s", "spin_measured": "rad/s",
}
"""Unit of every column."""

INPUT_COLUMNS = ("mu", "e", "e_x", "axial", "angle", "impact_parameter", "ball_mass", "ball_radius",
                 "ball_inertia_factor", "bat_mass", "bat_radius", "bat_slope",
                 "bat_transverse_inertia", "bat_axial_inertia",
                 *(f for f in INPUT_FIELDS if f.endswith("_in")))
DERIVED_COLUMNS = ("exit_speed", "scattering_angle", "spin_axial", "spin")
COLUMNS = (*INPUT_COLUMNS, *(f for f in OUTPUT_FIELDS), "end_state", "status",
           *DERIVED_COLUMNS, "sample_id", "chunk")
"""All columns, in file order."""


def chunk_name(index: int) -> str:
    return f"chunk-{index:06d}.parquet"


# ---------------------------------------------------------------- locations

_URL_RE = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*://")


def location(where) -> Path | str:
    """A dataset location: a :class:`~pathlib.Path` for a local path (a ``file://`` URL
    without a host is one too), else the URL as a string."""
    if isinstance(where, str) and _URL_RE.match(where):
        parsed = urlparse(where)
        if parsed.scheme.lower() == "file" and parsed.netloc in ("", "localhost"):
            return Path(unquote(parsed.path))
        return where.rstrip("/")
    return Path(where)


def join(directory, name: str) -> Path | str:
    """The location of ``name`` inside the dataset directory ``directory``."""
    directory = location(directory)
    return directory / name if isinstance(directory, Path) else f"{directory}/{name}"


@functools.lru_cache(maxsize=32)
def _filesystem(url: str) -> tuple[pafs.FileSystem, str]:
    """(file system, path) of a URL: pyarrow's own file systems first, then fsspec."""
    try:
        return pafs.FileSystem.from_uri(url)
    except pa.ArrowInvalid:  # a scheme pyarrow does not know
        pass
    try:
        import fsspec

        fs, path = fsspec.core.url_to_fs(url)
    except ImportError:
        raise InputError(None, "this URL scheme needs fsspec (pip install fsspec)",
                         url) from None
    except ValueError as err:
        raise InputError(None, f"unsupported URL: {err}", url) from None
    return pafs.PyFileSystem(pafs.FSSpecHandler(fs)), path.rstrip("/")


def _resolve(url: str) -> tuple[pafs.FileSystem, str]:
    """(file system, path) of a file or directory URL; the file system is resolved (and
    cached) per parent directory, so the files of one dataset share it."""
    parent, _, name = url.rpartition("/")
    if not name or parent.endswith(":/") or parent.endswith(":"):
        return _filesystem(url)
    fs, base = _filesystem(parent)
    return fs, f"{base}/{name}"


def entry_type(where) -> str | None:
    """``"dir"``, ``"file"`` or None (nothing there)."""
    where = location(where)
    if isinstance(where, Path):
        return "dir" if where.is_dir() else "file" if where.exists() else None
    fs, path = _resolve(where)
    kind = fs.get_file_info(path).type
    return {pafs.FileType.Directory: "dir", pafs.FileType.File: "file"}.get(kind)


def list_names(directory) -> list[str]:
    """Names of the entries of a dataset directory."""
    directory = location(directory)
    if isinstance(directory, Path):
        return [entry.name for entry in directory.iterdir()]
    fs, path = _resolve(directory)
    infos = fs.get_file_info(pafs.FileSelector(path, allow_not_found=True))
    return [info.base_name for info in infos]


def remove(directory, name: str, missing_ok=False) -> None:
    """Delete the file or tree ``name`` in ``directory``."""
    target = join(directory, name)
    if isinstance(target, Path):
        if target.is_dir() and not target.is_symlink():
            shutil.rmtree(target)
        else:
            target.unlink(missing_ok=missing_ok)
        return
    fs, path = _resolve(target)
    kind = fs.get_file_info(path).type
    if kind == pafs.FileType.Directory:
        fs.delete_dir(path)
    elif kind != pafs.FileType.NotFound or not missing_ok:
        fs.delete_file(path)


def make_dirs(directory) -> None:
    """Create ``directory`` (and its parents) if it does not exist."""
    directory = location(directory)
    if isinstance(directory, Path):
        directory.mkdir(parents=True, exist_ok=True)
    else:
        fs, path = _resolve(directory)
        fs.create_dir(path, recursive=True)


def _temporary_name(name: str) -> str:
    # Unique per writer: a chunk recomputed by another process (a retried task on another
    # host, where the pid may be the same) never shares a temporary file.
    return f".{name}.{os.getpid()}-{uuid.uuid4().hex[:8]}.tmp"


def _write_url_atomic(target: str, write) -> None:
    """``write(filesystem, temporary_path)``, then move the file to ``target``."""
    fs, path = _resolve(target)
    parent, _, name = path.rpartition("/")
    tmp = f"{parent}/{_temporary_name(name)}"
    try:
        write(fs, tmp)
        fs.move(tmp, path)
    except BaseException:
        try:
            fs.delete_file(tmp)
        except Exception:  # noqa: BLE001 - best effort; the original error matters
            pass
        raise


def package_versions() -> dict:
    import numba
    import pandas
    import scipy

    import mcbat

    return {"mcbat": mcbat.__version__, "python": platform.python_version(),
            "numpy": np.__version__, "numba": numba.__version__, "scipy": scipy.__version__,
            "pandas": pandas.__version__, "pyarrow": pa.__version__}


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
    metadata : dict
        JSON-serialisable dataset metadata stored in the schema.
    noise : dict of str -> float64[n], optional
        Simulated measurement errors: column ``<name>_measured`` = ``<name>`` + error,
        appended after the contract columns (the model value stays untouched).
    """
    n = inputs.shape[1]
    cols = {name: inputs[i] for i, name in enumerate(INPUT_FIELDS)}
    cols.update(extra_inputs)
    cols.update({name: out[i] for i, name in enumerate(OUTPUT_FIELDS)})
    vx, vy, vz = cols["ball_vx"], cols["ball_vy"], cols["ball_vz"]
    wx, wy, wz = cols["ball_wx"], cols["ball_wy"], cols["ball_wz"]
    derived = {
        "exit_speed": np.sqrt(vx * vx + vy * vy + vz * vz),
        "scattering_angle": np.degrees(np.arctan2(vy, vx)),
        "spin_axial": wz,
        "spin": np.sqrt(wx * wx + wy * wy + wz * wz),
    }
    arrays = []
    for name in COLUMNS:
        if name in derived:
            arrays.append(pa.array(derived[name]))
        elif name == "status":
            arrays.append(pa.array(status, pa.int8()))
        elif name == "end_state":
            arrays.append(pa.array(end_state, pa.int8()))
        elif name == "rk4_steps":
            arrays.append(pa.array(np.nan_to_num(cols[name]).astype(np.int32)))
        elif name == "sample_id":
            arrays.append(pa.array(np.arange(sample_id_start, sample_id_start + n,
                                             dtype=np.int64)))
        elif name == "chunk":
            arrays.append(pa.array(np.full(n, chunk, np.int32)))
        else:
            arrays.append(pa.array(cols[name]))
    names = list(COLUMNS)
    for name, error in (noise or {}).items():
        value = derived[name] if name in derived else cols[name]
        arrays.append(pa.array(value + error))
        names.append(f"{name}_measured")
    schema_meta = {METADATA_KEY: json.dumps(metadata, sort_keys=True).encode()}
    return pa.Table.from_arrays(arrays, names=names).replace_schema_metadata(schema_meta)


def write_atomic(table: pa.Table, path) -> None:
    """Write ``table`` to ``path`` (a local path or a URL) via a hidden temporary file and
    an atomic rename (a move, for a URL)."""
    path = location(path)
    # Constant columns (most inputs of a typical study) cost nothing with dictionary + RLE;
    # dictionary-encoding random floats only wastes time before pyarrow falls back. LZ4:
    # doubles of physics barely compress, so the fastest codec wins (measured: zstd-1 is
    # 1.7x slower for a 7 % smaller file).
    constant = []
    for name, col in zip(table.column_names, table.columns):
        values = col.to_numpy()
        if len(values) and values.min() == values.max():
            constant.append(name)
    options = dict(compression="lz4", use_dictionary=constant,
                   write_statistics=["sample_id", "chunk"])
    if not isinstance(path, Path):
        _write_url_atomic(path, lambda fs, tmp: pq.write_table(table, tmp, filesystem=fs,
                                                               **options))
        return
    tmp = path.with_name(_temporary_name(path.name))
    try:
        pq.write_table(table, tmp, **options)
        with open(tmp, "rb") as handle:
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_json_atomic(data: dict, path) -> None:
    """Write ``data`` as JSON to ``path`` (a local path or a URL), atomically."""
    path = location(path)
    if not isinstance(path, Path):
        text = json.dumps(data, indent=2, sort_keys=True) + "\n"

        def write(fs, tmp):
            with fs.open_output_stream(tmp) as handle:
                handle.write(text.encode("utf-8"))

        _write_url_atomic(path, write)
        return
    tmp = path.with_name(_temporary_name(path.name))
    try:
        with open(tmp, "w", encoding="utf-8") as handle:
            json.dump(data, handle, indent=2, sort_keys=True)
            handle.write("\n")
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def read_manifest(directory) -> dict | None:
    """The dataset manifest, or None if ``directory`` (a path or URL) has none."""
    path = join(directory, MANIFEST)
    try:
        if isinstance(path, Path):
            if not path.exists():
                return None
            text = path.read_text(encoding="utf-8")
        else:
            fs, fs_path = _resolve(path)
            if fs.get_file_info(fs_path).type == pafs.FileType.NotFound:
                return None
            with fs.open_input_stream(fs_path) as handle:
                text = handle.read().decode("utf-8")
        return json.loads(text)
    except (OSError, ValueError) as err:
        raise InputError(None, f"unreadable dataset manifest: {err}", str(path)) from None


def chunk_files(directory) -> dict[int, Path | str]:
    """Final-named chunk files in ``directory``, by chunk index (paths, or URLs for a
    URL)."""
    found = {}
    for name in list_names(directory):
        match = _CHUNK_RE.match(name)
        if match:
            found[int(match.group(1))] = join(directory, name)
    return found


def chunk_is_complete(path, expected_rows: int, config_hash: str) -> bool:
    """True if ``path`` is a readable chunk of this dataset with the expected rows."""
    try:
        path = location(path)
        if isinstance(path, Path):
            meta = pq.read_metadata(path)
        else:
            fs, fs_path = _resolve(path)
            meta = pq.read_metadata(fs_path, filesystem=fs)
        info = json.loads(meta.metadata[METADATA_KEY])
    except Exception:  # noqa: BLE001 - any unreadable file is redone, not trusted
        return False
    return meta.num_rows == expected_rows and info.get("config_hash") == config_hash


def load(directory, columns=None, labels=False):
    """Load a dataset directory written by ``mcbat run`` as a pandas DataFrame.

    Parameters
    ----------
    directory : str or Path
        The dataset directory, or its URL (see the module docstring).
    columns : list of str, optional
        Only these columns.
    labels : bool
        Turn ``status`` and ``end_state`` codes into categorical labels.

    Returns
    -------
    pandas.DataFrame
        Rows sorted by ``sample_id``; ``df.attrs["mcbat"]`` holds the dataset manifest
        and ``df.attrs["directory"]`` the directory.
    """
    import pandas as pd

    directory = location(directory)
    if entry_type(directory) != "dir":
        raise InputError(None, "no such dataset directory", str(directory))
    manifest = read_manifest(directory)
    if manifest is None:
        raise InputError(None, f"not an mcbat dataset (no {MANIFEST})", str(directory))
    files = [path for _, path in sorted(chunk_files(directory).items())]
    if not files:
        raise InputError(None, "the dataset has no chunk files yet", str(directory))
    unknown = sorted(set(columns or ()) - set(UNITS))
    if unknown:
        raise InputError("columns", f"unknown column {unknown[0]!r}")
    table = pa.concat_tables(_read_table(path, columns) for path in files)
    df = table.to_pandas()
    if "sample_id" in df.columns:
        df = df.sort_values("sample_id", kind="stable").reset_index(drop=True)
    if labels:
        if "status" in df.columns:
            df["status"] = pd.Categorical.from_codes(df["status"].astype(int),
                                                     list(st.STATUS_NAMES.values()))
        if "end_state" in df.columns:
            df["end_state"] = pd.Categorical.from_codes(df["end_state"].astype(int),
                                                        list(st.END_STATE_NAMES.values()))
    df.attrs["mcbat"] = manifest
    df.attrs["directory"] = str(directory)
    return df


def _read_table(path, columns) -> pa.Table:
    if isinstance(path, Path):
        return pq.read_table(path, columns=columns)
    fs, fs_path = _resolve(path)
    return pq.read_table(fs_path, columns=columns, filesystem=fs)
