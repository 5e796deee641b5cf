"""A cold command compiles its other kernel groups in a helper process on the second core
(``mcbat.cli.precompile``), waits for them before their first call and then loads them:
the same answers, sooner."""

import json
import os
import subprocess
import sys
import threading
import time

import numba
import numpy as np
import pytest

from mcbat.cli import compiling, precompile
from mcbat.cli.app import build_parser
from mcbat.core import jit
from mcbat.core.swing.game import solve_game_batch
from tests.conftest import ROOT


def _args(*argv):
    return build_parser().parse_args(list(argv))


def _env(cache, **extra):
    return {**os.environ, "NUMBA_CACHE_DIR": str(cache), "NUMBA_NUM_THREADS": "2", **extra}


def test_a_kernel_call_waits_for_the_helper_of_its_group_once():
    calls = []

    def wait():
        time.sleep(0.2)
        calls.append(time.perf_counter())

    jit.compiled_elsewhere(["flight", "sampling"], wait)
    try:
        jit.await_group("game")  # not the helper's: no wait
        assert calls == []
        t0 = time.perf_counter()
        jit.await_group("flight")
        assert len(calls) == 1 and time.perf_counter() - t0 >= 0.2
        jit.await_group("sampling")  # the helper is done: forgotten
        jit.await_group("flight")
        assert len(calls) == 1
    finally:
        jit.compiled_elsewhere((), None)


def test_threads_calling_at_once_wait_for_one_helper():
    done = threading.Event()
    jit.compiled_elsewhere(["game"], lambda: done.wait(5))
    threads = [threading.Thread(target=jit.await_group, args=("game",)) for _ in range(4)]
    for t in threads:
        t.start()
    done.set()
    for t in threads:
        t.join(5)
    assert not any(t.is_alive() for t in threads)
    jit.compiled_elsewhere((), None)


def test_this_process_compiles_the_group_it_starts_on_a_helper_the_others(monkeypatch,
                                                                         tmp_path):
    study = tmp_path / "g.toml"
    study.write_text((ROOT / "studies" / "game_fastball.toml").read_text())
    monkeypatch.setattr(compiling, "_cold", lambda name: True)
    started = []
    monkeypatch.setattr(compiling, "_start_helper",
                        lambda first, groups: started.append(list(groups)) or True)
    monkeypatch.setattr(compiling, "_parallel", lambda: True)

    @numba.njit
    def not_a_kernel(x):
        return x + 1.0

    first = compiling._FirstCompile(_args("run", str(study)), None, False)
    first.on_start(not_a_kernel)  # outside every group: which comes first is not known
    assert started == []
    first.on_start(solve_game_batch)
    assert started == [["sampling", "flight"]]  # the command's order, less the game
    first.on_start(solve_game_batch)
    assert started == [["sampling", "flight"]]  # once


def test_one_group_or_one_core_starts_no_helper(monkeypatch):
    monkeypatch.setattr(compiling, "_cold", lambda name: True)
    monkeypatch.setattr(precompile, "start", lambda groups: pytest.fail("started"))
    from mcbat.core.flight.trajectory import fly_batch

    compiling._FirstCompile(_args("flight", "-"), None, False).on_start(fly_batch)
    monkeypatch.setenv(precompile.ENV, "0")
    assert not precompile.parallel()
    compiling._FirstCompile(_args("impact", "x.json"), None, False).on_start(solve_game_batch)


def test_every_group_has_a_compiler():
    assert set(precompile.COMPILERS) == set(compiling.KERNEL_GROUPS)
    assert precompile.main(["no_such_group"]) == 1


@pytest.mark.skipif(not precompile.parallel(), reason="one core: no helper")
def test_a_cold_game_case_compiles_on_two_cores_and_answers_as_a_warm_one(tmp_path):
    cache = tmp_path / "cache"
    argv = [sys.executable, "-m", "mcbat", "impact", "examples/game_fastball.json"]
    cold = subprocess.run(argv, capture_output=True, text=True, cwd=ROOT, env=_env(cache))
    assert cold.returncode == 0, cold.stderr
    assert "on two cores" in cold.stderr.splitlines()[0], cold.stderr
    warm = subprocess.run(argv, capture_output=True, text=True, cwd=ROOT, env=_env(cache))
    assert warm.returncode == 0 and "compiling" not in warm.stderr, warm.stderr
    assert json.loads(warm.stdout) == json.loads(cold.stdout)


PROBE = """
import json, sys
from numba.core import event
from mcbat.cli.compiling import group_of
compiled = []
class Listener(event.Listener):
    def on_start(self, ev):
        compiled.append(group_of(ev.data["dispatcher"]))
    def on_end(self, ev):
        pass
with event.install_listener("numba:compile", Listener()):
    from mcbat.cli.app import main
    code = main(sys.argv[1:])
print(json.dumps({"code": code, "groups": sorted({g for g in compiled if g})}))
"""


@pytest.mark.slow
def test_the_compilers_compile_what_the_commands_call(tmp_path):
    """After the helper's compilers filled an empty cache, no command compiles a kernel
    of any group again (the same argument types, so the same cache entries)."""
    cache = tmp_path / "cache"
    done = subprocess.run([sys.executable, "-m", "mcbat.cli.precompile",
                           *compiling.KERNEL_GROUPS], cwd=ROOT, env=_env(cache))
    assert done.returncode == 0
    ball = tmp_path / "ball.json"
    ball.write_text(json.dumps({"launch_speed": 103, "launch_angle": 27, "backspin": 2000}))
    commands = [
        ["impact", "examples/game_fastball.json"], ["impact", "examples/cabo2012_sec5.json"],
        ["flight", str(ball)], ["flight", str(ball), "--trajectory", "0.5"],
        ["run", "studies/game_fastball.toml", "--samples", "500", "--out",
         str(tmp_path / "game"), "--quiet"],
        ["run", "studies/example.toml", "--samples", "500", "--out", str(tmp_path / "drop"),
         "--quiet"],
        ["reproduce", "--samples", "64", "--out", str(tmp_path / "cabo2012"), "--quiet"],
        ["infer", "data/statcast_2020-09-03.csv", "--out", str(tmp_path / "i.parquet")],
        ["replay", "data/statcast_2020-09-03.csv"]]
    for command in commands:
        out = subprocess.run([sys.executable, "-c", PROBE, *command], capture_output=True,
                             text=True, cwd=ROOT, env=_env(cache, MCBAT_PARALLEL_COMPILE="0"))
        assert out.returncode == 0, (command, out.stderr)
        report = json.loads(out.stdout.strip().splitlines()[-1])
        assert report == {"code": 0, "groups": []}, (command, report)


def test_a_function_passed_by_address_gives_the_direct_call_and_waits_for_its_group():
    @numba.njit
    def row(values, col, out):
        out[col] = values[col] * values[col] + 1.0

    signature = numba.types.none(numba.float64[::1], numba.int64, numba.float64[::1])

    @numba.njit
    def kernel(values, function, out):
        for col in range(values.shape[0]):
            function(values, np.int64(col), out)

    values = np.linspace(-2.0, 3.0, 7)
    by_address, direct = np.empty(7), np.empty(7)
    waits = []
    jit.compiled_elsewhere(["game"], lambda: waits.append(True))
    try:
        kernel(values, jit.FunctionAddress(row, signature, group="game"), by_address)
    finally:
        jit.compiled_elsewhere((), None)
    for col in range(7):
        row(values, col, direct)
    assert waits == [True]  # waited for the helper before compiling the function
    assert row.signatures == [tuple(signature.args)]  # one compile, of that signature
    np.testing.assert_array_equal(by_address, direct)
    np.testing.assert_array_equal(direct, values * values + 1.0)


PROBE_FUNCTIONS = PROBE.replace("group_of(ev.data[\"dispatcher\"])",
                                "ev.data[\"dispatcher\"].py_func.__name__").replace(
    "{g for g in compiled if g}", "set(compiled)")


@pytest.mark.slow
def test_the_inference_kernel_compiles_without_the_game_row_it_calls(tmp_path):
    """With the game group in the cache, a cold ``infer`` compiles the inference kernel
    alone: the game's row function and the impact solver are loaded, not compiled again
    (which is what lets a helper compile them at the same time)."""
    cache = tmp_path / "cache"
    done = subprocess.run([sys.executable, "-m", "mcbat.cli.precompile", "game"], cwd=ROOT,
                          env=_env(cache))
    assert done.returncode == 0
    out = subprocess.run(
        [sys.executable, "-c", PROBE_FUNCTIONS, "infer", "data/statcast_2020-09-03.csv",
         "--out", str(tmp_path / "i.parquet")],
        capture_output=True, text=True, cwd=ROOT, env=_env(cache, MCBAT_PARALLEL_COMPILE="0"))
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert "infer_contact_batch" in report["groups"], report
    assert not {"solve_game_row", "solve_impact"} & set(report["groups"]), report["groups"]
