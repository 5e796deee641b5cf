"""``mcbat warmup``: compile every numba kernel once, so that no later command waits for
it (a fresh install's first commands otherwise compile what they need, 10-20 s each)."""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from importlib import resources
from pathlib import Path

from mcbat.cli.common import EXIT_INTERNAL, EXIT_OK, Command

__all__ = ["COMMAND", "WARMUPS", "cmd_warmup"]

#: A game case (``examples/game_fastball.json``), a bat-frame case (Cabo et al.'s Sec. V
#: bodies) and a batted ball: the inputs of the commands each group is compiled by.
GAME_CASE = {"handedness": "R", "bat": {"preset": "r161"},
             "pitch": {"release_speed": 94, "extension": 6.3, "vertical_approach_angle": -5,
                       "spin_rate": 2300, "spin_axis": 210},
             "swing": {"bat_speed": 72, "attack_angle": 10, "vertical_bat_angle": -30},
             "contact": {"from_barrel_end": {"value": 6, "unit": "in"},
                         "undercut": {"value": 0.5, "unit": "in"}},
             "mu": 0.5}
BAT_FRAME_CASE = {"ball": {"mass": 0.145, "radius": 0.036, "inertia_factor": 0.4},
                  "bat": {"mass": 0.989, "radius": 0.03335, "transverse_inertia": 0.046,
                          "axial_inertia": 4.39e-4},
                  "contact": {"axial": 0.115, "angle": 0.007853981633974483},
                  "ball_velocity": [-4.0, 0.0, 0.0], "ball_spin": [0.0, 0.0, 0.0],
                  "mu": 0.5, "restitution": {"loss_fraction": 0.6183822}}
BATTED_BALL = {"launch_speed": {"value": 103, "unit": "mph"},
               "launch_angle": {"value": 27, "unit": "deg"},
               "backspin": {"value": 2000, "unit": "rpm"}}

#: Kernel group (``mcbat.cli.compiling.KERNEL_GROUPS``) -> the commands that compile it,
#: run on small inputs (``{dir}``: a scratch folder; ``{statcast}``: the balls in play of
#: 2020-09-03 that ship with mcbat, ``data/README.md``). Running the commands themselves
#: (each in a process of its own) compiles exactly what they call.
WARMUPS = {
    "game": [["impact", "{dir}/game.json"]],
    "flight": [["flight", "{dir}/ball.json", "--trajectory", "0.5"],
               ["flight", "{dir}/ball.json"], ["replay", "{statcast}"]],
    "bat_frame": [["impact", "{dir}/bat_frame.json"],
                  ["reproduce", "--samples", "64", "--out", "{dir}/cabo2012", "--quiet"]],
    "sampling": [["run", "example", "--samples", "64", "--out", "{dir}/example", "--quiet"],
                 ["run", "game_fastball", "--samples", "64", "--out", "{dir}/game", "--quiet"]],
    "inference": [["infer", "{statcast}"]],
}


def _run(argv) -> tuple[int, str]:
    """``mcbat ARGV`` in a process of its own, as a user would run it; returns (exit code,
    stderr)."""
    proc = subprocess.run([sys.executable, "-m", "mcbat.cli", *argv], capture_output=True,
                          text=True, stdin=subprocess.DEVNULL)
    return proc.returncode, proc.stderr


def cmd_warmup(args) -> int:
    """Compile (or load) every kernel group; one line each, then the total."""
    from mcbat.cli.compiling import KERNEL_GROUPS

    status = EXIT_OK
    t_all = time.perf_counter()
    sample = resources.files("mcbat.data").joinpath("statcast_2020-09-03_in_play.csv")
    with tempfile.TemporaryDirectory(prefix="mcbat-warmup-") as tmp, \
            resources.as_file(sample) as statcast:
        for name, case in (("game", GAME_CASE), ("bat_frame", BAT_FRAME_CASE),
                           ("ball", BATTED_BALL)):
            Path(tmp, f"{name}.json").write_text(json.dumps(case), encoding="utf-8")
        for name, commands in WARMUPS.items():
            t0 = time.perf_counter()
            failed = None
            for command in commands:
                argv = [a.format(dir=tmp, statcast=statcast) for a in command]
                code, err = _run(argv)
                if code != 0:
                    lines = err.strip().splitlines()
                    failed = f"mcbat {command[0]} exited {code}: {lines[-1] if lines else ''}"
                    break
            seconds = time.perf_counter() - t0
            label = KERNEL_GROUPS[name].label
            if failed:
                status = EXIT_INTERNAL
                print(f"mcbat: {label}: failed after {seconds:.1f} s ({failed})", flush=True)
            else:
                print(f"mcbat: {label}: ready in {seconds:.1f} s", flush=True)
    print(f"mcbat: warmup done in {time.perf_counter() - t_all:.1f} s; later commands load "
          "the kernels from numba's cache", file=sys.stdout, flush=True)
    return status


COMMAND = Command(
    "warmup", help="compile every kernel once (after installing: later commands start "
                   "at once)",
    description="Compile every numba kernel mcbat has (the game, flight, bat-frame, "
                "sampling and inference kernels) by running each command that uses "
                "them on a small input, and cache the machine code (numba's cache, "
                "beside the package or in NUMBA_CACHE_DIR), so that no later command "
                "compiles. Prints a line per kernel group and the total time; a group "
                "already compiled loads in a second.",
    arguments=(),
    run=cmd_warmup)
