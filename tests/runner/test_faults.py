"""Faults injected for real: a read-only and a full output file system (tmpfs mounts).

Mounting needs root and the mount syscall (as on the project's machines); elsewhere these
tests are skipped with the reason. The process kill and truncated-file faults are in
``test_run.py``.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

import mcbat
from mcbat.dataset import chunks as ds

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "studies" / "example.toml"


def _mount(target: Path, options: str) -> bool:
    target.mkdir(parents=True, exist_ok=True)
    if os.geteuid() != 0:
        return False
    proc = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(target)],
                          capture_output=True, check=False)
    return proc.returncode == 0


@pytest.fixture
def tmpfs(tmp_path):
    mounted = []

    def mount(name, options):
        target = tmp_path / name
        if not _mount(target, options):
            pytest.skip("needs root and permission to mount a tmpfs")
        mounted.append(target)
        return target

    yield mount
    for target in mounted:
        subprocess.run(["umount", "-l", str(target)], check=False)


def run(*args):
    """The real command in a subprocess."""
    return subprocess.run([sys.executable, "-m", "mcbat.cli", *map(str, args)],
                          capture_output=True, text=True, check=False)


def test_read_only_output_directory_is_a_clear_error(tmpfs):
    # (the real command: the fault reaches the process's exit status, without a traceback)
    target = tmpfs("ro", "ro,size=1m")
    proc = run("run", EXAMPLE, "--out", target / "ds", "--samples", 1000, "--quiet")
    assert proc.returncode == 2
    assert proc.stdout == "" and "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "--out" in lines[0] and "Read-only file system" in lines[0]
    assert list(target.iterdir()) == []


def test_full_disk_is_a_clear_error_and_the_run_resumes_identically(tmpfs, tmp_path, cli):
    # Room for the manifest and some chunk files, not for all of them.
    target = tmpfs("small", "size=3m")
    args = ("run", EXAMPLE, "--samples", 40_000, "--chunk-size", 4_000, "--seed", 8,
            "--quiet")
    proc = cli(*args, "--out", target / "ds")
    assert proc.returncode == 2, proc.stderr
    assert "No space left on device" in proc.stderr and "Traceback" not in proc.stderr
    assert proc.stdout == ""
    assert len(proc.stderr.strip().splitlines()) == 1
    kept = ds.chunk_files(target / "ds")
    assert 0 < len(kept) < 10
    assert not list((target / "ds").glob(".*tmp"))  # no half-written file left behind
    for path in kept.values():  # what is there is complete
        assert ds.chunk_is_complete(path, 4_000, ds.read_manifest(
            target / "ds")["config_hash"])
    # Free space (grow the file system) and rerun: the dataset completes, identical to a
    # clean run.
    subprocess.run(["mount", "-o", "remount,size=64m", str(target)], check=True)
    assert cli(*args, "--out", target / "ds").returncode == 0
    clean = tmp_path / "clean"
    assert cli(*args, "--out", clean).returncode == 0
    a, b = mcbat.load(target / "ds"), mcbat.load(clean)
    assert a.drop(columns="chunk").equals(b.drop(columns="chunk"))


def test_full_disk_while_reproduce_writes_its_figures(tmpfs, cli):
    # Room for the marker and little else: the figures cannot be written.
    target = tmpfs("tiny", "size=64k")
    proc = cli("reproduce", "sawicki2003", "--out", target)
    assert proc.returncode == 2, proc.stderr
    line, = proc.stderr.strip().splitlines()
    assert "--out" in line and "No space left on device" in line
    assert "Traceback" not in proc.stderr
    assert not list(target.rglob(".*tmp"))  # no half-written text file left behind
