"""Bat profiles from tables: the TSV reader and the bundled presets.

This module does the file I/O that ``mcbat.bodies.profile`` must not. Tables list the
bat's diameter against the distance from the knob end (format and provenance of the
bundled tables: ``data/README.md``).
"""

from __future__ import annotations

import math
from importlib import resources
from pathlib import Path

import numpy as np

from mcbat.bodies.profile import BatProfile

__all__ = ["WOOD_DENSITY", "data_file", "load_profile_tsv", "r161_profile", "read_profile_tsv"]

#: Typical density of bat-grade wood (ash), kg/m^3.
WOOD_DENSITY = 649.0

_COLUMNS = ("distance from knob (cm)", "diameter (mm)")


def data_file(name: str):
    """A bundled table of the project's ``data/`` folder (shipped in the wheel as the
    resource package ``mcbat.data``; provenance in its ``README.md``)."""
    return resources.files("mcbat.data").joinpath(name)


def read_profile_tsv(path):
    """Read a knob-based profile table, converted to metres.

    Format: one row per line, two whitespace- or tab-separated columns: distance from
    the knob end in cm (strictly increasing) and diameter in mm (``>= 0``). Blank lines
    and lines whose first non-blank character is ``#`` are skipped.

    Parameters
    ----------
    path : str or os.PathLike
        The table file.

    Returns
    -------
    distance_from_knob_m, diameter_m : ndarray
        Both in metres.

    Raises
    ------
    ValueError
        Naming the file, and the line and column of the offending entry.
    OSError
        If the file cannot be read.
    """
    path = path if hasattr(path, "open") and not isinstance(path, str) else Path(path)
    distances, diameters = [], []
    previous_line = None
    with path.open(encoding="utf-8") as handle:
        for lineno, line in enumerate(handle, start=1):
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            fields = text.split()
            if len(fields) != 2:
                raise ValueError(
                    f"{path}: line {lineno}: expected 2 columns ({', '.join(_COLUMNS)}), "
                    f"got {len(fields)}: {text!r}"
                )
            values = []
            for column, (name, raw) in enumerate(zip(_COLUMNS, fields), start=1):
                try:
                    value = float(raw)
                except ValueError:
                    raise ValueError(
                        f"{path}: line {lineno}: column {column} ({name}): not a number: {raw!r}"
                    ) from None
                if not math.isfinite(value):
                    raise ValueError(
                        f"{path}: line {lineno}: column {column} ({name}): must be finite, "
                        f"got {raw!r}"
                    )
                values.append(value)
            distance, diameter = values
            if diameter < 0.0:
                raise ValueError(f"{path}: line {lineno}: column 2 ({_COLUMNS[1]}): "
                                 f"must be >= 0, got {fields[1]!r}")
            if distances and not distance > distances[-1]:
                raise ValueError(
                    f"{path}: line {lineno}: column 1 ({_COLUMNS[0]}): must increase, got "
                    f"{fields[0]} after {distances[-1]!r} on line {previous_line}"
                )
            distances.append(distance)
            diameters.append(diameter)
            previous_line = lineno
    if len(distances) < 2:
        raise ValueError(f"{path}: needs at least 2 data rows, got {len(distances)}")
    return np.array(distances) * 1e-2, np.array(diameters) * 1e-3


def load_profile_tsv(path, density=WOOD_DENSITY) -> BatProfile:
    """Load a bat profile table (cm from the knob, mm diameter) as a ``BatProfile``.

    The bat spans exactly the tabulated rows (radius linear between rows for the mass
    properties); see ``read_profile_tsv`` for the format.

    Parameters
    ----------
    path : str or os.PathLike
        The table file.
    density : float, optional
        Uniform density, kg/m^3 (default 649, typical wood).

    Returns
    -------
    BatProfile
        In the lab frame: origin at the CM, ``z`` towards the barrel end.

    Raises
    ------
    ValueError
        For a malformed table (naming the file, line and column) or a bad density.
    """
    distance, diameter = read_profile_tsv(path)
    return _profile(path, distance, diameter, density)


def _profile(path, distance, diameter, density):
    try:
        return BatProfile.from_knob_table(distance, diameter, density)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


def r161_profile(density=WOOD_DENSITY) -> BatProfile:
    """The Louisville Slugger R161 wood bat (Nathan, Am. J. Phys. 68, 979 (2000)).

    Reads the bundled ``data/r161_profile.tsv``. The table's first row is 1 cm from the knob
    end; the preset adds the knob's end face at 0 cm with the first row's diameter (the
    knob is 50.5 mm wide at both 1 and 2 cm), so the bat spans its full 0.84 m.

    Parameters
    ----------
    density : float, optional
        Uniform density, kg/m^3 (default 649, typical wood).

    Returns
    -------
    BatProfile
        Length 0.84 m; at 649 kg/m^3 its mass is about 0.865 kg with the CM about
        0.558 m from the knob.
    """
    path = data_file("r161_profile.tsv")
    distance, diameter = read_profile_tsv(path)
    if distance[0] > 0.0:
        distance = np.concatenate(([0.0], distance))
        diameter = np.concatenate((diameter[:1], diameter))
    return _profile(path.name, distance, diameter, density)
