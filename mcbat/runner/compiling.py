"""Whether a run's first chunk will compile the kernels, and the line that says so.

numba compiles a kernel on its first call in a process unless its on-disk cache
(``cache=True``, ``mcbat.core.jit``) holds machine code for this CPU and this source.
The batch kernels take 10-20 s to compile, during which the progress bar would sit at
0 % with no word of why. ``is_cold`` (``mcbat.core.jit``) reads numba's cache index
without compiling or loading anything. Other commands say it at their first compile
(``mcbat.cli.compiling``).
"""

from __future__ import annotations

import sys

from mcbat.core.jit import is_cold, said_compiling

__all__ = ["COMPILING", "MAYBE_COMPILING", "announce_compiling", "is_cold",
           "kernels_for"]

COMPILING = "mcbat: compiling the kernels (first run only, about 25 s)"
MAYBE_COMPILING = "mcbat: the kernels may need compiling (first run only, about 25 s)"

def kernels_for(study) -> list:
    """The batch kernels a run of ``study`` calls: the game's (and the flight's, with
    ``[flight]``) or the bat frame's."""
    from mcbat.solving import batch_kernels

    return batch_kernels(getattr(study, "kind", "impact") == "game",
                         getattr(study, "flight", None) is not None)


def announce_compiling(kernels, stream=None) -> str | None:
    """Write one line to ``stream`` (default stderr) when a first call of one of
    ``kernels`` will compile it (or may: the cache could not be read), unless this command
    said it already (``mcbat.core.jit.said_compiling``: the command line's notice, at
    its first compile, or this); returns the line."""
    if said_compiling["line"]:
        return None
    states = [is_cold(kernel) for kernel in kernels]
    if any(states):
        line = COMPILING
    elif None in states:
        line = MAYBE_COMPILING
    else:
        return None
    print(line, file=sys.stderr if stream is None else stream, flush=True)
    said_compiling["line"] = line
    return line
