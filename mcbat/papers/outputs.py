"""The results directory of a reproduction: it writes only what it owns.

A reproduction writes a few fixed names (``summary.json``, ``figures/``...) into its results
directory and records them in the marker file ``MARKER`` there. Before any work, every
name it will write that already exists and is not recorded in the marker (a user's
``summary.json``, a ``figures/`` directory of someone else's) is refused, unless
``overwrite``; other files in the directory are never touched. Text files are written
atomically, and a full or read-only disk is one clear error about ``out``.
"""

from __future__ import annotations

import contextlib
import json
import os
from pathlib import Path

from mcbat.dataset import storage
from mcbat.errors import InputError

__all__ = ["MARKER", "ResultsDirectory", "echo_results"]

#: The marker of a reproduction's results directory: which paper wrote which names.
MARKER = "_mcbat_results.json"


class ResultsDirectory:
    """The results directory ``root`` of reproduction ``paper``, which writes ``names``.

    Parameters
    ----------
    root : str or Path
        The directory (created if missing).
    paper : str
        The reproduction's name (recorded in the marker).
    names : iterable of str
        Every file or directory name it writes directly in ``root``.
    overwrite : bool
        Replace existing names that another program (or a user) wrote.

    Raises
    ------
    InputError
        Naming ``out``: ``root`` is a file, or holds a name the run would write that
        mcbat did not write (without ``overwrite``).
    """

    def __init__(self, root, paper: str, names, *, overwrite: bool = False):
        self.root, self.paper, self.names = Path(root), paper, sorted(names)
        if self.root.exists() and not self.root.is_dir():
            raise InputError("out", "exists and is not a directory", str(self.root))
        owned = set(self._recorded())
        foreign = [name for name in self.names
                   if (self.root / name).exists() and name not in owned]
        if foreign and not overwrite:
            raise InputError("out", f"holds {foreign[0]!r}, which mcbat did not write; "
                             "pass {overwrite} to replace it, or choose another directory",
                             str(self.root), mentions={"overwrite": True})

    def _recorded(self) -> list:
        try:
            marker = json.loads((self.root / MARKER).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return []
        names = marker.get("names") if isinstance(marker, dict) else None
        return [n for n in names if isinstance(n, str)] if isinstance(names, list) else []

    @contextlib.contextmanager
    def writing(self):
        """Create the directory and claim the names (marker first, so a killed run's
        outputs stay claimed); a full or read-only disk becomes an error about ``out``."""
        try:
            self.root.mkdir(parents=True, exist_ok=True)
            names = sorted(set(self._recorded()) | set(self.names))
            storage.write_json_atomic({"paper": self.paper, "names": names},
                                      self.root / MARKER)
            yield self
        except OSError as err:
            reason = os.strerror(err.errno) if err.errno else str(err)
            raise InputError("out", f"cannot write the results: {reason}; free space (or fix "
                             "permissions) and rerun", str(self.root)) from None

    def write_text(self, name: str, text: str) -> Path:
        """Write ``text`` to ``root/name`` atomically; returns the path."""
        if name not in self.names:
            raise ValueError(f"{name!r} is not one of this run's names {self.names}")
        path = self.root / name
        storage.write_bytes_atomic(text.encode("utf-8"), path)
        return path

    def directory(self, name: str) -> Path:
        """The subdirectory ``root/name`` (one of the names), created."""
        if name not in self.names:
            raise ValueError(f"{name!r} is not one of this run's names {self.names}")
        path = self.root / name
        path.mkdir(exist_ok=True)
        return path


def echo_results(echo, root, seconds: float, files, figures, width: int) -> None:
    """Tell where a reproduction's results went, through ``echo``: the directory ``root``
    and the time taken, then one line per file of ``files`` (``(label, path)`` pairs)
    and per figure, the labels padded to ``width`` characters."""
    echo(f"results in {root}/ ({seconds:.1f} s):")
    for label, path in files:
        echo(f"  {label:<{width}}{path}")
    for path in figures:
        echo(f"  {'figure':<{width}}{path}")
