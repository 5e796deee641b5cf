"""Engines: where the chunks of a run are computed.

An engine only executes a todo list of chunks with ``mcbat.runner.plan.run_chunk``;
the plan, the directory checks and the bookkeeping are the same for all of them
(``mcbat.runner.study_run.run_study``). The data do not depend on the engine.

``local`` (``mcbat.runner.engines.local``)
    This process: numba threads solve, a writer thread writes the previous chunk.
``dask`` (``mcbat.runner.engines.dask``)
    One task per chunk on a Dask cluster (optional extra ``mcbat[dask]``).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import AbstractContextManager
from typing import Protocol

from mcbat.runner.plan import ChunkJob, ChunkSummary

__all__ = ["Engine"]


class Engine(Protocol):
    """What ``mcbat.runner.study_run.run_study`` needs of an engine."""

    name: str

    def connect(self) -> AbstractContextManager:
        """Start or join whatever computes the chunks, for the duration of the run."""

    def ready(self, study, job: ChunkJob, display) -> None:
        """Load the study's kernels where the chunks will be computed, before the run's
        clock starts (rows/s measure the same thing for every engine)."""

    def run(self, study, job: ChunkJob, todo: list, display) -> Iterator[ChunkSummary]:
        """Compute and write the chunks ``todo``; yield a summary as each completes."""

    def note(self, summaries: list) -> str | None:
        """One line on where the chunks were computed, or None."""
