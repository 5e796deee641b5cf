"""The studies mcbat ships (``studies/`` of the repository, the resource package
``mcbat.studies``), named on any command that takes a study, from any directory
(``mcbat run game_fastball``, ``mcbat fit --study bat_tracking``)."""

from __future__ import annotations

import contextlib
import sys
import tomllib
from importlib import resources
from pathlib import Path

from mcbat.errors import InputError

__all__ = ["shipped_studies", "study_file"]


def shipped_studies() -> dict[str, str]:
    """The studies mcbat ships: name (the file's stem) -> its ``[study] description``."""
    out = {}
    for entry in sorted(resources.files("mcbat.studies").iterdir(), key=lambda e: e.name):
        if entry.name.endswith(".toml"):
            try:
                study = tomllib.loads(entry.read_text(encoding="utf-8")).get("study", {})
            except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
                study = {}
            out[entry.name.removesuffix(".toml")] = str(study.get("description", ""))
    return out


def study_file(given, flag=None):
    """A context giving the path of the study ``given``: a file that exists, else the
    shipped study of that name (``game_fastball``, ``game_fastball.toml`` or
    ``studies/game_fastball.toml``). ``flag`` names the option in an error."""
    path = Path(given)
    if path.exists() or not (len(path.parts) == 1 or path.parent == Path("studies")):
        return contextlib.nullcontext(path)  # load_study reports a missing or bad file
    name = path.name.removesuffix(".toml")
    shipped = shipped_studies()
    if name not in shipped:
        raise InputError(flag, f"{given}: no such study file, and no study of that name "
                         f"ships with mcbat (shipped: {', '.join(shipped)}; mcbat run "
                         "--list describes them)")
    print(f"mcbat: {given}: not found here; using the study {name!r} shipped with mcbat",
          file=sys.stderr)
    return resources.as_file(resources.files("mcbat.studies").joinpath(f"{name}.toml"))
