"""``mcbat run --engine dask``: the chunks of a run as tasks on a Dask cluster.

The engine only replaces the loop over the chunks to compute (``mcbat.runner.plan.run_study``
prepares the dataset directory and picks the chunks, as for the local engine). Each chunk
is one task, ``mcbat.runner.engines.dask_tasks.chunk_task``, sent with the study's plain-data
definition, the run's ``mcbat.runner.plan.ChunkJob`` and the chunk index: the worker
draws the inputs itself from (seed, sample index), solves them with the numba kernel and
writes the Parquet file atomically to the dataset directory, which must be storage that
every worker shares (or a URL). Only a small summary comes back, so the data are
identical to a local run's, whatever the number of workers or the order of the tasks.

Threads: a worker process runs one task at a time (``threads_per_worker=1``) and gives
the kernel a budget of numba threads (``numba.set_num_threads`` in every task, since the
setting is per thread; for a local cluster also ``NUMBA_NUM_THREADS`` in the worker's
environment), so that workers x budget never exceeds the cores. A worker plugin loads the
kernel once per worker before its first task (also on a worker that is restarted).

Failures: a task whose worker dies is rescheduled by the Dask scheduler on another worker
(up to ``distributed.scheduler.allowed-failures`` times, default 3); a task that raises is
retried ``RETRIES`` times. Reruns are harmless: a chunk file is written under a
temporary name and renamed, with the same content every time. At the end the engine
removes temporary files a killed worker left behind and checks that every chunk file is
complete. A scheduler that goes away mid-run (killed, or its host lost) ends the run at
once with ``mcbat.errors.EnvironmentFailure`` (the CLI's exit code 4): Dask would
otherwise spend ``distributed.comm.timeouts.connect`` (30 s) trying to reconnect, and the
tasks it held are lost anyway. ``dask`` and ``distributed`` are an optional extra: they (and
``mcbat.runner.engines.dask_tasks``, which needs them) are imported only when this
engine is used, inside its methods.
"""

from __future__ import annotations

import contextlib
import logging
import sys
import uuid

import numba

from mcbat.dataset import chunks
from mcbat.errors import EnvironmentFailure, InputError, Metavar
from mcbat.runner.plan import positive_int, remove_temporary_files, write_error

__all__ = ["INSTALL_HINT", "RETRIES", "DaskEngine", "require_distributed"]

INSTALL_HINT = "needs the optional Dask extra; install it with pip install 'mcbat[dask]'"
#: Automatic retries of a chunk task that raised (a transient storage error, say).
RETRIES = 2


def require_distributed():
    """Import ``distributed``, or explain in one line how to install it."""
    try:
        import distributed
    except ImportError:
        raise InputError("engine", INSTALL_HINT) from None
    return distributed


class DaskEngine:
    """Compute a run's chunks on a Dask cluster.

    Parameters
    ----------
    scheduler : str, optional
        Address of a running scheduler (``tcp://host:8786``) to join. Its workers should
        run one task at a time (``dask worker ADDRESS --nthreads 1``).
    workers : int, optional
        Without ``scheduler``: start a ``LocalCluster`` of this many worker processes on
        127.0.0.1 (default: one per core).
    threads : int, optional
        Numba threads per worker. Default: the cores divided among the local cluster's
        workers, or 1 per worker of a joined cluster (one worker process per core). A
        worker uses at most its own ``NUMBA_NUM_THREADS`` (its core count by default).

    Raises
    ------
    InputError
        Bad options, or Dask not installed; before anything is started or written.
    """

    name = "dask"

    def __init__(self, *, scheduler=None, workers=None, threads=None):
        require_distributed()  # first: without Dask, the install hint is what helps
        if scheduler is not None and workers is not None:
            raise InputError("workers", "give either {scheduler} (join a running cluster) or "
                             "{workers} (start a local one), not both",
                             mentions={"scheduler": Metavar("ADDRESS"),
                                       "workers": Metavar("N")})
        if scheduler is not None and (not isinstance(scheduler, str) or not scheduler.strip()):
            raise InputError("scheduler", "must be a scheduler address like "
                             f"tcp://host:8786, got {scheduler!r}")
        if threads is not None:
            threads = positive_int(threads, "threads")
        cores = numba.config.NUMBA_NUM_THREADS
        if scheduler is None:
            workers = cores if workers is None else positive_int(workers, "workers")
            budget = threads if threads is not None else max(1, cores // workers)
            if workers * budget > cores:
                flag = "threads" if threads is not None else "workers"
                raise InputError(flag, f"{workers} worker process(es) x {budget} numba "
                                 f"thread(s) would oversubscribe the {cores} cores of this "
                                 "machine")
            threads = budget
        elif threads is None:
            threads = 1
        self.scheduler = scheduler.strip() if scheduler is not None else None
        self.workers = workers
        self.threads = threads
        self.client = None

    # ------------------------------------------------------------ the cluster

    @contextlib.contextmanager
    def connect(self):
        """Start the local cluster or join the scheduler, and warm the workers."""
        from distributed import Client, LocalCluster

        from mcbat.runner.engines.dask_tasks import WarmUp

        cluster = client = None
        try:
            if self.scheduler is None:
                import dask

                # The workers' statistical profiler samples the task thread every 10 ms,
                # for a dashboard we do not start: off, it gave a few per cent more rows/s
                # on 2 cores (benchmarks/bench_dask.py).
                with dask.config.set({"distributed.worker.profile.enabled": False}):
                    cluster = self._local_cluster(LocalCluster)
                client = Client(cluster)
            else:
                try:
                    client = Client(self.scheduler)
                except (OSError, ValueError, TypeError) as err:
                    raise InputError("scheduler", f"cannot connect to {self.scheduler}: "
                                     f"{err}") from None
                if not client.nthreads():
                    print(f"mcbat: waiting for workers to join {self.scheduler} "
                          "(start them with: dask worker ADDRESS --nthreads 1)",
                          file=sys.stderr)
            try:
                client.register_plugin(WarmUp(self.threads), name=WarmUp.name)
            except Exception as err:  # noqa: BLE001 - a worker without a usable mcbat
                raise InputError("scheduler", f"a worker could not load mcbat "
                                 f"({type(err).__name__}: {err}); every worker needs the "
                                 "client's environment") from None
            self.client = client
            yield self
        finally:
            self.client = None
            if client is not None:
                if client.status == "running":
                    with contextlib.suppress(Exception):
                        client.unregister_worker_plugin(WarmUp.name)
                    client.close()
                else:  # the scheduler went away: do not wait for Dask's reconnection,
                    # and keep the reconnection attempt we cut short from logging its
                    # tracebacks (the user gets one line: EnvironmentFailure)
                    quiet = logging.getLogger("distributed.client")
                    level, quiet.level = quiet.level, logging.CRITICAL + 1
                    try:
                        with contextlib.suppress(Exception):
                            client.close(timeout=1)
                    finally:
                        quiet.setLevel(level)
            if cluster is not None:
                cluster.close()

    def ready(self, study, job, display):
        """Load (or compile) the study's kernels on every worker before the clock starts,
        one task per worker, as the local engine does in its process: the game kernel for
        a game study, the bat-frame kernel for a drop-test study, never both. (A worker
        that joins later loads them in its first chunk.) A worker that cannot compute
        the run's chunks says so here, as its first chunk would."""
        from mcbat.runner.engines.dask_tasks import warm_study

        definition = study.definition()
        futures = [self.client.submit(warm_study, definition, job, self.threads,
                                      workers=[worker], allow_other_workers=False,
                                      pure=False, key=f"mcbat-ready-{uuid.uuid4().hex[:8]}")
                   for worker in self.client.scheduler_info()["workers"]]
        for future in futures:
            try:
                self._result(future, display)
            except Exception:
                if self._scheduler_lost():
                    raise self._lost_scheduler() from None
                raise

    def _local_cluster(self, LocalCluster):
        return LocalCluster(
            n_workers=self.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
            # The scheduler serves HTTP even without a dashboard, on 8787 when given None:
            # a free port on the loopback never meets the user's own cluster (nor warns).
            dashboard_address="127.0.0.1:0", silence_logs=logging.CRITICAL,
            # Sizes the worker's numba pool to the budget, if numba is imported after the
            # worker starts (so with the mcbat command; a __main__ that imports numba is
            # re-imported first by the spawned worker). The budget itself is enforced in
            # every task (set_numba_threads).
            env={"NUMBA_NUM_THREADS": str(self.threads)})

    # ------------------------------------------------------------ the chunks

    def run(self, study, job, todo, display):
        """Submit one task per chunk in ``todo``; yield their summaries as they finish."""
        from distributed import as_completed

        from mcbat.runner.engines.dask_tasks import chunk_task

        if not todo:
            return
        token = uuid.uuid4().hex[:8]
        keys = [f"mcbat-chunk-{k:06d}-{token}" for k in todo]
        futures = self.client.map(chunk_task, todo, key=keys, definition=study.definition(),
                                  job=job, threads=self.threads, retries=RETRIES, pure=False)
        try:
            for future in as_completed(futures):
                try:
                    summary = self._result(future, display)
                except Exception:
                    if self._scheduler_lost():
                        raise self._lost_scheduler() from None
                    raise
                future.release()
                yield summary
        finally:
            if self.client.status == "running":
                self.client.cancel(futures)
        # Every task has returned, so a temporary chunk file left now was being written by
        # a worker that was killed (its chunk was recomputed elsewhere).
        remove_temporary_files(job.out)
        for k in [] if job.summary_only else todo:
            if not chunks.chunk_is_complete(job.path(k), job.rows(k), job.config_hash):
                raise RuntimeError(f"chunk {k} was reported written but {job.path(k)} is not "
                                   "a complete chunk file")

    @staticmethod
    def _result(future, display):
        """A finished chunk task's summary, its failure as the error a user can act on."""
        from distributed.comm import CommClosedError
        from distributed.scheduler import KilledWorker

        from mcbat.runner.engines.dask_tasks import WorkerSetupError

        try:
            return future.result()
        except CommClosedError:
            raise  # the connection, not the disk (run() tells a lost scheduler apart)
        except OSError as err:
            raise write_error(err, display) from None
        except WorkerSetupError as err:
            raise InputError(err.field, err.message) from None
        except KilledWorker as err:
            raise RuntimeError(
                f"a chunk task was lost with {err.allowed_failures + 1} workers in a row "
                "(each died while computing it); complete chunk files are kept, rerun to "
                "resume") from None

    def _scheduler_lost(self, wait=2.0) -> bool:
        """True if the client lost its scheduler: a failed task result can arrive a moment
        before the client notices the closed connection, so look for ``wait`` seconds."""
        import time

        deadline = time.monotonic() + wait
        while True:
            comm = self.client.scheduler_comm
            if self.client.status != "running" or comm is None or comm.closed():
                return True
            if time.monotonic() > deadline:
                return False
            time.sleep(0.05)

    def _lost_scheduler(self):
        where = self.scheduler or "the local cluster's scheduler"
        return EnvironmentFailure(
            f"lost the connection to the Dask scheduler ({where}); complete chunk files "
            "are kept: restart the scheduler and its workers and rerun the same command to "
            "resume")

    def note(self, summaries) -> str:
        """One line on where the chunks were computed."""
        workers = {s.worker for s in summaries}
        threads = sorted({s.threads for s in summaries})
        where = (f"local cluster of {self.workers} worker process(es)"
                 if self.scheduler is None else f"scheduler {self.scheduler}")
        return (f"engine: dask, {where}: {len(summaries)} chunk(s) computed by "
                f"{len(workers)} worker process(es), "
                f"{'/'.join(map(str, threads))} numba thread(s) each")
