"""A command's first compile says so, once, on stderr (``mcbat.cli.compiling``); a warm
command says nothing; ``mcbat warmup`` compiles every kernel group."""

import argparse
import io
import json
import os
import re
import subprocess
import sys

import numba
import pytest

from mcbat.cli import compiling
from mcbat.cli.app import build_parser
from tests.conftest import ROOT

BALL = {"launch_speed": {"value": 103, "unit": "mph"},
        "launch_angle": {"value": 27, "unit": "deg"},
        "backspin": {"value": 2000, "unit": "rpm"}}
LINE = re.compile(r"mcbat: compiling the .+ \(first run only, about \d+ s\)")


def _mcbat(cache, *args, stdin=None):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "NUMBA_NUM_THREADS": "2"}
    return subprocess.run([sys.executable, "-m", "mcbat", *args], input=stdin,
                          capture_output=True, text=True, cwd=ROOT, env=env)


def test_a_first_flight_says_it_compiles_and_a_second_does_not(tmp_path):
    """An empty numba cache: one line on stderr before the answer; the same cache once
    filled: nothing on stderr, the same answer."""
    cold = _mcbat(tmp_path / "cache", "flight", "-", stdin=json.dumps(BALL))
    assert cold.returncode == 0, cold.stderr
    lines = cold.stderr.splitlines()
    assert len(lines) == 1 and LINE.fullmatch(lines[0]) and "flight kernel" in lines[0], lines
    warm = _mcbat(tmp_path / "cache", "flight", "-", stdin=json.dumps(BALL))
    assert warm.returncode == 0 and warm.stderr == "", warm.stderr
    assert json.loads(warm.stdout) == json.loads(cold.stdout)


def _fresh_kernel():
    """A numba function this process has not compiled (not cached): its first call
    compiles, as a cold kernel's would."""
    @numba.njit
    def twice(x):
        return 2.0 * x
    return twice


def _args(*argv):
    return build_parser().parse_args(list(argv))


def test_the_line_comes_at_the_first_compile_only(monkeypatch):
    monkeypatch.setattr(compiling, "_cold", lambda name: True)
    out = io.StringIO()
    with compiling.notice(_args("flight", "-"), out):
        assert out.getvalue() == ""  # nothing before a compile
        _fresh_kernel()(1.0)
        _fresh_kernel()(2.0)  # a second compile: no second line
    lines = out.getvalue().splitlines()
    assert len(lines) == 1 and LINE.fullmatch(lines[0]) and "the flight kernel" in lines[0]


def test_no_line_without_a_compile_with_quiet_or_for_a_command_without_kernels(monkeypatch):
    monkeypatch.setattr(compiling, "_cold", lambda name: True)
    kernel = _fresh_kernel()
    kernel(1.0)  # compiled: calling it again compiles nothing
    out = io.StringIO()
    with compiling.notice(_args("flight", "-"), out):
        kernel(3.0)
    for argv in (("run", "example", "--quiet"), ("statcast", "x.csv"), ("check", "d")):
        with compiling.notice(_args(*argv), out):
            _fresh_kernel()(1.0)
    assert out.getvalue() == ""


def test_a_run_that_said_it_before_its_bar_is_not_told_twice(monkeypatch):
    import mcbat.runner.compiling as runner
    from mcbat.core.jit import said_compiling

    monkeypatch.setattr(compiling, "_cold", lambda name: True)
    out = io.StringIO()
    with compiling.notice(_args("run", "example"), out):
        monkeypatch.setitem(said_compiling, "line", runner.COMPILING)
        _fresh_kernel()(1.0)
    assert out.getvalue() == ""


def test_the_groups_of_each_command(tmp_path):
    game = tmp_path / "g.toml"
    game.write_text((ROOT / "studies" / "game_fastball.toml").read_text())
    drop = tmp_path / "d.toml"
    drop.write_text((ROOT / "studies" / "example.toml").read_text())
    groups = compiling.command_groups
    assert groups(_args("impact", "x.json")) == ("game", "flight")
    assert groups(_args("flight")) == ("flight",)
    assert groups(_args("infer", "x.csv")) == ("inference", "game")
    assert groups(_args("run", str(game))) == ("sampling", "game", "flight")
    assert groups(_args("run", str(drop))) == ("sampling", "bat_frame")
    assert groups(_args("synth", "--study", str(drop))) == ("sampling", "bat_frame")
    assert groups(_args("fit", "--study", str(game))) == ("sampling", "game")
    assert groups(_args("fit", "--flight")) == ("flight",)
    assert groups(_args("calibrate")) == ("bat_frame",)
    assert groups(_args("reproduce", "sawicki2003")) == ("game", "flight")
    assert groups(_args("reproduce")) == ("sampling", "bat_frame")
    assert groups(_args("statcast", "x.csv")) == groups(_args("warmup")) == ()


def test_every_group_names_cached_numba_kernels_and_the_line_adds_their_times(monkeypatch):
    from mcbat.core.flight.trajectory import fly_batch
    from mcbat.core.swing.game import solve_game_batch

    for name, group in compiling.KERNEL_GROUPS.items():
        for dispatcher in group.dispatchers():
            assert isinstance(dispatcher, numba.core.registry.CPUDispatcher), (name, dispatcher)
            assert not isinstance(dispatcher._cache, numba.core.caching.NullCache), name
            assert compiling.group_of(dispatcher) in (name, "bat_frame")
    assert compiling.group_of(solve_game_batch) == "game"
    assert compiling.group_of(fly_batch) == "flight"
    assert compiling.group_of(_fresh_kernel()) is None
    # (the shared solver's time counts once, and only while it is still to compile)
    import mcbat.core.jit as jit

    monkeypatch.setattr(jit, "is_cold", lambda d: False)
    game, flight = compiling.KERNEL_GROUPS["game"], compiling.KERNEL_GROUPS["flight"]
    line = compiling.compiling_line(["game", "flight"])
    assert line.startswith("mcbat: compiling the game kernel and the flight kernel (")
    assert f"about {5 * round((game.seconds + flight.seconds) / 5)} s" in line
    monkeypatch.setattr(jit, "is_cold", lambda d: True)
    assert (f"about {5 * round((game.seconds + compiling.SOLVER[1]) / 5)} s"
            in compiling.compiling_line(["game"]))


def test_warmup_runs_a_command_for_every_group(cli):
    """In the test process the kernels are compiled: every group is ready, and the
    commands the warm-up runs succeed (a failing one would say 'failed')."""
    from mcbat.cli.warmup import WARMUPS

    assert set(WARMUPS) == set(compiling.KERNEL_GROUPS)
    done = cli("warmup")
    assert done.returncode == 0, done.stdout
    lines = done.stdout.splitlines()
    labels = [g.label for g in compiling.KERNEL_GROUPS.values()]
    assert [line.split(":")[1].strip() for line in lines[:-1]] == labels
    assert all(" ready in " in line for line in lines[:-1]) and "warmup done" in lines[-1]


@pytest.mark.slow
def test_after_warmup_no_command_compiles(tmp_path):
    """An empty cache filled by ``mcbat warmup``: the game case, the bat-frame case, the
    flight, the inference and the paper's reproduction start without compiling."""
    cache = tmp_path / "cache"
    done = _mcbat(cache, "warmup")
    assert done.returncode == 0 and "failed" not in done.stdout, done.stdout
    for args in (("impact", "examples/game_fastball.json"),
                 ("impact", "examples/cabo2012_sec5.json"),
                 ("infer", "data/statcast_2020-09-03_in_play.csv"),
                 ("reproduce", "--samples", "64", "--out", str(tmp_path / "cabo2012"))):
        proc = _mcbat(cache, *args)
        assert proc.returncode == 0 and "compiling" not in proc.stderr, (args, proc.stderr)
    proc = _mcbat(cache, "flight", "-", stdin=json.dumps(BALL))
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr


def test_the_parser_knows_warmup():
    assert isinstance(build_parser().parse_args(["warmup"]), argparse.Namespace)
