"""Running studies: the plan, the engines, and ``run_study``.

Imports go one way: ``mcbat.runner.plan`` (the chunks; with
``mcbat.runner.job``, ``mcbat.runner.directory`` and
``mcbat.runner.chunk_run``, ``run_chunk``) <-
``mcbat.runner.engines`` (local, dask) <- ``mcbat.runner.study_run``
(``run_study``). ``mcbat.runner.frame`` solves a DataFrame in memory.

(The package is ``runner`` rather than ``run`` because ``mcbat.run`` is the front door's
function, which a subpackage of that name would shadow once imported.)
"""

from mcbat.runner.frame import solve_frame
from mcbat.runner.plan import ChunkJob, ChunkSummary, plan_run, run_chunk
from mcbat.runner.study_run import RunSummary, run_study

__all__ = ["ChunkJob", "ChunkSummary", "RunSummary", "plan_run", "run_chunk", "run_study",
           "solve_frame"]
