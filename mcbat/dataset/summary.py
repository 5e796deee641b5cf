"""Summary scans: binned statistics of a run, merged chunk by chunk (``[summary]``).

Each chunk contributes a *partial* (``summarise``: per bin, the row count and, per
summarised column, the non-NaN count, compensated sums, min, max and a log-bucket
histogram; ``mcbat.dataset.binned_stats``). The run merges the partials **in chunk order**
(``SummaryState``), so the result is the same whatever the threads, the engine or the
order in which chunks finish. The merged state of chunks ``[0, merged)`` is saved as
``_summary_state.npz`` (atomically, at most every few seconds, its size and CRC-32 in the
manifest's ``summary`` record): a killed run resumes from it. When every chunk is merged,
the run writes ``_summary.parquet``: one row per bin with

* ``<by>_low``, ``<by>_high`` for each ``by`` column, in the unit the study gave;
* ``count``: the rows in the bin;
* for each summarised column: ``<col>_count`` (its non-NaN values: failed rows have NaN
  outputs and are skipped, as pandas does), ``<col>_mean``, ``<col>_std`` (sample
  standard deviation, ``ddof = 1``), ``<col>_min``, ``<col>_max`` and the quantiles
  ``<col>_p5``, ``<col>_p50``... (``q`` in percent);
* for each ``share_above`` threshold ``t`` of a column: ``<col>_above_<t>_count`` (its
  values strictly above ``t``), ``<col>_above_<t>`` (their share of ``<col>_count``) and
  ``<col>_above_<t>_err`` (the share's binomial error ``sqrt(p (1 - p) / n)``; 0 when
  every value or none is above: read the counts then). Counts are integers, merged
  exactly, so the shares too do not depend on the chunking.

Rows outside every bin (or with a NaN ``by`` value) are counted in the table's metadata
(``outside``) and in ``df.attrs["outside"]``, never lost. Quantile resolution: the value of
rank ``floor(q (N - 1))`` (pandas' ``interpolation="lower"``) to within
``mcbat.dataset.binned_stats.ALPHA`` relative (0.5 %), or to within
``mcbat.dataset.binned_stats.MIN_MAGNITUDE`` for values smaller than that.
"""

from __future__ import annotations

import io
import json
import zipfile
from typing import NamedTuple

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from mcbat.dataset import binned_stats as core
from mcbat.dataset import storage
from mcbat.dataset.chunks import checksum, numpy_to_arrow, read_manifest
from mcbat.dataset.load import units_of
from mcbat.errors import InputError

__all__ = ["MAX_PARTIAL_BYTES", "STATE", "SUMMARY", "ChunkPartial", "SummaryState",
           "check_summary_size", "load_summary", "quantile_name", "share_name", "shares",
           "summarise", "summary_table"]

SUMMARY = "_summary.parquet"
STATE = "_summary_state.npz"
#: Largest partial (histograms above all) a chunk may carry.
MAX_PARTIAL_BYTES = 256 * 2**20


class ChunkPartial(NamedTuple):
    """One chunk's share of the summary: the binned statistics and, per bin and
    ``share_above`` threshold, the count of values above it (int64[B, t])."""

    stats: core.SummaryPartial
    above: np.ndarray


def _buckets(spec) -> int:
    return core.n_buckets() if spec.quantiles else 0


def check_summary_size(spec) -> None:
    """Refuse a ``[summary]`` whose per-chunk partial would not fit in memory."""
    size = core.partial_bytes(spec.n_bins, len(spec.columns), _buckets(spec))
    if size > MAX_PARTIAL_BYTES:
        raise InputError("summary.by", f"{spec.n_bins:,} bins x {len(spec.columns)} columns "
                         f"with quantiles need {size / 2**20:,.0f} MB per chunk (at most "
                         f"{MAX_PARTIAL_BYTES // 2**20} MB): use fewer bins or columns, or no "
                         "quantiles")


def summarise(spec, cols: dict):
    """The partial statistics of one chunk's columns ``cols`` (name -> array)."""
    n = len(cols["status"])
    by = np.empty((len(spec.by), n))
    for i, axis in enumerate(spec.by):
        by[i] = cols[axis.name]
    values = np.empty((len(spec.columns), n))
    for j, name in enumerate(spec.columns):
        values[j] = cols[name]
    index = np.empty(n, np.int64)
    core.bin_rows(by, np.array([a.low for a in spec.by]), np.array([a.high for a in spec.by]),
                  np.array([a.bins for a in spec.by], np.int64), index)
    partial = core.allocate_partial(spec.n_bins, len(spec.columns), _buckets(spec))
    core.accumulate(index, values, partial)
    return ChunkPartial(partial, _count_above(spec, index, cols))


def _shares(spec) -> tuple:
    return getattr(spec, "share_above", ())


def _count_above(spec, index, cols) -> np.ndarray:
    """Per bin, the values of each ``share_above`` column strictly above its threshold
    (NaN is never above; rows outside every bin are not counted)."""
    shares = _shares(spec)
    above = np.zeros((spec.n_bins, len(shares)), np.int64)
    inside = index >= 0
    for k, (name, threshold) in enumerate(shares):
        hit = inside & (np.asarray(cols[name], np.float64) > threshold)
        above[:, k] = np.bincount(index[hit], minlength=spec.n_bins)
    return above


class SummaryState:
    """The merged statistics of chunks ``[0, merged)``, and the partials of later chunks
    that finished early (merged as soon as the chunks before them are)."""

    def __init__(self, spec, total=None, merged=0, above=None):
        self.spec = spec
        self.total = total if total is not None else core.allocate_partial(
            spec.n_bins, len(spec.columns), _buckets(spec))
        self.above = (above if above is not None
                      else np.zeros((spec.n_bins, len(_shares(spec))), np.int64))
        self.merged = merged
        self.pending = {}

    def add(self, index: int, partial: ChunkPartial) -> None:
        """Chunk ``index``'s partial; merged in chunk order."""
        if index < self.merged:
            return  # (recomputed after a resume point: already in the total)
        self.pending[index] = partial
        while self.merged in self.pending:
            stats, above = self.pending.pop(self.merged)
            core.merge_into(self.total, stats)
            self.above += above
            self.merged += 1

    # -------------------------------------------------------------- on disk

    def to_bytes(self) -> bytes:
        """The state as a compressed ``.npz`` file's bytes (what ``np.savez_compressed``
        writes, at deflate level 1: the histograms are mostly zeros, and its default
        level took twice as long, 28 ms against 12 for a 5 MB state, for 20 % less)."""
        buffer = io.BytesIO()
        arrays = {"merged": np.int64(self.merged), **self.total._asdict(),
                  "share_above": self.above}
        with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED, compresslevel=1) as archive:
            for name, value in arrays.items():
                with archive.open(f"{name}.npy", "w", force_zip64=True) as member:
                    np.lib.format.write_array(member, np.asarray(value), allow_pickle=False)
        return buffer.getvalue()

    def save(self, out) -> dict:
        """Write the state atomically; returns its manifest record."""
        data = self.to_bytes()
        storage.write_bytes_atomic(data, storage.join(out, STATE))
        return {"merged": self.merged, "bytes": len(data), "crc32": checksum(data)}

    @classmethod
    def resume(cls, spec, out, record) -> SummaryState:
        """The saved state if it matches its manifest ``record``, else a fresh one (the
        run then recomputes every chunk's partial)."""
        fresh = cls(spec)
        if not isinstance(record, dict):
            return fresh
        try:
            data = storage.read_bytes(storage.join(out, STATE))
        except OSError:
            return fresh
        if len(data) != record.get("bytes") or checksum(data) != record.get("crc32"):
            return fresh
        with np.load(io.BytesIO(data)) as saved:
            arrays = {name: saved[name] for name in fresh.total._fields}
            merged = int(saved["merged"])
            above = (saved["share_above"] if "share_above" in saved.files
                     else np.zeros((spec.n_bins, 0), np.int64))
        total = type(fresh.total)(**arrays)
        if (any(a.shape != b.shape for a, b in zip(total, fresh.total))
                or above.shape != fresh.above.shape):
            return fresh
        return cls(spec, total, merged, above)


def quantile_name(column: str, q: float) -> str:
    """``exit_speed_p5`` for ``q = 0.05``."""
    return f"{column}_p{q * 100:g}"


def share_name(column: str, threshold: float) -> str:
    """``hit_distance_above_380`` for the share of ``hit_distance`` above 380."""
    return f"{column}_above_{threshold:g}"


def _share(above, n):
    """The share ``above / n`` and its binomial error (NaN where ``n`` is 0)."""
    above, n = np.asarray(above, np.float64), np.asarray(n, np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):
        p = np.where(n > 0, above / n, np.nan)
        err = np.where(n > 0, np.sqrt(p * (1.0 - p) / n), np.nan)
    return p, err


def shares(spec, state: SummaryState) -> list:
    """Each ``share_above`` threshold over every bin together (rows outside every bin
    left out): dicts of ``column``, ``above`` (the threshold, in the column's stored
    ``unit``), ``unit``, ``count`` (values above it), ``n`` (the column's values), ``share`` and
    ``error`` (binomial, ``sqrt(p (1 - p) / n)``; None when ``n`` is 0)."""
    out = []
    for k, (name, threshold) in enumerate(_shares(spec)):
        j = spec.columns.index(name)
        above, n = int(state.above[:, k].sum()), int(state.total.n[:, j].sum())
        p, err = _share(above, n)
        out.append({"column": name, "above": threshold,
                    "unit": units_of([name]).get(name), "count": above, "n": n,
                    "share": None if n == 0 else float(p), "error": None if n == 0
                    else float(err)})
    return out


def summary_table(spec, state: SummaryState, metadata: dict) -> pa.Table:
    """The final table: one row per bin (row-major over the ``by`` axes)."""
    total = state.total
    arrays, names = [], []
    grids = np.meshgrid(*[np.arange(a.bins) for a in spec.by], indexing="ij")
    for axis, grid in zip(spec.by, grids):
        width = (axis.high_given - axis.low_given) / axis.bins
        i = grid.ravel()
        arrays += [numpy_to_arrow(axis.low_given + i * width), numpy_to_arrow(axis.low_given
                                                                 + (i + 1) * width)]
        names += [f"{axis.name}_low", f"{axis.name}_high"]
    arrays.append(numpy_to_arrow(np.asarray(total.count, np.int64)))
    names.append("count")
    stats = core.finalize(total, np.array(spec.quantiles, np.float64))
    for j, column in enumerate(spec.columns):
        arrays.append(numpy_to_arrow(np.asarray(stats.n[:, j], np.int64)))
        names.append(f"{column}_count")
        for stat in ("mean", "std", "min", "max"):
            arrays.append(numpy_to_arrow(getattr(stats, stat)[:, j]))
            names.append(f"{column}_{stat}")
        for k, q in enumerate(spec.quantiles):
            arrays.append(numpy_to_arrow(stats.quantiles[:, j, k]))
            names.append(quantile_name(column, q))
    units = dict(metadata.get("units") or {})
    for k, (column, threshold) in enumerate(_shares(spec)):
        name = share_name(column, threshold)
        p, err = _share(state.above[:, k], stats.n[:, spec.columns.index(column)])
        arrays += [numpy_to_arrow(np.asarray(state.above[:, k], np.int64)),
                   numpy_to_arrow(p), numpy_to_arrow(err)]
        names += [f"{name}_count", name, f"{name}_err"]
        units.update({f"{name}_count": "1", name: "1", f"{name}_err": "1"})
    if _shares(spec):
        metadata = {**metadata, "units": units, "share_above": shares(spec, state)}
    table = pa.Table.from_arrays(arrays, names=names)
    return table.replace_schema_metadata({b"mcbat": json.dumps(metadata, sort_keys=True)})


def write_summary(out, spec, state: SummaryState, metadata: dict) -> dict:
    """Write ``_summary.parquet`` atomically; returns its manifest record."""
    table = summary_table(spec, state, {**metadata, "outside": int(state.total.outside[0]),
                                        "quantile_alpha": core.ALPHA,
                                        "quantile_min_magnitude": core.MIN_MAGNITUDE})
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink, compression="zstd")
    data = sink.getvalue()
    storage.write_bytes_atomic(data, storage.join(out, SUMMARY))
    return {"rows": table.num_rows, "bytes": data.size, "crc32": checksum(data)}


def load_summary(directory):
    """The ``_summary.parquet`` of a run with a ``[summary]`` section, as a DataFrame.

    Returns
    -------
    pandas.DataFrame
        One row per bin (see the module docstring); ``df.attrs``: ``units`` (of the bin
        edges as given in the study, and of the statistics: the columns' stored units),
        ``outside`` (rows in no bin), ``quantile_resolution``, ``mcbat`` (the manifest)
        and, with ``share_above``, ``share_above``: each threshold's share over every bin
        together (``shares``).

    Raises
    ------
    InputError
        Not a dataset, a run without ``[summary]``, an unfinished summary, or a file that
        does not match its manifest record.
    """
    location = storage.location(directory)
    manifest = read_manifest(location)
    if not isinstance(manifest, dict):
        raise InputError(None, "not an mcbat dataset (no manifest)", str(directory))
    record = (manifest.get("summary") or {}).get("table")
    if manifest.get("study", {}).get("summary") is None:
        raise InputError(None, "this dataset's study has no [summary] section",
                         str(directory))
    if not isinstance(record, dict):
        raise InputError(None, "the summary is not finished (rerun `mcbat run` to "
                         "complete it)", str(directory))
    try:
        data = storage.read_bytes(storage.join(location, SUMMARY))
    except OSError as err:
        raise InputError(None, f"{SUMMARY}: {err}", str(directory)) from None
    if len(data) != record.get("bytes") or checksum(data) != record.get("crc32"):
        raise InputError(None, f"{SUMMARY} does not match the manifest (changed or "
                         "corrupted); rerun `mcbat run` to rewrite it", str(directory))
    table = pq.ParquetFile(pa.BufferReader(data)).read()  # (no dataset scanner: load)
    meta = json.loads(table.schema.metadata[b"mcbat"])
    df = table.to_pandas()
    if "share_above" in meta:
        df.attrs["share_above"] = meta["share_above"]
    df.attrs.update(units=meta.get("units", {}), outside=meta.get("outside"),
                    quantile_resolution={"relative": meta.get("quantile_alpha"),
                                         "absolute_below": meta.get(
                                             "quantile_min_magnitude")},
                    mcbat=manifest)
    return df
