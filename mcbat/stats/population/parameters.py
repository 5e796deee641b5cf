"""The free parameters of a population fit (``mcbat.stats.population.fit``): the study keys
whose distribution's mean and width it fits, and the physics constants it sets."""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy import special

from mcbat.errors import InputError
from mcbat.stats.population.table import PITCH_COLUMNS
from mcbat.study import units as u
from mcbat.study.game_keys import KEYS

__all__ = ["PHYSICS", "PHYSICS_RANGE", "FreeKey", "fittable_parameters", "parse_free"]

PHYSICS = {"e": ("restitution", "e_ref"), "mu": ("friction", "mu"),
           "e_x": ("restitution", "e_x")}
"""Physics constants a population fit can free, and the study key each sets."""
PHYSICS_RANGE = {"e": (0.2, 0.8), "mu": (0.0, 1.5), "e_x": (0.0, 1.0)}
_FITTABLE_FIELDS = {"normal": ("mean", "std"), "truncnormal": ("mean", "std")}
_SI = {"speed": "mph", "angle": "deg", "length": "in", "spin": "rpm", "dimensionless": "1"}
"""The unit parameters are reported (and fitted) in when the study wrote none."""


@dataclass
class FreeKey:
    """A free study key: its distribution (in the reporting unit) and where it is drawn."""

    key: str
    column: str
    kind: str
    unit: str
    scale: float  # SI per reporting unit
    mean: float
    std: float
    low: float = -math.inf
    high: float = math.inf

    def logpdf(self, x, mean, std):
        """Log density (up to a constant common to every parameter value) at ``x``."""
        z = (x - mean) / std
        out = -0.5 * z * z - math.log(std)
        if self.kind == "truncnormal":
            mass = (special.ndtr((self.high - mean) / std)
                    - special.ndtr((self.low - mean) / std))
            out = out - math.log(max(mass, 1e-300))
        return out

    def spec(self, mean, std):
        """The TOML spec of this distribution with ``mean``, ``std`` (reporting unit)."""
        spec = {"dist": self.kind, "mean": mean, "std": std, "unit": self.unit}
        if self.kind == "truncnormal":
            spec.update(low=self.low, high=self.high)
        return spec


def _key_of(study, key):
    dist = study.inputs.get(key)
    section, name = key.split(".", 1)
    if dist is None or dist.kind not in _FITTABLE_FIELDS:
        what = "is not in the study" if dist is None else f"is a {dist.kind} distribution"
        raise InputError("free", f"{key} {what}: a population fit frees the mean and std "
                         f"of a normal or truncnormal key (the study's: "
                         f"{', '.join(fittable_parameters(study)) or 'none'})")
    unit = dist.unit or _SI.get(dist.quantity, u.SI_UNITS[dist.quantity])
    scale = u.factor(unit, dist.quantity)
    low, high = dist.support() if dist.kind == "truncnormal" else (-math.inf, math.inf)
    return FreeKey(key, KEYS[section][name][2], dist.kind, unit, scale, dist.mean / scale,
                dist.std / scale, low / scale, high / scale)


def fittable_parameters(study):
    """The names a population fit of ``study`` can free: ``<key>.mean``, ``<key>.std`` of
    its normal and truncnormal keys that are not measured pitch values, and
    ``PHYSICS``."""
    names = [f"{key}.{f}" for key, dist in study.inputs.items()
             if getattr(dist, "kind", None) in _FITTABLE_FIELDS and key not in PITCH_COLUMNS
             for f in _FITTABLE_FIELDS[dist.kind]]
    return names + list(PHYSICS)


def parse_free(study, free):
    """``(keys, dist_params, physics)`` of the free parameter names, each checked."""
    if getattr(study, "kind", None) != "game":
        raise InputError("study", "a population fit needs a game study (with [pitch] and "
                         "[swing]: docs/batting.md)")
    keys, params, physics = {}, [], []
    for name in free:
        if name in PHYSICS:
            physics.append(name)
            continue
        key, _, what = name.rpartition(".")
        if key in PITCH_COLUMNS:
            raise InputError("free", f"{name}: the pitch is measured row by row, not drawn")
        if key == "swing.vertical_bat_angle" and getattr(
                getattr(study, "pitches", None), "swing_plane", False):
            raise InputError("free", f"{name}: with [pitches] swing_plane = true the bat's "
                             "angle follows from each row's measured swing plane")
        if what not in ("mean", "std") or not key:
            raise InputError("free", f"unknown parameter {name!r} (the study's: "
                             f"{', '.join(fittable_parameters(study))})")
        if key not in keys:
            keys[key] = _key_of(study, key)
        params.append((name, key, what))
    if not free or len(set(free)) != len(free):
        raise InputError("free", "give each parameter once, at least one")
    for name in physics:
        section, key = PHYSICS[name]
        if f"{section}.{key}" in keys:
            raise InputError("free", f"{name} sets {section}.{key}, whose distribution's "
                             "parameters are free too: free one or the other")
    return keys, params, physics
