"""The dataset directory of a run: prepared (created, or checked to hold this very
dataset; foreign data never lost), the chunks still to compute, and the temporary files a
killed run left.

Errors name the Python parameters (``out``); the CLI maps them to flags.
"""

from __future__ import annotations

import json

from mcbat.dataset import chunks, storage
from mcbat.dataset.check import chunk_mismatch
from mcbat.dataset.lock import LOCK_NAME
from mcbat.dataset.summary import STATE, SUMMARY
from mcbat.errors import InputError
from mcbat.runner.job import ChunkJob

__all__ = ["chunks_to_compute", "prepare_directory", "remove_temporary_files"]


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
    bytes, ``mcbat.dataset.chunks.verify_chunk``). ``redone`` lists ``(index, reason)``
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
