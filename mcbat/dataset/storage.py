"""Where datasets live: local paths and URLs, and atomic writes to either.

A dataset location is a local path (also written ``file:///abs/path``), or a URL of a file
system that pyarrow can write: one ``pyarrow.fs.FileSystem.from_uri`` understands
(``s3://``, ``gs://``, ``hdfs://``, ...) or, failing that, any fsspec URL (wrapped with
``pyarrow.fs.FSSpecHandler``). Local paths use plain ``os`` calls (fsync, an atomic
``os.replace``); URLs write a temporary file and then ``move`` it, which is a rename on
POSIX-like file systems and a copy (atomic per object) on object stores.

Errors name no command-line flag: a location the user gave is reported as ``location``
(the CLI says ``--out``).
"""

from __future__ import annotations

import contextlib
import datetime
import functools
import json
import os
import re
import shutil
import uuid
from pathlib import Path
from urllib.parse import unquote, urlparse

import pyarrow as pa
import pyarrow.fs as pafs

from mcbat.errors import InputError

__all__ = ["LOCAL", "entry_type", "file_size", "is_temporary_name", "join", "list_entries",
           "list_names", "local_path", "location",
           "make_dirs", "read_bytes", "read_json", "remove", "resolve", "write_atomic",
           "write_bytes_atomic", "write_json_atomic"]

#: The local file system, for pyarrow calls on local paths (a path string given to pyarrow
#: alone is parsed as a URI when it holds a colon: ``run:1/chunk-000000.parquet``).
LOCAL = pafs.LocalFileSystem()
_URL_RE = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*://")
_TEMPORARY_RE = re.compile(r"^\..+\.tmp$")


#: Schemes that name this machine's files: a location in one of them is a local path.
_LOCAL_URL_RE = re.compile(r"^(?:file|local):", re.IGNORECASE)
#: fsspec protocols that are not storage a dataset can live in (views of other file
#: systems, archives, inline data, read-only code hosts): refused with a clear message.
_NOT_STORAGE = frozenset({"data", "reference", "dir", "zip", "tar", "libarchive", "git",
                          "github", "cached", "simplecache", "filecache", "blockcache",
                          "jupyter", "jlab", "dask"})


def location(where) -> Path | str:
    """A dataset location: a ``pathlib.Path`` for a local path, else the URL as a
    string.

    A plain or relative path is a path whatever it holds (``run:1`` is the relative
    directory of that name); ``file:///abs`` and ``file:/abs`` are the path ``/abs``;
    ``local:///abs`` stays a URL (pyarrow's LocalFileSystem, the same code path as
    ``s3://``), spelled ``local:///abs`` whatever its slashes. Every spelling of a local
    directory has one lock: ``local_path``.
    """
    if isinstance(where, Path):
        return where
    if not isinstance(where, str):
        raise InputError(None, f"must be a path or a URL, got {type(where).__name__}",
                         repr(where))
    if not where.strip():
        raise InputError(None, "must not be empty (give a directory or a URL)", repr(where))
    if "\x00" in where:
        raise InputError(None, "must not contain a NUL character", repr(where))
    if _LOCAL_URL_RE.match(where):
        parsed = urlparse(where)
        scheme = parsed.scheme.lower()
        if parsed.netloc not in ("", "localhost"):
            raise InputError(None, f"a {scheme}:// URL names this machine's files; "
                             f"host {parsed.netloc!r} is not supported (mount it and give "
                             "the local path)", where)
        if parsed.query or parsed.fragment:
            raise InputError(None, "URL query strings and fragments are not supported",
                             where)
        path = unquote(parsed.path)
        if not path.startswith("/"):
            raise InputError(None, f"a {scheme}: URL needs an absolute path "
                             f"({scheme}:///abs/path); give a relative directory as "
                             "a plain path", where)
        path = os.path.normpath(path)
        return Path(path) if scheme == "file" else f"local://{path}"
    if _URL_RE.match(where):
        parsed = urlparse(where)
        scheme = parsed.scheme.lower()
        if parsed.query or parsed.fragment:
            raise InputError(None, "URL query strings and fragments are not supported (the "
                             "dataset's file names are appended to the path); configure the "
                             "file system through its environment variables instead", where)
        if scheme in _NOT_STORAGE:
            raise InputError(None, f"{scheme}:// is not storage a dataset can be written to "
                             "or read from; give a directory or a URL of a file system "
                             "(s3://, gs://, hdfs://, ...)", where)
        return where.rstrip("/")
    return Path(where)


def local_path(where) -> Path | None:
    """The absolute local directory that ``where`` names, whatever its spelling (a
    relative path, ``file:``, ``local://``, or any URL whose file system is this
    machine's); None for remote storage. The run's lock is taken there."""
    where = location(where)
    if isinstance(where, Path):
        return Path(os.path.abspath(where))
    fs, path = resolve(where)
    return Path(os.path.abspath(path)) if _is_local(fs) else None


def _is_local(fs) -> bool:
    """Whether a resolved file system is this machine's own (pyarrow's or fsspec's)."""
    if isinstance(fs, pafs.LocalFileSystem):
        return True
    if isinstance(fs, pafs.PyFileSystem):
        inner = getattr(fs.handler, "fs", None)
        return type(inner).__name__ == "LocalFileSystem"
    return False


def join(directory, name: str) -> Path | str:
    """The location of ``name`` inside the directory ``directory``."""
    directory = location(directory)
    return directory / name if isinstance(directory, Path) else f"{directory}/{name}"


def url_timeout() -> float:
    """Seconds a cloud file system may retry a request before the command fails:
    ``MCBAT_URL_TIMEOUT`` (default 30)."""
    try:
        value = float(os.environ.get("MCBAT_URL_TIMEOUT", "30"))
    except ValueError:
        value = 30.0
    return value if 0 < value < 86_400 else 30.0


@functools.lru_cache(maxsize=32)
def _filesystem(url: str) -> tuple[pafs.FileSystem, str]:
    """(file system, path) of a URL: pyarrow's own file systems first, then fsspec."""
    scheme = url.partition("://")[0].lower()
    if scheme in ("gs", "gcs"):
        # pyarrow's Google Cloud Storage client retries for 15 minutes by default: without
        # a network (or credentials) a command hung for as long. Bounded here.
        return (pafs.GcsFileSystem(retry_time_limit=datetime.timedelta(
            seconds=url_timeout())), url.partition("://")[2].rstrip("/"))
    try:
        return pafs.FileSystem.from_uri(url)
    except pa.ArrowInvalid:  # a scheme pyarrow does not know
        return _fsspec_filesystem(url)
    except (pa.ArrowException, OSError, ValueError) as err:
        raise InputError(None, f"unsupported URL: {err}", url) from None


def _fsspec_filesystem(url: str) -> tuple[pafs.FileSystem, str]:
    """(file system, path) of a URL through fsspec, for the schemes pyarrow does not know."""
    try:
        import fsspec
    except ImportError:
        raise InputError(None, "this URL scheme needs fsspec (pip install fsspec)",
                         url) from None
    try:
        fs, path = fsspec.core.url_to_fs(url)
    except ImportError as err:  # the scheme's own dependencies (aiohttp for http://, ...)
        raise InputError(None, f"this URL scheme needs a package that is not installed: "
                         f"{err}", url) from None
    except Exception as err:  # noqa: BLE001 - any URL fsspec cannot resolve is the user's
        raise InputError(None, f"unsupported URL: {err}", url) from None
    if type(fs).__name__ in ("DataFileSystem", "ReferenceFileSystem", "DirFileSystem"):
        raise InputError(None, "not storage a dataset can live in", url)
    return pafs.PyFileSystem(pafs.FSSpecHandler(fs)), path.rstrip("/")


def resolve(url: str) -> tuple[pafs.FileSystem, str]:
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
    fs, path = resolve(where)
    kind = fs.get_file_info(path).type
    return {pafs.FileType.Directory: "dir", pafs.FileType.File: "file"}.get(kind)


def list_names(directory) -> list[str]:
    """Names of the entries of a directory."""
    directory = location(directory)
    if isinstance(directory, Path):
        return [entry.name for entry in directory.iterdir()]
    fs, path = resolve(directory)
    infos = fs.get_file_info(pafs.FileSelector(path, allow_not_found=True))
    return [info.base_name for info in infos]


def list_entries(directory) -> dict:
    """``{name: "file" | "dir" | "other"}`` of the entries of a directory (a symbolic link
    counts as what it points to)."""
    directory = location(directory)
    if isinstance(directory, Path):
        out = {}
        for entry in directory.iterdir():
            try:
                out[entry.name] = ("dir" if entry.is_dir() else "file" if entry.is_file()
                                   else "other")
            except OSError:
                out[entry.name] = "other"
        return out
    fs, path = resolve(directory)
    infos = fs.get_file_info(pafs.FileSelector(path, allow_not_found=True))
    kinds = {pafs.FileType.Directory: "dir", pafs.FileType.File: "file"}
    return {info.base_name: kinds.get(info.type, "other") for info in infos}


def remove(directory, name: str, missing_ok=False) -> None:
    """Delete the file or tree ``name`` in ``directory``."""
    target = join(directory, name)
    if isinstance(target, Path):
        if target.is_dir() and not target.is_symlink():
            shutil.rmtree(target)
        else:
            target.unlink(missing_ok=missing_ok)
        return
    fs, path = resolve(target)
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
        fs, path = resolve(directory)
        fs.create_dir(path, recursive=True)


def temporary_name(name: str) -> str:
    """The hidden temporary name under which ``name`` is written before its rename.

    Unique per writer: a file recomputed by another process (a retried task on another
    host, where the pid may be the same) never shares a temporary file.
    """
    return f".{name}.{os.getpid()}-{uuid.uuid4().hex[:8]}.tmp"


def is_temporary_name(name: str) -> bool:
    """True for a name ``temporary_name`` makes."""
    return bool(_TEMPORARY_RE.match(name))


def write_atomic(path, write) -> None:
    """Write a file atomically: ``write(filesystem, temporary_path)`` (filesystem None for
    a local path), then an fsync and an atomic rename (a move, for a URL).

    Nothing is left behind if ``write`` fails: the temporary file is removed.
    """
    path = location(path)
    if not isinstance(path, Path):
        fs, fs_path = resolve(path)
        parent, _, name = fs_path.rpartition("/")
        tmp = f"{parent}/{temporary_name(name)}"
        try:
            write(fs, tmp)
            fs.move(tmp, fs_path)
        except BaseException:
            with contextlib.suppress(Exception):  # best effort; the original error matters
                fs.delete_file(tmp)
            raise
        return
    tmp = path.with_name(temporary_name(path.name))
    try:
        write(None, tmp)
        with open(tmp, "rb") as handle:
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


DIRECT_ALIGNMENT = 4096
"""Alignment (bytes) of the memory, offsets and sizes of a direct write."""
DIRECT_MINIMUM = 1 << 20
"""Files smaller than this are written through the page cache."""


def direct_io_enabled() -> bool:
    """Whether large local files may bypass the page cache (``O_DIRECT``): where the OS has
    it and the environment variable ``MCBAT_DIRECT_IO`` is not ``0``."""
    return hasattr(os, "O_DIRECT") and os.environ.get("MCBAT_DIRECT_IO", "1") != "0"


def _write_direct(data, path) -> bool:
    """Write ``data`` (a buffer at a ``DIRECT_ALIGNMENT``-aligned address) to the new
    file ``path`` bypassing the page cache; False, with nothing written, where the file
    system refuses (tmpfs, some network file systems), and the caller writes normally.

    Why: on Linux a buffered write copies every byte into freshly allocated page-cache
    pages, and on a virtual machine that allocation is most of the cost (a 90 MB chunk: 0.26
    s of system time, against 0.01 s direct), time taken from the kernel's threads. The
    aligned head is written from ``data`` itself; the tail (less than one block) from a
    zero-padded block, and the file is then cut to its size.
    """
    view = memoryview(data).cast("B")
    size = len(view)
    address = pa.py_buffer(view).address
    if size < DIRECT_MINIMUM or address % DIRECT_ALIGNMENT or not direct_io_enabled():
        return False
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_DIRECT, 0o644)
    except OSError:
        return False
    try:
        head = size - size % DIRECT_ALIGNMENT
        done = 0
        while done < head:
            done += os.write(fd, view[done:head])
        if head < size:
            block = memoryview(bytearray(2 * DIRECT_ALIGNMENT))
            start = -pa.py_buffer(block).address % DIRECT_ALIGNMENT
            tail = block[start:start + DIRECT_ALIGNMENT]
            tail[:size - head] = view[head:]
            os.write(fd, tail)
            os.ftruncate(fd, size)
    except OSError:
        os.close(fd)
        os.unlink(path)
        return False
    os.close(fd)
    return True


def write_bytes_atomic(data, path) -> None:
    """Write the bytes-like ``data`` to ``path`` (a local path or a URL), atomically.

    A large local file whose bytes sit at an aligned address (the chunk encoder's buffer)
    is written bypassing the page cache (``_write_direct``; ``MCBAT_DIRECT_IO=0``
    turns that off)."""

    def write(fs, tmp):
        if fs is None:
            if _write_direct(data, tmp):
                return
            with open(tmp, "wb") as handle:
                handle.write(data)
        else:
            with fs.open_output_stream(tmp) as handle:
                handle.write(data)

    write_atomic(path, write)


def write_json_atomic(data: dict, path) -> None:
    """Write ``data`` as JSON to ``path`` (a local path or a URL), atomically."""
    write_bytes_atomic((json.dumps(data, indent=2, sort_keys=True) + "\n").encode("utf-8"),
                       path)


def read_bytes(path) -> bytes:
    """The whole content of the file at ``path`` (a local path or a URL)."""
    path = location(path)
    if isinstance(path, Path):
        return path.read_bytes()
    fs, fs_path = resolve(path)
    with fs.open_input_stream(fs_path) as handle:
        return handle.read()


def file_size(path) -> int | None:
    """Size in bytes of the file at ``path``, or None if there is no file there."""
    path = location(path)
    if isinstance(path, Path):
        try:
            return path.stat().st_size if path.is_file() else None
        except OSError:
            return None
    fs, fs_path = resolve(path)
    info = fs.get_file_info(fs_path)
    return info.size if info.type == pafs.FileType.File else None


def read_json(path, what: str = "JSON file"):
    """The JSON document at ``path`` (a local path or a URL), or None if there is none.

    ``what`` names the file in the error message.

    Raises
    ------
    InputError
        If the file exists but cannot be read or parsed.
    """
    path = location(path)
    try:
        if isinstance(path, Path):
            if not path.exists():
                return None
            text = path.read_text(encoding="utf-8")
        else:
            fs, fs_path = resolve(path)
            if fs.get_file_info(fs_path).type == pafs.FileType.NotFound:
                return None
            with fs.open_input_stream(fs_path) as handle:
                text = handle.read().decode("utf-8")
        return json.loads(text)
    except (OSError, ValueError) as err:
        raise InputError(None, f"unreadable {what}: {err}", str(path)) from None
    except RecursionError:
        raise InputError(None, f"unreadable {what}: nested too deeply", str(path)) from None
