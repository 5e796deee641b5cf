"""Run the ``mcbat`` console entry point in the test process.

Starting ``python -m mcbat`` costs seconds (numpy, pandas, scipy, numba and the cached
kernels are imported afresh each time); a bad-input test only needs what ``main`` returns
and prints. :func:`run_in_process` calls the function the console script calls
(``[project.scripts]`` in pyproject.toml) with ``argv`` and returns the same three things
a subprocess gives: the exit code, stdout and stderr.

What a command may change for the whole process is put back afterwards, so one test's
run cannot leak into the next: the working directory, the environment, the numba thread
count (``--threads`` sets it), the SIGINT/SIGTERM handlers, the warnings filters and the
root logger. An exception that escapes ``main`` is not caught: in the real command it
would be a traceback, so the test fails on it.

The behaviours that need a real process (the installed script's exit status, a killed run,
locks held by another process, signals, pipes) stay subprocess tests.
"""

from __future__ import annotations

import io
import logging
import os
import signal
import sys
import warnings
from dataclasses import dataclass

import numba

from mcbat.cli import main


@dataclass(frozen=True)
class CliResult:
    """What the command returned and printed (the shape of ``subprocess.CompletedProcess``)."""

    returncode: int
    stdout: str
    stderr: str


def run_in_process(capsys, monkeypatch, *args, stdin=None, cwd=None) -> CliResult:
    """Run ``mcbat *args`` through :func:`mcbat.cli.main` with ``stdin`` (bytes or str;
    default: empty) in ``cwd``; returns its :class:`CliResult`."""
    capsys.readouterr()  # drop what the test printed before
    raw = stdin.encode() if isinstance(stdin, str) else (stdin or b"")
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(raw), encoding="utf-8"))
    cwd_before, env_before = os.getcwd(), dict(os.environ)
    threads = numba.get_num_threads()
    handlers = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    root = logging.getLogger()
    level, log_handlers = root.level, list(root.handlers)
    try:
        if cwd is not None:
            os.chdir(cwd)
        with warnings.catch_warnings():
            try:
                code = main([str(a) for a in args])
            except SystemExit as done:  # argparse's --help and --version
                code = done.code if isinstance(done.code, int) else 1
    finally:
        os.chdir(cwd_before)
        os.environ.clear()
        os.environ.update(env_before)
        numba.set_num_threads(threads)
        for sig, handler in handlers.items():
            signal.signal(sig, handler)
        root.setLevel(level)
        root.handlers[:] = log_handlers
    out, err = capsys.readouterr()
    return CliResult(code, out, err)


def mcbat_main(capsys, *args) -> tuple[int, str, str]:
    """:func:`run_in_process` for a test without ``monkeypatch``: (exit code, stdout,
    stderr)."""
    import pytest

    with pytest.MonkeyPatch.context() as monkeypatch:
        r = run_in_process(capsys, monkeypatch, *args)
    return r.returncode, r.stdout, r.stderr
