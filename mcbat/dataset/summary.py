"""Summary scans: binned statistics of a run, merged chunk by chunk (``[summary]``).

Each chunk contributes a *partial* (:func:`summarise`: per bin, the row count and, per
summarised column, the non-NaN count, compensated sums, min, max and a log-bucket
histogram; :mod:`mcbat.dataset.binned_stats`). The run merges the partials **in chunk order**
(:class:`SummaryState`), so the result is the same whatever the threads, the engine or the
order in which chunks finish. The merged state of chunks ``[0, merged)`` is saved as
``_summary_state.npz`` (atomically, at most every few seconds, its size and CRC-32 in the
manifest's ``summary`` record): a killed run resumes from it. When every chunk is merged,
the run writes ``_summary.parquet``: one row per bin with

* ``<by>_low``, ``<by>_high`` for each ``by`` column, in the unit the study gave;
* ``count``: the rows in the bin;
* for each summarised column: ``<col>_count`` (its non-NaN values: failed rows have NaN
  outputs and are skipped, as pandas does), ``<col>_mean``, ``<col>_std`` (sample
  standard deviation, ``ddof = 1``), ``<col>_min``, ``<col>_max`` and the quantiles
  ``<col>_p5``, ``<col>_p50``... (``q`` in percent).

Rows outside every bin (or with a NaN ``by`` value) are counted in the table's metadata
(``outside``) and in ``df.attrs["outside"]``, never lost. Quantile resolution: the value of
rank ``floor(q (N - 1))`` (pandas' ``interpolation="lower"``) to within
:data:`mcbat.dataset.binned_stats.ALPHA` relative (0.5 %), or to within
:data:`~mcbat.dataset.binned_stats.MIN_MAGNITUDE` for values smaller than that.
"""

from __future__ import annotations

import io
import json
import zipfile

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from mcbat.dataset import binned_stats as core
from mcbat.dataset import storage
from mcbat.dataset.chunks import checksum, numpy_to_arrow, read_manifest
from mcbat.errors import InputError

__all__ = ["MAX_PARTIAL_BYTES", "STATE", "SUMMARY", "SummaryState", "check_summary_size",
           "load_summary", "quantile_name", "summarise", "summary_table"]

SUMMARY = "_summary.parquet"
STATE = "_summary_state.npz"
#: Largest partial (histograms above all) a chunk may carry.
MAX_PARTIAL_BYTES = 256 * 2**20


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
    return partial


class SummaryState:
    """The merged statistics of chunks ``[0, merged)``, and the partials of later chunks
    that finished early (merged as soon as the chunks before them are)."""

    def __init__(self, spec, total=None, merged=0):
        self.spec = spec
        self.total = total if total is not None else core.allocate_partial(
            spec.n_bins, len(spec.columns), _buckets(spec))
        self.merged = merged
        self.pending = {}

    def add(self, index: int, partial) -> None:
        """Chunk ``index``'s partial; merged in chunk order."""
        if index < self.merged:
            return  # (recomputed after a resume point: already in the total)
        self.pending[index] = partial
        while self.merged in self.pending:
            core.merge_into(self.total, self.pending.pop(self.merged))
            self.merged += 1

    # -------------------------------------------------------------- on disk

    def to_bytes(self) -> bytes:
        """The state as a compressed ``.npz`` file's bytes (what ``np.savez_compressed``
        writes, at deflate level 1: the histograms are mostly zeros, and its default
        level took twice as long, 28 ms against 12 for a 5 MB state, for 20 % less)."""
        buffer = io.BytesIO()
        arrays = {"merged": np.int64(self.merged), **self.total._asdict()}
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
        total = type(fresh.total)(**arrays)
        if any(a.shape != b.shape for a, b in zip(total, fresh.total)):
            return fresh
        return cls(spec, total, merged)


def quantile_name(column: str, q: float) -> str:
    """``exit_speed_p5`` for ``q = 0.05``."""
    return f"{column}_p{q * 100:g}"


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
        ``outside`` (rows in no bin), ``quantile_resolution`` and ``mcbat`` (the manifest).

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
    table = pq.read_table(pa.BufferReader(data))
    meta = json.loads(table.schema.metadata[b"mcbat"])
    df = table.to_pandas()
    df.attrs.update(units=meta.get("units", {}), outside=meta.get("outside"),
                    quantile_resolution={"relative": meta.get("quantile_alpha"),
                                         "absolute_below": meta.get(
                                             "quantile_min_magnitude")},
                    mcbat=manifest)
    return df
