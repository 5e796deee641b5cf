"""Compile kernel groups in a second process while a command compiles its own.

A command's first call on a fresh install compiles several independent kernel groups
one after the other (a game study's run: the sampler, the game kernel, the flight
kernel), on one core. When its first compile starts, ``mcbat.cli.compiling.notice``
hands the other groups the command still needs to ``start``: a helper process
(``python -m mcbat.cli.precompile GROUP ...``) compiles them into numba's on-disk cache
on the second core, and before this process first calls a kernel of one of them it waits
for the helper (``mcbat.core.jit.await_group``) and then loads the machine code instead
of compiling it again.

Each group is compiled by calling its kernels once on one row of zeros, through the
same solving-layer functions, with the same argument types, as the commands call them (a
row of zeros is an invalid input: the kernels answer with a status code, and compile all
the same). Results never depend on which process compiled a kernel (``mcbat.core.jit``:
strict IEEE arithmetic). ``MCBAT_PARALLEL_COMPILE=0`` turns the helper off; so does a
machine with one core.
"""

from __future__ import annotations

import os
import subprocess
import sys

__all__ = ["COMPILERS", "ENV", "compile_group", "parallel", "start"]

#: The environment variable that turns the helper off when set to 0.
ENV = "MCBAT_PARALLEL_COMPILE"


def _game() -> None:
    import numpy as np

    from mcbat.solving import GAME_INPUT_FIELDS, SolverSettings, solve_games

    solve_games(np.zeros((len(GAME_INPUT_FIELDS), 1)), SolverSettings())


def _bat_frame() -> None:
    import numpy as np

    from mcbat.solving import (
        INPUT_FIELDS,
        SolverSettings,
        impact_history,
        solve_impacts,
        solve_one_impact,
    )
    from mcbat.solving.single import IMPACT_INPUT_COUNT

    solve_impacts(np.zeros((len(INPUT_FIELDS), 1)), SolverSettings())
    solve_one_impact((0.0,) * IMPACT_INPUT_COUNT, SolverSettings())
    impact_history(np.eye(3), np.array([0.0, 0.0, -1.0]), 0.5, np.linspace(0.0, 1e-3, 3),
                   SolverSettings())


def _flight() -> None:
    import numpy as np

    from mcbat.solving import fly_balls, fly_balls_each, fly_one, fly_sampled
    from mcbat.solving import heights_at_distance as heights
    from mcbat.study.flight import FlightSettings, params_each

    settings = FlightSettings()
    params = settings.params(0.145, 0.0366)
    start, v, w = (0.0, 0.6, 0.9), (0.0, 40.0, 10.0), (0.0, 0.0, 0.0)
    fly_one(params, start, v, w)
    fly_sampled(params, start, v, w, np.empty((4, 2)), 0.5)
    velocity, spin = np.zeros((3, 1)), np.zeros((3, 1))
    velocity[1, 0] = 40.0
    fly_balls(params, start, velocity, spin)
    each = params_each(settings, 0.145, 0.0366, 1)
    starts = np.ascontiguousarray(np.array(start)[:, None])
    fly_balls_each(each, starts, velocity, spin)
    heights(each, starts, velocity, spin, np.full(1, 50.0))


def _sampling() -> None:
    from importlib import resources

    from mcbat.study import load_study

    with resources.as_file(resources.files("mcbat.studies").joinpath("example.toml")) as path:
        load_study(path).sample(0, 1)


def _inference() -> None:
    from importlib import resources

    import mcbat.statcast as sc
    from mcbat.inference import infer_spin

    sample = resources.files("mcbat.data").joinpath("statcast_2020-09-03_in_play.csv")
    with resources.as_file(sample) as path:
        table = sc.read(path)
    infer_spin(table.head(2))


#: Kernel group (``mcbat.cli.compiling.KERNEL_GROUPS``) -> what compiles it.
COMPILERS = {"game": _game, "bat_frame": _bat_frame, "flight": _flight,
             "sampling": _sampling, "inference": _inference}


def compile_group(name: str) -> None:
    """Compile (or load) the kernels of group ``name`` in this process."""
    COMPILERS[name]()


def parallel() -> bool:
    """Whether a helper may compile: two cores for this process, and not turned off."""
    if os.environ.get(ENV, "1").strip() == "0":
        return False
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # (no affinity on this platform)
        cores = os.cpu_count() or 1
    return cores >= 2


def start(groups) -> subprocess.Popen | None:
    """Start a helper compiling ``groups`` (names, in that order); None if it cannot
    start. Its output is discarded: a group it fails to compile is compiled by the
    command itself, as without a helper."""
    try:
        return subprocess.Popen([sys.executable, "-m", "mcbat.cli.precompile", *groups],
                                stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
    except OSError:
        return None


def main(argv=None) -> int:
    """Compile the groups named in ``argv``; exit 0, or 1 if one failed."""
    names = sys.argv[1:] if argv is None else argv
    failed = 0
    for name in names:
        try:
            compile_group(name)
        except Exception:  # noqa: BLE001 - the command compiles what is missing itself
            failed = 1
    return failed


if __name__ == "__main__":
    sys.exit(main())
