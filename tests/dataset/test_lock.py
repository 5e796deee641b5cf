"""One writer per dataset directory: the first ``mcbat run`` is a real process (paused,
killed or running under Dask); the second runs in this process (the ``cli`` fixture), so the
lock is still held by another process."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import mcbat
from mcbat.dataset.lock import LOCK_NAME, dataset_lock
from mcbat.errors import InputError
from mcbat.runner import run_study
from mcbat.study import load_study

ROOT = Path(__file__).resolve().parents[2]
STUDY = ROOT / "studies" / "throughput.toml"
SAMPLES = "1200000"  # a few seconds on 2 cores: long enough to start a second run


def _start(out, *extra):
    return subprocess.Popen([sys.executable, "-m", "mcbat", "run", str(STUDY), "--out",
                             str(out), "--samples", SAMPLES, "--chunk-size", "100000",
                             "--quiet", *extra], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=ROOT)


def _wait_for_holder(out, proc, timeout=60.0):
    """Until the run holds the lock (its pid is written in the lock file)."""
    deadline = time.monotonic() + timeout
    lock = Path(out) / LOCK_NAME
    while time.monotonic() < deadline:
        if lock.exists() and f"pid {proc.pid} " in lock.read_text():
            return
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    pytest.fail("the first run never took the lock")


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The run of :func:`_start` that nobody disturbed (the same config, through the
    library)."""
    out = tmp_path_factory.mktemp("lock") / "ref"
    run_study(load_study(STUDY), out, samples=int(SAMPLES), chunk_size=100_000,
              progress=False)
    return out


@pytest.mark.parametrize("second_args", [
    ["--samples", SAMPLES, "--chunk-size", "100000"],   # the identical run
    ["--samples", "5000", "--overwrite"],               # another config, told to replace
])
def test_a_second_run_on_the_same_directory_is_refused(tmp_path, cli, reference,
                                                       second_args):
    out = tmp_path / "ds"
    first = _start(out)
    _wait_for_holder(out, first)
    # The first run is paused while the second starts: on a loaded machine the second's
    # start can outlast the first's whole run. A paused process keeps its lock.
    os.kill(first.pid, signal.SIGSTOP)
    try:
        second = cli("run", STUDY, "--out", out, "--quiet", *second_args)
    finally:
        os.kill(first.pid, signal.SIGCONT)
    assert second.returncode == 2, second.stderr
    assert second.stdout == ""
    line, = second.stderr.strip().splitlines()
    assert "--out" in line and f"pid {first.pid}" in line
    stdout, stderr = first.communicate(timeout=300)
    assert first.returncode == 0, stderr
    df = mcbat.load(out)
    assert len(df) == int(SAMPLES) and df["sample_id"].is_unique
    # the same as a run nobody disturbed
    assert sorted(p.name for p in reference.glob("chunk-*.parquet")) == \
        sorted(p.name for p in out.glob("chunk-*.parquet"))
    for path in sorted(reference.glob("chunk-*.parquet")):
        assert (out / path.name).read_bytes() == path.read_bytes(), path.name


def test_the_lock_of_a_killed_run_is_not_stale(tmp_path, cli):
    out = tmp_path / "ds"
    first = _start(out)
    _wait_for_holder(out, first)
    os.kill(first.pid, signal.SIGKILL)
    first.wait()
    resumed = cli("run", STUDY, "--out", out, "--samples", SAMPLES, "--chunk-size",
                  "100000", "--quiet")
    assert resumed.returncode == 0, resumed.stderr
    assert len(mcbat.load(out)) == int(SAMPLES)


@pytest.mark.parametrize("leftover", [
    "._mcbat.json.4242-0123abcd.tmp",          # killed while writing its first manifest
    ".chunk-000000.parquet.4242-0123abcd.tmp",  # (and with a chunk in flight)
])
def test_a_run_killed_before_its_first_manifest_leaves_a_resumable_directory(tmp_path, cli,
                                                                             leftover):
    """Found by CI under load: a run killed between writing its manifest's temporary file
    and renaming it left a directory that the rerun refused as "not an mcbat dataset"
    (the temporary manifest was not recognised as ours). The leftovers of a killed run
    are removed, and the rerun proceeds; a foreign file still stops it."""
    out = tmp_path / "ds"
    out.mkdir()
    (out / LOCK_NAME).write_text("pid 4242 on a host that is gone\n")
    (out / leftover).write_bytes(b'{"half a manif')
    resumed = cli("run", STUDY, "--out", out, "--samples", "3000", "--quiet")
    assert resumed.returncode == 0, resumed.stderr
    assert not (out / leftover).exists()
    assert len(mcbat.load(out)) == 3000
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / leftover).write_bytes(b"{")
    (foreign / "notes.txt").write_text("mine")
    refused = cli("run", STUDY, "--out", foreign, "--samples", "3000", "--quiet")
    assert refused.returncode == 2 and "not an mcbat dataset" in refused.stderr
    assert refused.stderr.count("\n") == 1
    assert (foreign / "notes.txt").read_text() == "mine"


def test_the_lock_in_process(tmp_path):
    out = tmp_path / "d"
    with dataset_lock(out):
        with pytest.raises(InputError) as err, dataset_lock(out):
            pass
        assert err.value.field == "out" and f"pid {os.getpid()}" in err.value.message
    with dataset_lock(out):  # released
        pass
    assert not out.exists()  # the lock made the directory; an empty one is removed again
    out.mkdir()
    (out / "kept.txt").write_text("x")
    with dataset_lock(out):
        assert (out / LOCK_NAME).exists()
    assert sorted(p.name for p in out.iterdir()) == ["kept.txt"]


def test_a_refused_run_leaves_no_directory_behind(tmp_path, cli):
    bad = cli("run", STUDY, "--out", tmp_path / "new", "--samples", "0", "--quiet")
    assert bad.returncode == 2 and "--samples" in bad.stderr
    assert not (tmp_path / "new").exists()


def test_a_dask_run_holds_the_lock_too(tmp_path, cli):
    out = tmp_path / "ds"
    # (one worker: a run with NUMBA_NUM_THREADS=1 counts one core and refuses two)
    first = _start(out, "--engine", "dask", "--workers", "1", "--threads", "1")
    _wait_for_holder(out, first, timeout=120.0)
    second = cli("run", STUDY, "--out", out, "--quiet", "--samples", SAMPLES,
                 "--chunk-size", "100000", "--engine", "dask")
    assert second.returncode == 2 and f"pid {first.pid}" in second.stderr, second.stderr
    stdout, stderr = first.communicate(timeout=300)
    assert first.returncode == 0, stderr
    assert len(mcbat.load(out)) == int(SAMPLES)
