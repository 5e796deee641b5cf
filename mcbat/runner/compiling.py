"""Whether a run's first chunk will compile the kernels, and the line that says so.

numba compiles a kernel on its first call in a process unless its on-disk cache
(``cache=True``, ``mcbat.core.jit``) holds machine code for this CPU and this source.
The batch kernels take 20-30 s to compile, during which the progress bar would sit at
0 % with no word of why. The test reads the cache's index as numba's own lookup does (by
the CPU and the function's bytecode; the argument types are not compared), without
compiling or loading anything.
"""

from __future__ import annotations

import sys

__all__ = ["COMPILING", "MAYBE_COMPILING", "announce_compiling", "is_cold", "kernels_for"]

COMPILING = "mcbat: compiling the kernels (first run only, ~30 s)"
MAYBE_COMPILING = "mcbat: the kernels may need compiling (first run only, ~30 s)"


def is_cold(dispatcher):
    """True when calling ``dispatcher`` (a numba function) will compile it first: no
    machine code in this process, and none in its on-disk cache for this CPU and source;
    False when it will not; None when this numba's cache cannot be read this way."""
    if dispatcher.signatures:
        return False  # compiled (or loaded from the cache) in this process already
    try:
        cache = dispatcher._cache  # numba's internals: any change means "unknown"
        index = cache._cache_file._load_index()  # {} without a file, or for an old source
        wanted = cache._index_key(None, dispatcher.targetctx.codegen())[1:]
    except Exception:  # noqa: BLE001 - an unknown state, never a failed run
        return None
    return not any(tuple(key[1:]) == wanted for key in index)


def kernels_for(study) -> list:
    """The batch kernels a run of ``study`` calls: the game's (and the flight's, with
    ``[flight]``) or the bat frame's."""
    if getattr(study, "kind", "impact") != "game":
        from mcbat.core.batch import solve_batch

        return [solve_batch]
    from mcbat.core.swing import solve_game_batch

    if getattr(study, "flight", None) is None:
        return [solve_game_batch]
    from mcbat.core.flight import fly_batch

    return [solve_game_batch, fly_batch]


def announce_compiling(kernels, stream=None) -> str | None:
    """Write one line to ``stream`` (default stderr) when a first call of one of
    ``kernels`` will compile it (or may: the cache could not be read); returns the line."""
    states = [is_cold(kernel) for kernel in kernels]
    if any(states):
        line = COMPILING
    elif None in states:
        line = MAYBE_COMPILING
    else:
        return None
    print(line, file=sys.stderr if stream is None else stream, flush=True)
    return line
