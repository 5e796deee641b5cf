"""First call of each command: the wall and CPU time of a fresh install's first run, when
numba compiles the kernels it needs, and of the run after it (warm: loaded from numba's
cache).

Run:  .venv/bin/python -m benchmarks first_call [--commands impact,flight,...]

Every command runs in a fresh process with its own empty ``NUMBA_CACHE_DIR`` (nothing
compiled before it) and ``NUMBA_NUM_THREADS=2``; then once more with the same cache. The
CPU time is the process's own (user + system, ``os.wait4``). The inputs some commands
need (a measurement table for ``fit``, a dataset for ``compare`` and ``check``) are made
first, untimed, with the usual cache. Whether the first call printed the compiling line
(``mcbat.runner.compiling``) and the second did not is recorded too.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import harness

ROOT = Path(__file__).resolve().parents[1]
FLIGHT_JSON = ('{"launch_speed": {"value": 103, "unit": "mph"}, "launch_angle": {"value": 27, '
               '"unit": "deg"}, "backspin": {"value": 2000, "unit": "rpm"}}')
STATCAST = "data/statcast_2020-09-03.csv"

#: name -> (the arguments of ``mcbat``, stdin); ``{work}`` is the run's scratch folder.
COMMANDS = {
    "impact": (["impact", "examples/game_fastball.json"], None),
    "impact (bat frame)": (["impact", "examples/cabo2012_sec5.json"], None),
    "flight": (["flight", "-"], FLIGHT_JSON),
    "run": (["run", "studies/game_fastball.toml", "--samples", "2000", "--out",
             "{work}/run"], None),
    "reproduce": (["reproduce", "--samples", "300", "--out", "{work}/reproduce"], None),
    "calibrate": (["calibrate"], None),
    "synth": (["synth", "--study", "studies/game_fastball.toml", "--rows", "30", "--e", "0.5",
               "--e-x", "0.3", "--out", "{work}/synth.csv"], None),
    "fit": (["fit", "--study", "studies/game_fastball.toml", "--data", "{work}/measured.csv",
             "--free", "e", "--intervals", "curvature", "--no-compare", "--json"], None),
    "statcast": (["statcast", STATCAST], None),
    "infer": (["infer", STATCAST], None),
    "replay": (["replay", STATCAST], None),
    "compare": (["compare", "{work}/dataset", STATCAST], None),
    "check": (["check", "{work}/dataset"], None),
}
#: python -m benchmarks --quick first_call
QUICK_ARGS = ["--commands", "flight,impact"]


def _mcbat(args, work, env=None, stdin=None):
    """Run ``mcbat ARGS`` from the repository's root; returns (wall s, CPU s, exit code,
    stderr)."""
    argv = [sys.executable, "-m", "mcbat.cli", *(a.format(work=work) for a in args)]
    t0 = time.perf_counter()
    with tempfile.TemporaryFile() as err:
        proc = subprocess.Popen(argv, cwd=ROOT, env=env, stdout=subprocess.DEVNULL,
                                stderr=err, stdin=subprocess.PIPE if stdin else
                                subprocess.DEVNULL)
        if stdin:
            proc.stdin.write(stdin.encode())
            proc.stdin.close()
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        stderr = err.read().decode(errors="replace")
    return wall, usage.ru_utime + usage.ru_stime, proc.returncode, stderr


def setup(work: Path) -> None:
    """The inputs of ``fit``, ``compare`` and ``check`` (untimed, the usual cache)."""
    for args in (["synth", "--study", "studies/game_fastball.toml", "--rows", "30", "--e",
                  "0.5", "--e-x", "0.3", "--out", "{work}/measured.csv"],
                 ["run", "studies/game_fastball.toml", "--samples", "2000", "--out",
                  "{work}/dataset", "--quiet"]):
        _, _, code, stderr = _mcbat(args, work)
        if code != 0:
            raise SystemExit(f"set-up failed: mcbat {' '.join(args)}: {stderr.strip()}")


def first_call(name: str, work: Path) -> dict:
    """The first and the second call of command ``name``, each in a fresh process, with a
    cache of their own that starts empty."""
    args, stdin = COMMANDS[name]
    cache = work / ("cache-" + name.replace(" ", "_").replace("(", "").replace(")", ""))
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "NUMBA_NUM_THREADS": "2"}
    result = {"argv": "mcbat " + " ".join(a.replace("{work}/", "") for a in args)}
    for phase in ("cold", "warm"):
        wall, cpu, code, stderr = _mcbat(args, work, env, stdin)
        if code != 0:
            raise SystemExit(f"mcbat {' '.join(args)} ({phase}) exited {code}: "
                             f"{stderr.strip()[-500:]}")
        result.update({f"{phase}_wall_s": round(wall, 2), f"{phase}_cpu_s": round(cpu, 2),
                       f"{phase}_announced": "compiling" in stderr})
    print(f"{name:<20} first call {result['cold_wall_s']:6.1f} s wall {result['cold_cpu_s']:6.1f}"
          f" s CPU{' (announced)' if result['cold_announced'] else ''}; then "
          f"{result['warm_wall_s']:5.1f} s wall {result['warm_cpu_s']:5.1f} s CPU", flush=True)
    return result


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--commands", default=",".join(COMMANDS),
                        help="comma-separated names (default: all: "
                             + ", ".join(COMMANDS) + ")")
    args = parser.parse_args(argv)
    names = [n.strip() for n in args.commands.split(",") if n.strip()]
    unknown = [n for n in names if n not in COMMANDS]
    if unknown:
        parser.error(f"unknown command(s) {', '.join(unknown)}; known: {', '.join(COMMANDS)}")
    with tempfile.TemporaryDirectory(prefix="mcbat-first-call-") as tmp:
        work = Path(tmp)
        if {"fit", "compare", "check"} & set(names):
            setup(work)
        metrics = {"commands": {name: first_call(name, work) for name in names}}
    cold = [m["cold_wall_s"] for m in metrics["commands"].values()]
    cold_cpu = [m["cold_cpu_s"] for m in metrics["commands"].values()]
    metrics["max_cold_wall_s"], metrics["max_cold_cpu_s"] = max(cold), max(cold_cpu)
    harness.record("first_call", metrics, {
        "numba_num_threads": 2, "cache": "an empty NUMBA_CACHE_DIR per command",
        "commands": names})


if __name__ == "__main__":
    main()
