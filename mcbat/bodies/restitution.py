"""The restitution of a baseball on a wood bat at game speeds: the parameters of the model
of ``mcbat.core.restitution`` (``e*`` by normal speed and contact position, the
tangential ``e_x``), the game preset with its sources (``docs/batting.md``), and the
location tables of ``data/``.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass

import numpy as np

from mcbat.bodies.tables import data_file
from mcbat.checks import check_real
from mcbat.errors import InputError

__all__ = ["GAME_E_X", "GAME_RESTITUTION", "LOCATION_TABLES", "Restitution", "location_table"]

#: Tangential restitution e_x at game speeds: 0.2, fitted to the backspin inferred from the
#: tracked balls in play of 2024 (their measured pitches and swings) against Nathan's
#: average spin model of tracked balls, and judged on 2025's (docs/spin_inference.md);
#: inside the laboratory range (Cross & Nathan 2006: ~0.16 in this model; Nathan et al.,
#: Procedia Eng. 34, 182 (2012): ~0.30; Kensrud, Nathan & Smith, Am. J. Phys. 85, 503
#: (2017): ~0.4). One value for every caller: studies without [restitution], ``mcbat
#: impact`` and the spin inference. The game presets with an assumed swing keep their own
#: fitted 0.28 (docs/batting.md, "Batted-ball spin").
GAME_E_X = 0.2

#: Location tables shipped in ``data/`` (name -> file). None is a measurement: no table of
#: a wood bat's COR against the impact point is shipped. ``"assumed"`` (the game presets')
#: is flat between the barrel-end nodes of the first two bending modes and falls on both
#: sides at rates chosen so that ``q`` peaks there; ``"bat_tracking"`` (the bat-tracking
#: study's) is the same with its barrel-end side steeper, chosen with the contact's
#: pitch-location trend on tracked balls in play (provenance: ``data/README.md``; what
#: they do to ``q``: ``docs/batting.md``, ``docs/bat_tracking.md``).
LOCATION_TABLES = {"illustrative": "restitution_location_illustrative.csv",
                   "assumed": "restitution_location_assumed.csv",
                   "bat_tracking": "restitution_location_bat_tracking.csv"}


@dataclass(frozen=True)
class Restitution:
    """``e* = clip((e_ref - e_slope (|v_n| - e_speed_ref)) f(from_barrel_end), 0, 1)``.

    ``|v_n|`` is the normal approach speed of the contact points (m/s); ``f`` the
    location table (None: 1). A constant ``e*`` is ``Restitution(e_ref=e)``.
    """

    e_ref: float = 1.0
    e_slope: float = 0.0
    e_speed_ref: float = 0.0
    location: str | None = None
    e_x: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "e_ref",
                           check_real(self.e_ref, "e_ref", minimum=0.0, maximum=1.0))
        object.__setattr__(self, "e_slope", check_real(self.e_slope, "e_slope"))
        object.__setattr__(self, "e_speed_ref",
                           check_real(self.e_speed_ref, "e_speed_ref", minimum=0.0))
        object.__setattr__(self, "e_x", check_real(self.e_x, "e_x", minimum=0.0, maximum=1.0))
        if self.location is not None:
            location_table(self.location)

    def location_factor(self, from_barrel_end):
        """The table's factor at ``from_barrel_end`` (m), linear between rows and constant
        beyond the ends; 1 without a table. Float for a float, else an array."""
        if self.location is None:
            out = np.ones(np.shape(from_barrel_end))
        else:
            z, f = location_table(self.location)
            out = np.interp(from_barrel_end, z, f)
        return float(out) if np.ndim(out) == 0 else out

    def config(self) -> dict:
        """As plain data."""
        return {"e_ref": self.e_ref, "e_slope": self.e_slope, "e_speed_ref": self.e_speed_ref,
                "location": self.location, "e_x": self.e_x}


#: The game default: e* = 0.555 at a normal speed of 85 ft/s (the MLB ball specification's
#: mean COR against a wood wall, 2017), falling linearly to 0.4757 at 165.5 mph (a 94 mph
#: pitch on a 71.5 mph swing), where the rigid model then gives q = 0.21 at the R161's
#: sweet spot: the midpoint of q ~ 0.20 (Nathan 2003) and ~ 0.22 (Statcast's squared-up
#: examples). Derivation: docs/batting.md.
GAME_RESTITUTION = Restitution(e_ref=0.555, e_slope=0.00165, e_speed_ref=25.908,
                               e_x=GAME_E_X)

_TABLES: dict[str, tuple[np.ndarray, np.ndarray]] = {}


def location_table(name: str) -> tuple[np.ndarray, np.ndarray]:
    """``(from_barrel_end (m), factor)`` of the shipped table ``name``."""
    if name not in LOCATION_TABLES:
        raise InputError("location", f"unknown restitution location table {name!r} "
                         f"(expected one of: {', '.join(LOCATION_TABLES)})")
    if name not in _TABLES:
        text = data_file(LOCATION_TABLES[name]).read_text(encoding="utf-8")
        rows = [r for r in csv.reader(io.StringIO(text)) if r and not r[0].startswith("#")]
        body = np.array([[float(c) for c in r] for r in rows[1:]])
        z, f = body[:, 0] * 0.0254, body[:, 1]
        if not (np.all(np.diff(z) > 0) and np.all(f >= 0) and np.all(np.isfinite(f))):
            raise ValueError(f"bad restitution table {name!r}")
        _TABLES[name] = (z, f)
    return _TABLES[name]
