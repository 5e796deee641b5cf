"""Input files as the Statcast readers take them: regular files only, compressed ones with a
cap on what they may expand to.

A Statcast command reads its file at least once from the start (often twice: the header to
tell what it is, then the rows). A device (``/dev/zero``, ``/dev/urandom``), a named pipe
(FIFO) or a directory cannot be read that way: the first never ends, the second blocks
until someone writes and cannot be read again, the third holds no rows. They are refused
before anything is opened, with what they are.

A gzip file is read as it is decompressed; the text it expands to may be at most
``MAX_EXPANSION`` times the file's size (a Savant export compresses about 4-5 times),
and at least ``MIN_EXPANDED_BYTES``: a file that expands beyond that (a "gzip bomb", a
few MB of zeros that would become gigabytes) is refused when the cap is reached, naming the
cap.

The tables read from them are written back by ``write_parquet``: atomically, with their
metadata in the Parquet schema.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

from mcbat.errors import InputError

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["BLOCK_BYTES", "MAX_EXPANSION", "MAX_LINE_BYTES", "MIN_EXPANDED_BYTES",
           "CappedReader", "check_expansion", "check_regular_file", "file_kind", "text_lines",
           "write_parquet"]

MAX_EXPANSION = 50
"""A compressed input may expand to at most this many times its size on disk."""
MIN_EXPANDED_BYTES = 64 << 20
"""... and always to this many bytes (64 MiB): a small compressed file is never refused."""
MAX_LINE_BYTES = 16 << 20
"""The longest line a CSV reader accepts (16 MiB; a Savant row is 1-2 kB): a longer one is
not a table (a binary file, or a compressed one that expands to a single line)."""

_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a named pipe (FIFO)"),
          (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
          (stat.S_ISSOCK, "a socket"))


def file_kind(mode: int) -> str | None:
    """What a file of ``st_mode`` ``mode`` is when it is not a regular file, else None."""
    if stat.S_ISREG(mode):
        return None
    for test, name in _KINDS:
        if test(mode):
            return name
    return "not a regular file"


def check_regular_file(path: str | os.PathLike[str], label: str | None = None,
                       field: str | None = None) -> os.stat_result:
    """``path``'s status if it is a regular file (symbolic links followed), else
    ``mcbat.errors.InputError`` saying what it is, before anything is opened.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    label : str, optional
        How the error names the file (default ``path``).
    field : str, optional
        The field the error is about (``"pitches.file"``, ``"--data"``).
    """
    label = os.fspath(path) if label is None else label
    try:
        status = os.stat(path)
    except FileNotFoundError:
        raise InputError(field, "no such file", label) from None
    except NotADirectoryError:
        raise InputError(field, "no such file (a part of its path is not a directory)",
                         label) from None
    except (OSError, ValueError) as err:  # permission, a NUL in the name, a name too long
        reason = getattr(err, "strerror", None) or str(err)
        raise InputError(field, f"cannot read the file: {reason}", label) from None
    kind = file_kind(status.st_mode)
    if kind is not None:
        raise InputError(field, f"is {kind}, not a regular file: mcbat reads tables from "
                         "regular files only (save the data to a file first)", label)
    return status


class _Stream(Protocol):
    """What a ``CappedReader`` reads from: ``read(n)`` giving bytes."""

    def read(self, n: int, /) -> bytes: ...


class CappedReader:
    """A binary stream (a decompressor) that refuses to give more than ``limit`` bytes.

    Parameters
    ----------
    stream : file-like
        Read with ``read(n)``.
    limit : int
        Bytes it may give in all.
    label : str
        The file, for the error.
    on_disk : int
        The file's size, for the error.
    field : str, optional
        The field the error is about.
    """

    def __init__(self, stream: _Stream, limit: int, label: str, on_disk: int,
                 field: str | None = None) -> None:
        self.stream, self.limit, self.label = stream, int(limit), label
        self.on_disk, self.field, self.given = int(on_disk), field, 0

    @classmethod
    def for_file(cls, stream: _Stream, on_disk: int, label: str,
                 field: str | None = None) -> CappedReader:
        """A reader capped at ``MAX_EXPANSION`` times ``on_disk`` bytes (at least
        ``MIN_EXPANDED_BYTES``)."""
        return cls(stream, max(MAX_EXPANSION * on_disk, MIN_EXPANDED_BYTES), label, on_disk,
                   field)

    def read(self, n: int | None = -1) -> bytes:
        """Up to ``n`` bytes; ``mcbat.errors.InputError`` once the cap is passed."""
        want = self.limit + 1 - self.given if n is None or n < 0 else \
            min(n, self.limit + 1 - self.given)
        block = self.stream.read(max(want, 0))
        self.given += len(block)
        if self.given > self.limit:
            raise InputError(self.field, f"the compressed file ({self.on_disk:,} bytes) "
                             f"expands to more than {self.limit:,} bytes, the most mcbat "
                             f"reads from it ({MAX_EXPANSION} times its size, at least "
                             f"{MIN_EXPANDED_BYTES >> 20} MiB): not a compressed export "
                             "(decompress it yourself if it really is one)", self.label)
        return block


def check_expansion(path: str | os.PathLike[str], label: str | None = None,
                    field: str | None = None) -> None:
    """Read a gzip file through to its end under the cap (``CappedReader``), keeping
    nothing: ``mcbat.errors.InputError`` if it expands beyond the cap or is broken.
    Nothing happens for a file that is not gzip. For readers that would decompress the
    whole file at once (pandas) or read its first line without a limit."""
    import gzip
    import zlib

    label = os.fspath(path) if label is None else label
    status = check_regular_file(path, label, field)
    try:
        with open(path, "rb") as raw:
            if raw.read(2) != b"\x1f\x8b":
                return
            raw.seek(0)
            stream = CappedReader.for_file(gzip.GzipFile(fileobj=raw), status.st_size,
                                           label, field)
            while stream.read(1 << 23):
                pass
    except (OSError, EOFError, zlib.error) as err:
        raise InputError(field, f"cannot read the compressed file: {err}", label) from None


def write_parquet(df: pd.DataFrame, path: str | os.PathLike[str],
                  metadata: dict[bytes, bytes]) -> None:
    """Write ``df`` (without its index) to the Parquet file ``path``, with ``metadata``
    added to its schema's (key: value bytes).

    The file appears complete or not at all: the one atomic writer of mcbat writes it
    (``mcbat.dataset.storage.write_atomic``: a temporary name in the same directory,
    renamed; the temporary file removed if the write fails).
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    from mcbat.dataset.storage import write_atomic

    table = pa.Table.from_pandas(df, preserve_index=False)
    table = table.replace_schema_metadata({**(table.schema.metadata or {}), **metadata})
    write_atomic(Path(os.fspath(path)),
                 lambda fs, tmp: pq.write_table(table, tmp, filesystem=fs))


#: Bytes read (and decompressed) at a time by ``text_lines``.
BLOCK_BYTES = 1 << 23


def text_lines(path: Path, label: str) -> Iterator[str]:
    """The file's lines (``.gz`` decompressed as it is read, with the cap of
    ``mcbat.statcast.files``; UTF-8 with or without a BOM; each line with its newline),
    or ``InputError`` naming the file, and the line and byte of a decoding error."""
    import codecs
    import gzip
    import zlib

    status = check_regular_file(path, label)
    try:
        raw = path.open("rb")
    except OSError as err:
        raise InputError(None, f"cannot read the file: {err.strerror or err}", label) from None
    with raw:
        gz = path.suffix.lower() == ".gz" or raw.peek(2)[:2] == b"\x1f\x8b"
        stream = CappedReader.for_file(gzip.GzipFile(fileobj=raw), status.st_size,
                                       label) if gz else raw
        decoder = codecs.getincrementaldecoder("utf-8-sig")()
        consumed, line, pending, pending_size = 0, 1, [], 0
        while True:
            try:
                block = stream.read(BLOCK_BYTES)
            except (OSError, EOFError, zlib.error) as err:
                raise InputError(None, f"cannot read the file: {err}", label) from None
            try:
                text = decoder.decode(block, final=not block)
            except UnicodeDecodeError as err:
                at = line + block.count(b"\n", 0, max(err.start, 0))
                raise InputError(None, f"line {at}: not UTF-8 text (byte "
                                 f"{consumed + err.start}); a Savant export is a UTF-8 CSV "
                                 "file", label) from None
            consumed += len(block)
            pieces = text.split("\n")
            if len(pieces) > 1:
                pending.append(pieces[0])
                yield "".join(pending) + "\n"
                line += 1
                for piece in pieces[1:-1]:
                    yield piece + "\n"
                    line += 1
                pending, pending_size = [], 0
            pending.append(pieces[-1])
            pending_size += len(pieces[-1])
            if pending_size > MAX_LINE_BYTES:
                raise InputError(None, f"line {line}: longer than {MAX_LINE_BYTES:,} "
                                 "characters without a line break: not a CSV table", label)
            if not block:
                break
        tail = "".join(pending)
        if tail:
            yield tail
