"""The line a command prints when it starts compiling numba kernels, and the kernel groups.

A fresh install compiles the kernels a command needs on its first call (10-20 s on two
cores, ``docs/accuracy-and-speed.md``); later calls load them from numba's cache. Rather
than sit silent, the first compile of a command prints one line on stderr, at once:

    mcbat: compiling the game kernel and the flight kernel (first run only, about 15 s)

naming the kernel groups of the command (``COMMAND_GROUPS``) that are still to compile,
with the time they take (``KERNEL_GROUPS``). ``notice`` is the one place that does it,
around every command in ``mcbat.cli.app.main``: it listens for numba's own compile event
(its cache misses), so a warm command (everything loaded from the cache) prints nothing,
and an error found before any kernel runs stays the command's one line. A command with
``--quiet`` prints nothing; a study run prints its own line before its progress bar
(``mcbat.runner.compiling``). ``mcbat warmup`` compiles every group ahead of time.
"""

from __future__ import annotations

import contextlib
import importlib
import sys
from dataclasses import dataclass

from mcbat.cli.common import progress

__all__ = ["COMMAND_GROUPS", "KERNEL_GROUPS", "SOLVER", "KernelGroup", "command_groups",
           "compiling_line", "group_of", "notice"]


@dataclass(frozen=True)
class KernelGroup:
    """Kernels compiled together: what the line calls them, their entry points
    (``"module:function"``), and the seconds their first compile takes on two cores
    besides the shared impact solver (``SOLVER``), if ``uses_solver``."""

    label: str
    entries: tuple[str, ...]
    seconds: float
    uses_solver: bool = False

    def dispatchers(self) -> list:
        """The entry points' numba dispatchers (importing their modules compiles nothing)."""
        found = []
        for entry in self.entries:
            module, name = entry.split(":")
            found.append(getattr(importlib.import_module(module), name))
        return found


#: The impact solver every game, bat-frame and inference kernel calls (compiled once,
#: cached on its own): its entry point and seconds.
SOLVER = ("mcbat.core.cabo2012.impact:solve_impact", 8.0)

#: Every kernel group (``mcbat warmup`` compiles them in this order). The seconds are
#: first compiles measured on two cores (``python -m benchmarks first_call``).
KERNEL_GROUPS = {
    "game": KernelGroup("the game kernel", ("mcbat.core.swing.game:solve_game_batch",), 5.0,
                        True),
    "flight": KernelGroup("the flight kernel", (
        "mcbat.core.flight.trajectory:fly", "mcbat.core.flight.trajectory:integrate",
        "mcbat.core.flight.trajectory:fly_batch",
        "mcbat.core.flight.trajectory:fly_batch_each",
        "mcbat.core.flight.trajectory:height_at_distance_batch"), 6.0),
    "bat_frame": KernelGroup("the bat-frame kernel", (
        "mcbat.core.batch:solve_batch", "mcbat.core.cabo2012.impact:solve_impact"), 2.0, True),
    "sampling": KernelGroup("the sampler", ("mcbat.core.sampling:draw_random_inputs",), 5.0),
    # (the inference kernel calls the game's row function by address: the game group
    # compiles it, ``mcbat.solving.inference``)
    "inference": KernelGroup("the inference kernel", (
        "mcbat.core.contact_inference.solver:infer_contact_batch",), 10.0),
}

_GAME = ("game", "flight")


def _study_groups(path, flies) -> tuple[str, ...]:
    """The groups of a study's kernels: the game's (and the flight's, if ``flies`` and the
    study has ``[flight]``) or the bat frame's (the study file read as TOML; a game with
    flight if it cannot be read: a shipped study's name)."""
    import tomllib
    from pathlib import Path

    from mcbat.study.game_keys import is_game

    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError, TypeError, RecursionError):  # (the command reports it)
        return _GAME if flies else ("game",)
    if not is_game(data):
        return ("bat_frame",)
    return _GAME if flies and "flight" in data else ("game",)


def command_groups(args) -> tuple[str, ...]:
    """The kernel groups the command of the parsed ``args`` compiles on a first run (a
    bat-frame case of ``impact`` is told apart when it compiles: ``notice``)."""
    command = getattr(args, "command", None)
    study = getattr(args, "study", None)
    if command in ("run", "synth") or (command in ("fit", "calibrate") and study
                                       and not getattr(args, "flight", False)):
        flies = command == "run"  # (fit, synth and calibrate do not fly the balls)
        return ("sampling", *_study_groups(study, flies)) if study else ("sampling", *_GAME)
    if command == "reproduce":
        return {"sawicki2003": _GAME, "statcast": ("flight",)}.get(
            getattr(args, "paper", None), ("sampling", "bat_frame"))
    return COMMAND_GROUPS.get(command, ())


#: The kernel groups of each command that compiles (a study's commands: its kind's,
#: ``command_groups``).
COMMAND_GROUPS = {
    "impact": _GAME,
    "flight": ("flight",),
    "calibrate": ("bat_frame",),
    "fit": ("flight",),  # (--flight; with a study, the study's groups)
    "infer": ("inference", "game"),
    "replay": ("flight",),
}


def group_of(dispatcher) -> str | None:
    """The name of the group whose entry point ``dispatcher`` is, if any."""
    for name, group in KERNEL_GROUPS.items():
        for entry in group.entries:
            module, function = entry.split(":")
            if (getattr(dispatcher, "py_func", None) is not None
                    and dispatcher.py_func.__module__ == module
                    and dispatcher.py_func.__name__ == function):
                return name
    return None


def _cold(name) -> bool:
    from mcbat.core.jit import is_cold

    try:
        return any(is_cold(d) is not False for d in KERNEL_GROUPS[name].dispatchers())
    except (ImportError, AttributeError):
        return True


def _seconds(names) -> float:
    """The seconds compiling the groups ``names`` in one process takes (with the shared
    solver if one of them calls it and it is still to compile)."""
    from mcbat.core.jit import is_cold

    groups = [KERNEL_GROUPS[n] for n in names]
    seconds = sum(g.seconds for g in groups)
    if any(g.uses_solver for g in groups):
        module, function = SOLVER[0].split(":")
        if is_cold(getattr(importlib.import_module(module), function)) is not False:
            seconds += SOLVER[1]
    return seconds


def compiling_line(names, helped=()) -> str:
    """The line for compiling the groups ``names`` here while a helper process compiles
    the groups ``helped`` (``mcbat.cli.precompile``; the time is the longer of the two)."""
    groups = [KERNEL_GROUPS[n] for n in (*names, *helped)]
    if not groups:
        return "mcbat: compiling the kernels (first run only)"
    seconds = max(_seconds(names), _seconds(helped) + HELPER_START) if helped \
        else _seconds(names)
    labels = [g.label for g in groups]
    what = labels[0] if len(labels) == 1 else ", ".join(labels[:-1]) + " and " + labels[-1]
    where = " on two cores" if helped else ""
    return (f"mcbat: compiling {what}{where} (first run only, about "
            f"{5 * max(1, round(seconds / 5)):.0f} s)")


#: Seconds a helper process takes to start (importing mcbat, numba and numpy).
HELPER_START = 1.5
#: The most seconds a command waits for its helper before compiling on its own.
HELPER_PATIENCE = 600.0


class _FirstCompile:
    """numba listener: on the first compile event, start the helper (``mcbat.cli.
    precompile``) on the other cold groups of the command and print the line, once."""

    def __init__(self, args, stream, say):
        self.args, self.stream, self.say, self.said = args, stream, say, False
        self.helper, self.split = None, False

    def on_start(self, dispatcher) -> None:
        own = group_of(dispatcher)
        if self.split or (self.said and own is None):
            return
        names = [n for n in command_groups(self.args) if _cold(n)]
        if own is not None and own not in names:
            names = [own]  # (a bat-frame case of impact, a bat-frame study)
        if own is not None:
            # This process compiles the group it has started on; a helper the others, in
            # the order the command needs them. (A kernel outside every group, compiled
            # first, does not tell which group comes first: the split waits for one.)
            self.split = True
            helped = [n for n in names if n != own]
            if helped and _start_helper(self, helped):
                names = [own]
            else:
                helped = []
        else:  # (the likely split, for the line)
            names = sorted(names, key=lambda n: -_seconds([n]))
            helped, names = (names[1:], names[:1]) if len(names) > 1 and \
                _parallel() else ([], names)
        if self.said:
            return
        self.said = True
        from mcbat.core.jit import said_compiling

        if self.say and not said_compiling["line"]:  # (a study run may have said it)
            line = compiling_line(names, helped)
            print(line, file=self.stream or sys.stderr, flush=True)
            said_compiling["line"] = line

    def close(self) -> None:
        """Stop a helper still running (the command ended first) and forget it."""
        from mcbat.core.jit import compiled_elsewhere

        compiled_elsewhere((), None)
        helper, self.helper = self.helper, None
        if helper is not None and helper.poll() is None:
            helper.terminate()
            with contextlib.suppress(Exception):
                helper.wait(timeout=5)


def _parallel() -> bool:
    from mcbat.cli import precompile

    return precompile.parallel()


def _start_helper(first: _FirstCompile, groups) -> bool:
    """Start a helper compiling ``groups`` and tell the solving layer to wait for it;
    False if none may (``mcbat.cli.precompile.parallel``) or it did not start."""
    from mcbat.cli import precompile
    from mcbat.core.jit import compiled_elsewhere

    if not _parallel():
        return False
    helper = precompile.start(groups)
    if helper is None:
        return False
    first.helper = helper

    def wait() -> None:
        try:
            helper.wait(timeout=HELPER_PATIENCE)
        except Exception:  # noqa: BLE001 - a stuck helper: compile here instead
            helper.kill()

    compiled_elsewhere(groups, wait)
    return True


@contextlib.contextmanager
def notice(args, stream=None):
    """Within the block, the first numba compile (a cache miss) starts a helper process on
    the command's other cold kernel groups (``mcbat.cli.precompile``) and prints the
    compiling line for the command of ``args`` to ``stream`` (default stderr); no line
    for a command that compiles no kernel of its own, nor with ``--quiet``. A helper
    still running when the block ends is stopped."""
    if not command_groups(args):
        yield
        return
    from mcbat.core.jit import said_compiling

    said_compiling["line"] = None
    first = _FirstCompile(args, stream, progress(args))
    try:
        from numba.core import event
    except ImportError:  # no numba event API: no line, the command runs as before
        yield
        return

    class Listener(event.Listener):
        def on_start(self, ev):
            first.on_start((ev.data or {}).get("dispatcher"))

        def on_end(self, ev):
            pass  # the listener interface needs it; only the start of a compile is reported

    try:
        with event.install_listener("numba:compile", Listener()):
            yield
    finally:
        first.close()
