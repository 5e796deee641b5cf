"""What every chunk of one run shares (``ChunkJob``) and what computing one returns
(``ChunkSummary``): small, picklable records the engines pass around
(``mcbat.runner.plan`` makes the job)."""

from __future__ import annotations

from dataclasses import dataclass

from mcbat.dataset import chunks, storage
from mcbat.study.output import OutputSpec, SummarySpec

__all__ = ["ChunkJob", "ChunkSummary"]


@dataclass(frozen=True)
class ChunkJob:
    """What every chunk of one run shares. Small and picklable: the Dask engine sends it,
    with the study's plain-data definition and a chunk index, to the workers.

    Attributes
    ----------
    out : str
        Dataset directory: an absolute local path or a URL.
    samples, seed, chunk_size : int
        The run's sample count, seed and rows per chunk.
    config_hash : str
        ``dataset_hash`` of the run; stored in every chunk file.
    metadata : dict
        JSON-serialisable dataset metadata stored in every chunk file's schema.
    output : mcbat.study.output.OutputSpec
        The columns written and their precision (``[output]``).
    summary : mcbat.study.output.SummarySpec or None
        The binned statistics each chunk contributes (``[summary]``), names checked and
        bounds in the columns' stored units.
    summary_only : bool
        Compute the summary without writing the rows.
    """

    out: str
    samples: int
    seed: int
    chunk_size: int
    config_hash: str
    metadata: dict
    output: OutputSpec = OutputSpec()
    summary: SummarySpec | None = None
    summary_only: bool = False

    @property
    def chunks(self) -> int:
        """Number of chunks of the dataset."""
        return -(-self.samples // self.chunk_size)

    def bounds(self, index: int) -> tuple[int, int]:
        """``(start, stop)``: the sample indices of chunk ``index``."""
        start = index * self.chunk_size
        return start, min(self.samples, start + self.chunk_size)

    def rows(self, index: int) -> int:
        """Number of rows of chunk ``index``."""
        start, stop = self.bounds(index)
        return stop - start

    def path(self, index: int):
        """Location of the Parquet file of chunk ``index``."""
        return storage.join(self.out, chunks.chunk_name(index))


@dataclass(frozen=True)
class ChunkSummary:
    """What computing one chunk returns (small: no arrays).

    Attributes
    ----------
    index, rows : int
        The chunk and its number of rows.
    status_counts : tuple of int
        Rows per status code (``mcbat.core.status.STATUS_NAMES``).
    threads : int
        Numba threads the kernel ran with.
    worker : str
        ``host:pid`` of the process that computed it.
    file : dict or None
        The chunk file's manifest record (``{"rows", "bytes", "crc32"}``,
        ``mcbat.dataset.chunks.write_chunk``) once it is written; None while the
        local engine's writer thread still writes it, and in a summary-only run.
    partial : mcbat.dataset.binned_stats.SummaryPartial or None
        The chunk's share of the ``[summary]`` statistics.
    """

    index: int
    rows: int
    status_counts: tuple
    threads: int
    worker: str
    file: dict | None = None
    partial: object = None
