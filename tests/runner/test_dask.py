"""`mcbat run --engine dask`: the datasets are the local engine's, file for file, on a
LocalCluster of worker processes and on a real `dask scheduler` with `dask worker`
processes, also when a worker is killed mid-run; bad options and a missing Dask are clear
one-line errors that write nothing.

The clusters run on 127.0.0.1 with free ports; every process a test starts is stopped by
its fixture (process groups, SIGTERM then SIGKILL).
"""

import contextlib
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numba
import pandas as pd
import pytest

import mcbat
from mcbat.dataset import chunks as ds
from mcbat.runner import plan_run, run_study
from mcbat.runner.plan import prepare_directory
from mcbat.study import load_study
from tests.cli_runner import mcbat_main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "studies" / "example.toml"
THROUGHPUT = ROOT / "studies" / "throughput.toml"
CROSS_NATHAN = ROOT / "studies" / "cross_nathan_2006.toml"
TIMEOUT = 300  # s, for any one command: a hang fails the test instead of the CI job
INSTALL_HINT = ("mcbat: error: --engine: needs the optional Dask extra; install it "
                "with pip install 'mcbat[dask]'")


def mcbat_cli(*args, cwd=None, env=None):
    return subprocess.run([sys.executable, "-m", "mcbat.cli", *map(str, args)],
                          capture_output=True, text=True, check=False, cwd=cwd,
                          env=None if env is None else {**os.environ, **env}, timeout=TIMEOUT)


@pytest.fixture(scope="module")
def dask_installed():
    pytest.importorskip("distributed")  # a guard only: CI installs ".[test,dask]"


_REFERENCES = {}


def local_reference(tmp_path_factory, study_path, samples, seed, chunk_size):
    """The local engine's dataset for these arguments (computed once per test run)."""
    key = (study_path, samples, seed, chunk_size)
    if key not in _REFERENCES:
        out = tmp_path_factory.mktemp("local") / "ds"
        run_study(load_study(study_path), out, samples=samples, seed=seed,
                  chunk_size=chunk_size, progress=False)
        _REFERENCES[key] = out
    return _REFERENCES[key]


def assert_same_dataset(got, reference):
    """Exactly the reference's files (one per chunk, the manifest, no temporary or extra
    file), each byte for byte, and the same rows in every column."""
    names = sorted(p.name for p in Path(got).iterdir())
    assert names == sorted(p.name for p in Path(reference).iterdir())
    for name in names:
        assert (Path(got) / name).read_bytes() == (Path(reference) / name).read_bytes(), name
    a, b = mcbat.load(got), mcbat.load(reference)
    assert a["sample_id"].is_unique and len(a) == a.attrs["mcbat"]["samples"]
    pd.testing.assert_frame_equal(a, b, check_exact=True)


def engine_note(stdout):
    """(worker processes, numba threads) from the run summary's engine line."""
    match = re.search(r"computed by (\d+) worker process\(es\), ([\d/]+) numba thread",
                      stdout)
    assert match, stdout
    return int(match.group(1)), match.group(2)


def chunk_of(key):
    return int(re.search(r"chunk-(\d{6})", str(key)).group(1))


def _stop(run):
    """Kill a `mcbat run` process a test started, if it is still running."""
    if run is not None and run.poll() is None:
        run.kill()
        run.wait()


class ExternalCluster:
    """A `dask scheduler` and `dask worker` processes on 127.0.0.1, started the way they
    are on a real cluster (each worker: one process under a nanny, one thread)."""

    def __init__(self, directory: Path, n_workers=2):
        from distributed import Client

        self.directory = directory
        directory.mkdir(parents=True)
        self.procs = []
        scheduler_file = directory / "scheduler.json"
        self._start("scheduler", "scheduler", "--host", "127.0.0.1", "--port", "0",
                    "--no-dashboard", "--scheduler-file", scheduler_file)
        deadline = time.monotonic() + 60
        self.address = None
        while self.address is None:
            assert time.monotonic() < deadline, "the scheduler did not start"
            assert self.procs[0].poll() is None, self.log("scheduler")
            try:
                self.address = json.loads(scheduler_file.read_text())["address"]
            except (OSError, ValueError, KeyError):
                time.sleep(0.1)
        for i in range(n_workers):
            self._start(f"worker{i}", "worker", self.address, "--nworkers", "1",
                        "--nthreads", "1", "--host", "127.0.0.1", "--no-dashboard",
                        "--local-directory", directory / f"scratch{i}")
        with Client(self.address, timeout=30) as client:
            client.wait_for_workers(n_workers, timeout=120)

    def _start(self, name, *args):
        with open(self.directory / f"{name}.log", "w") as log:
            # The real `dask` command line (python -m dask == the `dask` script). Own
            # process group: close() stops a nanny together with its worker process.
            self.procs.append(subprocess.Popen(
                [sys.executable, "-m", "dask", *map(str, args)], stdout=log,
                stderr=subprocess.STDOUT, cwd=self.directory, process_group=0))

    def log(self, name):
        return (self.directory / f"{name}.log").read_text()

    def close(self):
        for proc in reversed(self.procs):
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)
        for proc in self.procs:
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()


@pytest.fixture(scope="module")
def cluster(dask_installed, tmp_path_factory):
    started = ExternalCluster(tmp_path_factory.mktemp("cluster") / "dask")
    yield started
    started.close()


# ---------------------------------------------------------------- identical datasets


def test_local_cluster_of_two_worker_processes_gives_the_local_dataset(
        dask_installed, tmp_path, tmp_path_factory, capsys):
    args = ("--samples", 48_000, "--seed", 5, "--chunk-size", 6_000)
    # Dask's default HTTP port held, as another cluster's dashboard would hold it: the run
    # must neither clash with it nor warn about it.
    with socket.socket() as taken, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with contextlib.suppress(OSError):  # already held by something else: as good
            taken.bind(("127.0.0.1", 8787))
            taken.listen()
        code, stdout, stderr = mcbat_main(capsys, "run", THROUGHPUT, "--out", tmp_path / "ds",
                                          *args, "--quiet", "--engine", "dask", "--workers", 2)
    assert code == 0, stderr
    assert not [w for w in caught if "already in use" in str(w.message)]
    assert "rows: 48,000 in 8 chunk file(s) (8 computed, 0 kept from before)" in stdout
    # Both worker processes computed chunks, each with its share of the cores.
    workers, threads = engine_note(stdout)
    assert workers == 2 and threads == str(max(1, numba.config.NUMBA_NUM_THREADS // 2))
    reference = local_reference(tmp_path_factory, THROUGHPUT, 48_000, 5, 6_000)
    assert_same_dataset(tmp_path / "ds", reference)


def test_scheduler_and_two_dask_workers_give_the_local_dataset(cluster, tmp_path,
                                                                tmp_path_factory, capsys,
                                                                monkeypatch):
    # The client runs elsewhere than the workers (another working directory) and names
    # the output relative to its own: the workers get the absolute path. The study has
    # simulated measurement noise, drawn on the workers too.
    monkeypatch.chdir(tmp_path)
    code, stdout, stderr = mcbat_main(
        capsys, "run", CROSS_NATHAN, "--out", "ds", "--samples", 40_000, "--seed", 3,
        "--chunk-size", 5_000, "--quiet", "--engine", "dask", "--scheduler", cluster.address)
    assert code == 0, stderr
    assert engine_note(stdout) == (2, "1")
    reference = local_reference(tmp_path_factory, CROSS_NATHAN, 40_000, 3, 5_000)
    assert "exit_speed_measured" in mcbat.load(reference).columns
    assert_same_dataset(tmp_path / "ds", reference)


def test_dask_engine_resumes_a_partial_dataset(cluster, tmp_path, tmp_path_factory, capsys):
    reference = local_reference(tmp_path_factory, EXAMPLE, 30_000, 11, 4_000)
    out = tmp_path / "ds"
    shutil.copytree(reference, out)
    for k in (1, 5):
        (out / ds.chunk_name(k)).unlink()
    truncated = out / ds.chunk_name(3)
    truncated.write_bytes(truncated.read_bytes()[:500])
    (out / ".chunk-000004.parquet.999-deadbeef.tmp").write_bytes(b"left by a killed run")
    kept = {k: p.stat().st_mtime_ns for k, p in ds.chunk_files(out).items() if k != 3}
    code, stdout, stderr = mcbat_main(
        capsys, "run", EXAMPLE, "--out", out, "--samples", 30_000, "--seed", 11,
        "--chunk-size", 4_000, "--engine", "dask", "--scheduler", cluster.address,
        "--threads", 2)
    assert code == 0, stderr
    assert "(3 computed, 5 kept from before)" in stdout
    assert "impacts/s" in stderr  # the progress bar, as in local runs
    # --threads is each worker's numba budget (at most the worker's cores).
    assert engine_note(stdout)[1] == str(min(2, numba.config.NUMBA_NUM_THREADS))
    assert {k: p.stat().st_mtime_ns for k, p in ds.chunk_files(out).items()
            if k in kept} == kept
    assert_same_dataset(out, reference)
    code, stdout, _ = mcbat_main(capsys, "run", EXAMPLE, "--out", out, "--samples", 30_000,
                                 "--seed", 11, "--chunk-size", 4_000, "--quiet", "--engine",
                                 "dask", "--scheduler", cluster.address)
    assert code == 0 and "(0 computed, 8 kept from before)" in stdout


@pytest.mark.parametrize("scheme", ["file", "local"])
def test_url_output_with_the_dask_engine(cluster, tmp_path, tmp_path_factory, capsys, scheme):
    # file:// is a local path; local:// goes through pyarrow.fs like s3:// or gs:// would
    # (pyarrow's LocalFileSystem), on the client and on the workers.
    url = f"{scheme}://{tmp_path / 'ds'}"
    code, stdout, stderr = mcbat_main(
        capsys, "run", EXAMPLE, "--out", url, "--samples", 30_000, "--seed", 11,
        "--chunk-size", 4_000, "--quiet", "--engine", "dask", "--scheduler", cluster.address)
    assert code == 0, stderr
    shown = tmp_path / "ds" if scheme == "file" else url
    assert f"dataset: {shown}\n" in stdout
    reference = local_reference(tmp_path_factory, EXAMPLE, 30_000, 11, 4_000)
    assert_same_dataset(tmp_path / "ds", reference)
    pd.testing.assert_frame_equal(mcbat.load(url), mcbat.load(reference), check_exact=True)


def test_output_the_workers_cannot_see_is_a_clear_error(cluster, capsys):
    # memory:// lives in one process: the workers do not see the client's dataset, as
    # with a local path on a disk that is not shared.
    # (The command line refuses memory:// up front; the Python API accepts it.)
    from mcbat.errors import InputError
    from mcbat.runner import run_study
    from mcbat.study import load_study

    with pytest.raises(InputError) as err:
        run_study(load_study(EXAMPLE), "memory://mcbat-test/ds", samples=2_000,
                  progress=False, engine="dask", scheduler=cluster.address)
    assert err.value.field == "out"
    assert err.value.message.startswith("the worker on")
    assert "storage every worker shares" in err.value.message
    code, _, stderr = mcbat_main(capsys, "run", EXAMPLE, "--out", "memory://mcbat-test/ds",
                                 "--samples", 2_000, "--quiet", "--engine", "dask",
                                 "--scheduler", cluster.address)
    assert code == 2 and "--out: memory:// keeps files" in stderr


def test_interrupted_dask_run_resumes_identically(cluster, tmp_path, tmp_path_factory):
    samples, chunk_size = 600_000, 20_000
    args = ["run", str(EXAMPLE), "--out", str(tmp_path / "ds"), "--samples", str(samples),
            "--seed", "21", "--chunk-size", str(chunk_size), "--quiet", "--engine", "dask",
            "--scheduler", cluster.address]
    # SIGINT as a terminal delivers it: a test suite started in the background of a
    # non-interactive shell has it ignored, and Python would keep ignoring it.
    run = subprocess.Popen([sys.executable, "-m", "mcbat.cli", *args],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + TIMEOUT
        while not ((tmp_path / "ds").is_dir() and len(ds.chunk_files(tmp_path / "ds")) >= 3):
            assert time.monotonic() < deadline and run.poll() is None
            time.sleep(0.01)
        run.send_signal(signal.SIGINT)  # Ctrl-C
        stdout, stderr = run.communicate(timeout=TIMEOUT)
    finally:
        _stop(run)
    assert run.returncode == 130, (stdout, stderr)
    assert "complete chunk files are kept, rerun the same command to resume" in stderr
    assert len(ds.chunk_files(tmp_path / "ds")) < samples // chunk_size
    resumed = mcbat_cli(*args)
    assert resumed.returncode == 0, resumed.stderr
    assert "kept from before" in resumed.stdout and "(0 computed" not in resumed.stdout
    reference = local_reference(tmp_path_factory, EXAMPLE, samples, 21, chunk_size)
    assert_same_dataset(tmp_path / "ds", reference)


# ---------------------------------------------------------------- a worker dies


def test_killed_worker_is_retried_and_the_dataset_is_identical(dask_installed, tmp_path,
                                                                tmp_path_factory):
    from distributed import Client

    samples, chunk_size = 600_000, 20_000
    reference = local_reference(tmp_path_factory, EXAMPLE, samples, 21, chunk_size)
    cluster = ExternalCluster(tmp_path / "dask")
    out = tmp_path / "ds"
    run = None
    try:
        run = subprocess.Popen(
            [sys.executable, "-m", "mcbat.cli", "run", str(EXAMPLE), "--out", str(out),
             "--samples", str(samples), "--seed", "21", "--chunk-size", str(chunk_size),
             "--quiet", "--engine", "dask", "--scheduler", cluster.address],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        with Client(cluster.address, timeout=30) as client:
            deadline = time.monotonic() + TIMEOUT
            while True:  # some chunks written, the victim busy with one it has not
                assert time.monotonic() < deadline and run.poll() is None, run.stderr.read()
                if out.is_dir() and len(ds.chunk_files(out)) >= 4:
                    pids = client.run(os.getpid)
                    victim = sorted(pids)[0]
                    busy = client.processing(workers=[victim]).get(victim, ())
                    if busy:
                        break
                time.sleep(0.01)
            # SIGKILL the worker process (its nanny stays and starts a fresh one).
            os.kill(pids[victim], signal.SIGKILL)
            written = set(ds.chunk_files(out))
        lost = {chunk_of(key) for key in busy} - written
        assert lost, "the killed worker held no unwritten chunk"
        assert len(written) < samples // chunk_size, "the run was over before the kill"
        stdout, stderr = run.communicate(timeout=TIMEOUT)
    finally:
        _stop(run)
        cluster.close()
    assert run.returncode == 0, stderr
    assert f"rows: {samples:,} in 30 chunk file(s) (30 computed" in stdout
    # The lost chunks were recomputed elsewhere; nothing is missing, duplicated or left
    # half-written: the very files of the local engine.
    assert_same_dataset(out, reference)


def test_a_lost_scheduler_is_one_line_and_exit_4_at_once_and_the_rerun_resumes(
        cluster, tmp_path, tmp_path_factory):
    samples, chunk_size = 600_000, 20_000
    doomed = ExternalCluster(tmp_path / "dask")  # its scheduler is killed: not the shared one
    out = tmp_path / "ds"
    args = ["run", str(EXAMPLE), "--out", str(out), "--samples", str(samples), "--seed",
            "21", "--chunk-size", str(chunk_size), "--quiet", "--engine", "dask"]
    run = None
    try:
        run = subprocess.Popen([sys.executable, "-m", "mcbat.cli", *args, "--scheduler",
                                doomed.address],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        deadline = time.monotonic() + TIMEOUT
        while not (out.is_dir() and len(ds.chunk_files(out)) >= 3):
            assert time.monotonic() < deadline and run.poll() is None, run.stderr.read()
            time.sleep(0.01)
        os.killpg(doomed.procs[0].pid, signal.SIGKILL)  # the scheduler, mid-run
        killed = time.monotonic()
        stdout, stderr = run.communicate(timeout=TIMEOUT)
        waited = time.monotonic() - killed
    finally:
        _stop(run)
        doomed.close()
    assert run.returncode == 4, stderr
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    assert lines[0].startswith("mcbat: error: lost the connection to the Dask scheduler "
                               f"({doomed.address})")
    assert "rerun the same command to resume" in lines[0]
    # Dask's own reconnection attempt would take distributed.comm.timeouts.connect (30 s).
    assert waited < 10, f"{waited:.1f} s between the scheduler's death and the exit"
    assert len(ds.chunk_files(out)) < samples // chunk_size, "the run was over before"
    assert not (out / "_mcbat.lock").exists()  # released: the rerun is not blocked
    # Another cluster (the shared one, alive): the same command resumes to the local
    # engine's dataset.
    resumed = mcbat_cli(*args, "--scheduler", cluster.address)
    assert resumed.returncode == 0, resumed.stderr
    assert "kept from before" in resumed.stdout
    assert_same_dataset(out, local_reference(tmp_path_factory, EXAMPLE, samples, 21,
                                             chunk_size))


# ---------------------------------------------------------------- chunk tasks


def test_a_rerun_chunk_task_is_idempotent(dask_installed, tmp_path, tmp_path_factory):
    from mcbat.runner.engines.dask_tasks import chunk_task

    study = load_study(EXAMPLE)
    reference = local_reference(tmp_path_factory, EXAMPLE, 30_000, 11, 4_000)
    out = tmp_path / "ds"
    job, manifest = plan_run(study, out, 30_000, 11, 4_000)
    prepare_directory(out, manifest, 4_000, False)
    for _ in range(2):  # a retried task, or a lost worker's task done again elsewhere
        summary = chunk_task(6, study.definition(), job, 1)
        assert (summary.index, summary.rows, summary.threads) == (6, 4_000, 1)
        assert sum(summary.status_counts) == 4_000
        assert sorted(p.name for p in out.iterdir()) == [ds.MANIFEST, ds.chunk_name(6)]
        assert (out / ds.chunk_name(6)).read_bytes() == \
            (reference / ds.chunk_name(6)).read_bytes()


def test_a_tolerance_override_reaches_the_worker(dask_installed, tmp_path):
    # run_study(tolerance=...) (mcbat run --tolerance): the worker rebuilds the study from
    # its definition with the overridden tolerance and writes the local engine's bytes.
    from mcbat.runner.engines.dask_tasks import chunk_task

    local = tmp_path / "local"
    run_study(load_study(EXAMPLE), local, samples=600, seed=5, chunk_size=300,
              tolerance=1e-11, progress=False)
    study = load_study(EXAMPLE).with_overrides(tolerance=1e-11)
    out = tmp_path / "ds"
    job, manifest = plan_run(study, out, 600, 5, 300)
    assert manifest["study"]["solver"]["tolerance"] == 1e-11
    prepare_directory(out, manifest, 300, False)
    summary = chunk_task(1, study.definition(), job, 1)
    assert summary.rows == 300
    assert (out / ds.chunk_name(1)).read_bytes() == (local / ds.chunk_name(1)).read_bytes()


def test_a_worker_with_another_environment_refuses(dask_installed, tmp_path):
    from mcbat.runner.engines.dask_tasks import WorkerSetupError, chunk_task

    study = load_study(EXAMPLE)
    out = tmp_path / "ds"
    job, manifest = plan_run(study, out, 1_000, 1, 500)
    prepare_directory(out, manifest, 500, False)
    versions = {**job.metadata["versions"], "numba": "0.0.1"}
    other = type(job)(**{**job.__dict__, "metadata": {**job.metadata, "versions": versions}})
    with pytest.raises(WorkerSetupError, match="numba"):
        chunk_task(0, study.definition(), other, 1)
    assert not ds.chunk_files(out)


# ---------------------------------------------------------------- bad options


@pytest.mark.parametrize("args, words", [
    (("--engine", "dask", "--workers", "0"), "--workers: must be an integer >= 1"),
    (("--engine", "dask", "--workers", "1", "--threads", "100000"),
     "--threads: 1 worker process(es) x 100000 numba thread(s) would oversubscribe"),
    (("--engine", "dask", "--workers", "2", "--scheduler", "tcp://127.0.0.1:8786"),
     "--workers: give either --scheduler ADDRESS"),
    (("--scheduler", "tcp://127.0.0.1:8786"), "--scheduler: only with --engine dask"),
    (("--workers", "2"), "--workers: only with --engine dask"),
    (("--engine", "spark"), "argument --engine: invalid choice: 'spark'"),
])
def test_bad_engine_options_exit_2_and_write_nothing(dask_installed, tmp_path, capsys, args,
                                                     words):
    out = tmp_path / "out"
    code, _, stderr = mcbat_main(capsys, "run", EXAMPLE, "--out", out, "--quiet", *args)
    assert code == 2
    assert len(stderr.strip().splitlines()) == 1 and words in stderr
    assert "Traceback" not in stderr and not out.exists()


def test_unreachable_scheduler_exits_2_and_writes_nothing(dask_installed, tmp_path, capsys):
    import dask

    with socket.socket() as sock:  # a free port: nobody listens there
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    out = tmp_path / "out"
    with dask.config.set({"distributed.comm.timeouts.connect": "2s"}):
        code, _, stderr = mcbat_main(capsys, "run", EXAMPLE, "--out", out, "--quiet",
                                     "--engine", "dask", "--scheduler",
                                     f"tcp://127.0.0.1:{port}")
    assert code == 2
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in stderr
    assert f"--scheduler: cannot connect to tcp://127.0.0.1:{port}" in lines[0]
    assert not out.exists()


def test_without_dask_the_engine_says_how_to_install_it(tmp_path, capsys, monkeypatch):
    # Runs whether or not Dask is installed: importing it is made to fail (a None entry in
    # sys.modules makes `import distributed` raise ImportError, as if it were absent).
    for name in ("distributed", "dask"):
        monkeypatch.setitem(sys.modules, name, None)
    out = tmp_path / "out"
    for extra in ((), ("--workers", "2"), ("--scheduler", "tcp://127.0.0.1:8786")):
        code, _, stderr = mcbat_main(capsys, "run", EXAMPLE, "--out", out, "--quiet",
                                     "--engine", "dask", *extra)
        assert code == 2
        assert stderr.strip() == INSTALL_HINT
        assert not out.exists()
    # The local engine does not need Dask.
    code, _, stderr = mcbat_main(capsys, "run", EXAMPLE, "--out", out, "--quiet",
                                 "--samples", "1000")
    assert code == 0, stderr


# ---------------------------------------------------------------- real pitches

REAL_PITCHES = ROOT / "studies" / "real_pitches.toml"


def test_real_pitches_on_a_scheduler_and_two_workers_give_the_local_dataset(
        cluster, tmp_path, tmp_path_factory, capsys, monkeypatch):
    # The workers run in another directory than the client: they read the [pitches] file
    # by the absolute path the study's definition carries, and draw the same rows.
    monkeypatch.chdir(tmp_path)
    code, stdout, stderr = mcbat_main(
        capsys, "run", REAL_PITCHES, "--out", "ds", "--samples", 12_000, "--seed", 4,
        "--chunk-size", 3_000, "--quiet", "--engine", "dask", "--scheduler", cluster.address)
    assert code == 0, stderr
    assert engine_note(stdout) == (2, "1")
    reference = local_reference(tmp_path_factory, REAL_PITCHES, 12_000, 4, 3_000)
    assert "source_row" in mcbat.load(reference).columns
    assert_same_dataset(tmp_path / "ds", reference)


def test_a_worker_that_cannot_read_the_pitches_file_says_so(dask_installed, tmp_path):
    from mcbat.runner.engines.dask_tasks import WorkerSetupError, chunk_task

    data = tmp_path / "pitches.csv"
    shutil.copy(ROOT / "data" / "statcast_2020-09-03.csv", data)
    study_file = tmp_path / "real.toml"
    study_file.write_text(REAL_PITCHES.read_text().replace(
        "../data/statcast_2020-09-03.csv", str(data)))
    study = mcbat.load_study(study_file)
    out = tmp_path / "ds"
    job, manifest = plan_run(study, out, 600, 5, 300)
    prepare_directory(out, manifest, 300, False)
    definition = study.definition()
    assert definition["pitches"]["file"] == str(data)
    # The same file: the local engine's bytes.
    summary = chunk_task(1, definition, job, 1)
    assert summary.rows == 300
    local = tmp_path / "local"
    run_study(study, local, samples=600, seed=5, chunk_size=300, progress=False)
    assert (out / ds.chunk_name(1)).read_bytes() == (local / ds.chunk_name(1)).read_bytes()
    # A worker that sees another file under that path (or none) refuses to compute.
    from mcbat.runner.engines import dask_tasks

    dask_tasks._STUDIES.clear()
    data.write_text(data.read_text()[:-200].rsplit("\n", 1)[0] + "\n")
    with pytest.raises(WorkerSetupError, match="reads another .*pitches.csv than the client"):
        chunk_task(0, definition, job, 1)
    data.unlink()
    with pytest.raises(WorkerSetupError, match=r"cannot use the \[pitches\] file: cannot "
                                               r"read .*No such file"):
        chunk_task(0, definition, job, 1)
    assert sorted(p.name for p in out.iterdir()) == [ds.MANIFEST, ds.chunk_name(1)]


def _kernels_loaded():
    from mcbat.core.batch import solve_batch
    from mcbat.core.swing.game import solve_game_batch

    return {"bat_frame": bool(solve_batch.signatures),
            "game": bool(solve_game_batch.signatures)}


def test_workers_load_the_kernels_of_the_study_and_only_those(dask_installed, tmp_path):
    # Before a run's clock starts every worker loads its study's kernels: a game study's
    # workers load the game kernel and never the bat-frame kernel.
    from mcbat.runner.engines.dask import DaskEngine

    study = load_study(ROOT / "studies" / "game_fastball.toml")
    out = tmp_path / "ds"
    job, manifest = plan_run(study, out, 600, 5, 300)
    prepare_directory(out, manifest, 300, False)
    engine = DaskEngine(workers=2, threads=1)
    with engine.connect():
        before = engine.client.run(_kernels_loaded)
        engine.ready(study, job, out)
        after = engine.client.run(_kernels_loaded)
    assert len(after) == 2
    assert all(k == {"bat_frame": False, "game": False} for k in before.values()), before
    assert all(k == {"bat_frame": False, "game": True} for k in after.values()), after


def test_player_levels_on_a_scheduler_and_two_workers_give_the_local_dataset(
        cluster, tmp_path, tmp_path_factory, capsys, monkeypatch):
    # Every worker estimates the players' contact from the file itself, as the client
    # does: one batter over 41 games, every row moved, the same dataset.
    excerpt = ROOT / "tests" / "statcast" / "data" / "statcast_2024_ohtani_in_play_excerpt.csv"
    text = (ROOT / "studies" / "bat_tracking.toml").read_text()
    study = tmp_path_factory.mktemp("levels") / "levels.toml"
    study.write_text(text.replace('file = "../data/statcast_2025-05-01_bat_tracking.csv"',
                                  f"file = {str(excerpt)!r}"))
    monkeypatch.chdir(tmp_path)
    code, stdout, stderr = mcbat_main(
        capsys, "run", study, "--out", "ds", "--samples", 12_000, "--seed", 4,
        "--chunk-size", 3_000, "--engine", "dask", "--scheduler", cluster.address)
    assert code == 0, stderr
    assert "120 of the 120 rows met their players' contact" in stdout
    reference = local_reference(tmp_path_factory, study, 12_000, 4, 3_000)
    assert_same_dataset(tmp_path / "ds", reference)
