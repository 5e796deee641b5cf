"""Is a dataset directory complete and consistent with its manifest? ``check_dataset``.

The manifest (``_mcbat.json``) says how many chunks the dataset has and, once each one is
written, records its file (rows, bytes, CRC-32 of the bytes; ``mcbat.dataset.chunks``).
A chunk file belongs to the dataset only if it is recorded and matches its record:

- **missing**: a chunk the manifest expects has no file (an interrupted run);
- **extra**: a chunk file the manifest does not expect (an index beyond the last chunk, or
  a file a killed run wrote but never recorded; stray copies);
- **mismatched**: a recorded file whose size, row count, dataset hash or ``sample_id`` range
  differs from what it should be (a chunk copied over another, another dataset's chunk);
  with ``checksums=True`` also one whose bytes no longer give the recorded CRC-32 (bit rot,
  a partial overwrite; the only check that reads every byte).

- **foreign**: an entry a Parquet reader of the directory would read as data that is not a
  chunk file (``chunk-000002 (copy).parquet``, a directory named like a chunk): the
  documented ``pandas.read_parquet(DIR)`` would return its rows too.

``mcbat.load`` runs the cheap checks (file sizes and Parquet footers) and refuses a
dataset with any problem, unless ``allow_partial=True``; ``mcbat check DIR`` runs all of
them. Datasets written before chunk records existed (manifest without ``files``) are checked
by their footers alone and reported as **unverified** (their bytes have no checksum to
compare with), never as verified; rerunning the same ``mcbat run`` records them.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import pyarrow.parquet as pq

from mcbat.dataset import chunks, storage
from mcbat.errors import InputError

__all__ = ["UNVERIFIED", "DatasetCheck", "check_dataset", "chunk_mismatch"]

SUMMARY = "_summary.parquet"  # = mcbat.dataset.summary.SUMMARY (kept light: no numba here)


@dataclass
class DatasetCheck:
    """The result of ``check_dataset``.

    Attributes
    ----------
    directory : Path or str
        The dataset directory.
    manifest : dict
        Its manifest.
    good : dict of int -> location
        The chunk files that belong to the dataset, by chunk index.
    missing : list of int
        Chunks without a file.
    extra : list of str
        Chunk files that do not belong to the dataset.
    mismatched : list of (str, str)
        ``(file name, reason)`` of recorded chunks that do not match their record.
    checksums : bool
        Whether the CRC-32 of every file was verified.
    unverified : bool
        The manifest records no checksums (written by an older mcbat): the files' bytes
        cannot be verified, whatever ``checksums`` asked. Reported, never passed as
        verified; a rerun of the same ``mcbat run`` records them.
    foreign : list of str
        Entries a Parquet reader of the directory would read as data that are not chunk
        files of the dataset (a renamed copy, a directory with a chunk's name).
    summary : str or None
        What is wrong with the ``[summary]`` table of a study that has one (unfinished, or
        not matching its record), None when it is fine or there is none.
    """

    directory: object
    manifest: dict
    good: dict = field(default_factory=dict)
    missing: list = field(default_factory=list)
    extra: list = field(default_factory=list)
    mismatched: list = field(default_factory=list)
    checksums: bool = False
    unverified: bool = False
    foreign: list = field(default_factory=list)
    summary: str | None = None

    @property
    def summary_only(self) -> bool:
        """True for a summary-only run: no rows are expected."""
        return bool(self.manifest.get("summary_only"))

    @property
    def ok(self) -> bool:
        """True when every chunk is present and matches (none is expected of a
        summary-only run), nothing else is there, and the summary table is complete."""
        return not (self.missing or self.extra or self.mismatched or self.foreign
                    or self.summary)

    @property
    def rows_expected(self) -> int:
        """Rows of the complete dataset."""
        return int(self.manifest["samples"])

    @property
    def rows_good(self) -> int:
        """Rows in the chunks that belong to the dataset."""
        size = int(self.manifest["chunk_size"])
        return sum(min(size, self.rows_expected - k * size) for k in self.good)

    def problems(self) -> list[str]:
        """One line per kind of problem (empty when ``ok``)."""
        out = []
        if self.summary:
            out.append(self.summary)
        if self.foreign:
            one = len(self.foreign) == 1
            out.append(f"{len(self.foreign)} entr{'y' if one else 'ies'} that Parquet "
                       "readers of the directory would read as rows but "
                       f"{'is not a chunk file' if one else 'are not chunk files'} of the "
                       f"dataset ({', '.join(self.foreign[:3])}"
                       f"{', ...' if len(self.foreign) > 3 else ''}); move "
                       f"{'it' if one else 'them'} out of the directory")
        if self.missing:
            out.append(f"{len(self.missing)} of {self.manifest['chunks']} chunk(s) missing "
                       f"({_indices(self.missing)}): {self.rows_good:,} of "
                       f"{self.rows_expected:,} rows present; rerun the same `mcbat run` "
                       "to complete it")
        if self.extra:
            out.append(f"{len(self.extra)} chunk file(s) not part of the dataset "
                       f"({', '.join(self.extra[:3])}{', ...' if len(self.extra) > 3 else ''})"
                       "; rerun `mcbat run` to recompute them, or remove them")
        for name, reason in self.mismatched[:3]:
            out.append(f"{name}: {reason}; rerun `mcbat run` to recompute it")
        if len(self.mismatched) > 3:
            out.append(f"... and {len(self.mismatched) - 3} more mismatched chunk file(s)")
        return out

    def first_problem(self) -> str | None:
        """The first problem on one line, naming its file and what is wrong (None when
        ``ok`` and verified): the line ``mcbat check`` ends with on stderr."""
        found = []
        if self.summary:
            found.append(self.summary if self.summary.startswith(SUMMARY)
                         else f"{SUMMARY}: {self.summary}")
        found += [f"{name}: not a chunk file of the dataset, but Parquet readers of the "
                  "directory would read it as rows; move it out of the directory"
                  for name in self.foreign]
        found += [f"{chunks.chunk_name(k)}: missing ({self.rows_good:,} of "
                  f"{self.rows_expected:,} rows present); rerun the same `mcbat run` to "
                  "complete it" for k in self.missing]
        found += [f"{name}: not part of the dataset (beyond its last chunk, or never "
                  "recorded); rerun `mcbat run` to recompute it, or remove it"
                  for name in self.extra]
        found += [f"{name}: {reason}; rerun `mcbat run` to recompute it"
                  for name, reason in self.mismatched]
        if not found and self.unverified:
            found.append(f"{chunks.MANIFEST}: records no checksums (an older mcbat wrote "
                         "it), so changed bytes cannot be detected; rerun the same `mcbat "
                         "run` to recompute and record them")
        if not found:
            return None
        more = len(found) - 1
        return found[0] + (f" (and {more:,} more problem(s), listed above)" if more else "")

    def lines(self) -> list[str]:
        """The report of ``mcbat check``."""
        how = ("sizes and footers only: no checksums recorded" if self.unverified else
               "sizes, footers and CRC-32 of every byte" if self.checksums else
               "sizes and footers")
        stored = self.summary_only and not (self.good or self.missing or self.mismatched)
        head = [f"dataset: {self.directory}",
                f"chunks: {len(self.good)} of {self.manifest['chunks']} good ({how}), "
                f"{self.rows_good:,} of {self.rows_expected:,} rows"
                + (" (a summary-only run: no rows stored)" if stored else "")]
        problems = self.problems()
        if problems:
            return head + problems
        if self.unverified:
            return head + [UNVERIFIED]
        return head + ["ok: complete and consistent with its manifest"]


UNVERIFIED = ("unverified: complete by its sizes and footers, but the manifest records no "
              "checksums (an older mcbat wrote it), so changed bytes cannot be detected; "
              "rerun the same `mcbat run` to recompute and record them")


def _indices(indices) -> str:
    shown = ", ".join(str(k) for k in indices[:5])
    return shown + (", ..." if len(indices) > 5 else "")


def check_dataset(directory, *, checksums: bool = False) -> DatasetCheck:
    """Check the dataset at ``directory`` against its manifest (see the module docs).

    Parameters
    ----------
    directory : str or Path
        A dataset directory or its URL.
    checksums : bool
        Also verify the CRC-32 of every chunk file's bytes (reads every byte).

    Returns
    -------
    DatasetCheck

    Raises
    ------
    InputError
        No such directory, or not an mcbat dataset (no usable manifest).
    """
    directory = storage.location(directory)
    try:
        kind = storage.entry_type(directory)
    except OSError as err:  # an unreachable object store, a permission
        raise InputError(None, f"cannot read the dataset: {err}", str(directory)) from None
    if kind != "dir":
        raise InputError(None, "no such dataset directory", str(directory))
    manifest = chunks.read_manifest(directory)
    if manifest is None:
        raise InputError(None, f"not an mcbat dataset (no {chunks.MANIFEST})",
                         str(directory))
    if not isinstance(manifest, dict) or not all(
            isinstance(manifest.get(key), int) and manifest[key] >= 1
            for key in ("samples", "chunk_size", "chunks")):
        raise InputError(None, f"not an mcbat dataset (unusable {chunks.MANIFEST})",
                         str(directory))
    records = manifest.get("files")  # None: written before chunk records existed
    if records is not None and not isinstance(records, dict):
        raise InputError(None, f"not an mcbat dataset (unusable {chunks.MANIFEST}: 'files' "
                         f"is {type(records).__name__}, not an object)", str(directory))
    result = DatasetCheck(directory, manifest, checksums=checksums,
                          unverified=records is None)
    present = chunks.chunk_files(directory)
    result.foreign = chunks.foreign_entries(directory)
    n_chunks, size = manifest["chunks"], manifest["chunk_size"]
    for k, path in sorted(present.items()):
        name = chunks.chunk_name(k)
        if k >= n_chunks or (records is not None and name not in records):
            result.extra.append(name)
            continue
        rows = min(size, manifest["samples"] - k * size)
        reason = chunk_mismatch(path, k, rows, size, manifest, None if records is None
                                else records[name], checksums)
        if reason is None:
            result.good[k] = path
        else:
            result.mismatched.append((name, reason))
    # Every chunk of the run is expected, except in a summary-only run that stored no rows:
    # a summary-only manifest over chunk files (or their records) of a run that did store
    # them still owes every row, so a chunk missing there is never "complete".
    rows_stored = not result.summary_only or bool(records) or bool(present)
    result.missing = [k for k in range(n_chunks) if k not in present] if rows_stored else []
    result.summary = _summary_problem(directory, manifest, checksums)
    return result


def _summary_problem(directory, manifest, checksums) -> str | None:
    """What is wrong with the summary table of a study with ``[summary]`` (None: fine)."""
    if not isinstance(manifest.get("study"), dict) or manifest["study"].get("summary") is None:
        return None
    summary = manifest.get("summary")
    record = summary.get("table") if isinstance(summary, dict) else None
    if not isinstance(record, dict):
        return ("the [summary] table is not finished; rerun the same `mcbat run` to "
                "complete it")
    path = storage.join(directory, SUMMARY)
    size = storage.file_size(path)
    if size != record.get("bytes"):
        return f"{SUMMARY}: {size} bytes, {record.get('bytes')} recorded; rerun `mcbat run`"
    if checksums and chunks.checksum(storage.read_bytes(path)) != record.get("crc32"):
        return f"{SUMMARY}: checksum mismatch (changed or corrupted); rerun `mcbat run`"
    return None


def chunk_mismatch(path, index, rows, size, manifest, record, checksums) -> str | None:
    """Why chunk file ``path`` is not chunk ``index`` of this dataset (None if it is)."""
    if record is not None:
        if not isinstance(record, dict):
            return "unusable record in the manifest"
        actual = storage.file_size(path)
        if actual != record.get("bytes"):
            return f"{actual} bytes, {record.get('bytes')} recorded"
        if checksums:
            reason = chunks.verify_chunk(path, record)
            if reason is not None:
                return reason
    try:
        meta = chunks.read_metadata(path)
        info = json.loads(meta.metadata[chunks.METADATA_KEY])
    except Exception as err:  # noqa: BLE001 - any unreadable footer is a mismatch
        return f"unreadable Parquet footer ({type(err).__name__})"
    if meta.num_rows != rows:
        return f"{meta.num_rows} rows, {rows} expected"
    if info.get("config_hash") != manifest.get("config_hash"):
        return "a chunk of another dataset (its config hash differs)"
    first, last = _sample_id_range(meta)
    if (first, last) != (index * size, index * size + rows - 1):
        return (f"holds sample_id {first}..{last}, chunk {index} is "
                f"{index * size}..{index * size + rows - 1} (a copy of another chunk?)")
    return None


def _sample_id_range(meta: pq.FileMetaData) -> tuple:
    """``(min, max)`` of ``sample_id`` from the footer's statistics (None if absent)."""
    names = meta.schema.names
    if "sample_id" not in names:
        return None, None
    j = names.index("sample_id")
    lows, highs = [], []
    for i in range(meta.num_row_groups):
        stats = meta.row_group(i).column(j).statistics
        if stats is None or not stats.has_min_max:
            return None, None
        lows.append(stats.min)
        highs.append(stats.max)
    return (min(lows), max(highs)) if lows else (None, None)
