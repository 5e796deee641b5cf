"""Ball and bat presets of study files (``preset = "..."``), and the bodies they describe.

Balls
    ``"baseball"``: 0.145 kg, radius 0.036 m, ``I = 0.4 m R^2`` (PHYSICS.md, Sec. V).
Bats
    ``"cross_nathan_2006"``: the Sec. V bat of PHYSICS.md (Cross & Nathan's experiment):
    0.989 kg, ``I_t = 0.046``, ``I_3 = 4.39e-4`` kg m^2, length 0.84 m, CM 0.265 m from the
    barrel end, and a cylinder of radius 0.03335 m at the contact (wherever it is).

    ``"r161"``: the Louisville Slugger R161 wood profile (:func:`mcbat.bats.r161_profile`,
    uniform density 649 kg/m^3): tapered, so the radius and slope at the contact come from
    the profile, and so do the mass properties.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numpy as np

from mcbat.core.geometry import ball_centre_radial_distance


@dataclass(frozen=True)
class BallSpec:
    """A ball: mass (kg), radius (m), inertia factor ``f`` in ``I = f m R^2``."""

    mass: float
    radius: float
    inertia_factor: float = 0.4
    preset: str | None = None

    def config(self) -> dict:
        return {"preset": self.preset, "mass": self.mass, "radius": self.radius,
                "inertia_factor": self.inertia_factor}


@dataclass(frozen=True, eq=False)
class BatSpec:
    """A bat: mass properties about its CM and the surface at the contact.

    Exactly one of ``radius`` (a cylinder at the contact, slope 0) and ``profile`` (a
    :class:`mcbat.core.profile.BatProfile`, lab frame: ``z`` from the CM) is set.
    ``length`` and ``cm_from_barrel_end`` (m) bound the contact's axial position and convert
    distances from the barrel end (``axial = cm_from_barrel_end - distance``).
    """

    mass: float
    transverse_inertia: float
    axial_inertia: float
    radius: float | None = None
    profile: object | None = None
    length: float | None = None
    cm_from_barrel_end: float | None = None
    preset: str | None = None

    @classmethod
    def from_profile(cls, profile, preset=None) -> "BatSpec":
        """A uniform-density profiled bat (mass properties from the profile)."""
        return cls(mass=profile.mass, transverse_inertia=profile.transverse_inertia,
                   axial_inertia=profile.axial_inertia, profile=profile,
                   length=profile.length, cm_from_barrel_end=profile.barrel_end,
                   preset=preset)

    def axial_bounds(self) -> tuple[float, float] | None:
        """``(knob end, barrel end)`` axial positions (m from the CM), if known."""
        if self.profile is not None:
            return self.profile.knob_end, self.profile.barrel_end
        if self.length is not None and self.cm_from_barrel_end is not None:
            return self.cm_from_barrel_end - self.length, self.cm_from_barrel_end
        return None

    def axial_from_barrel_end(self, distance):
        """Axial position (m from the CM) of a point ``distance`` m from the barrel end."""
        return self.cm_from_barrel_end - distance

    def clip_axial(self, axial):
        """``axial`` clipped onto a profile's ends (undoes rounding in conversions; the
        range itself is validated); unchanged for a cylinder."""
        if self.profile is None:
            return axial
        clipped = np.clip(axial, self.profile.knob_end, self.profile.barrel_end)
        return float(clipped) if np.ndim(clipped) == 0 else clipped

    def surface(self, axial):
        """Radius (m) and slope ``dr/dz`` at axial position(s) ``axial``: floats for a
        scalar, else float64 arrays (NaN off a profile's ends)."""
        if self.profile is None:
            if np.ndim(axial) == 0:
                return float(self.radius), 0.0
            n = np.shape(axial)
            return np.full(n, float(self.radius)), np.zeros(n)
        return self.profile.radius(axial), self.profile.slope(axial)

    def min_reach(self, ball_radius, axial_low, axial_high) -> float:
        """Smallest distance (m) of a touching ball's centre from the bat axis,
        ``r(z) + R/sqrt(1 + r'(z)^2)``, over ``axial_low <= z <= axial_high``: the largest
        impact parameter that hits everywhere in that range.

        For a profile it is the minimum over every node in the range and a fine grid
        (spacing <= 0.05 mm), less 1e-7 m for what the grid may miss between points.
        """
        if self.profile is None:
            return float(ball_centre_radial_distance(ball_radius, self.radius, 0.0))
        lo, hi = (float(v) for v in self.clip_axial(np.array([axial_low, axial_high])))
        nodes = self.profile.z[(self.profile.z > lo) & (self.profile.z < hi)]
        count = max(2, int(math.ceil((hi - lo) / 5e-5)) + 1)
        z = np.concatenate((np.linspace(lo, hi, count), nodes))
        r, s = self.surface(z)
        return float(np.min(r + ball_radius / np.sqrt(1.0 + s * s))) - 1e-7

    def config(self) -> dict:
        out = {"preset": self.preset, "mass": self.mass,
               "transverse_inertia": self.transverse_inertia,
               "axial_inertia": self.axial_inertia, "length": self.length,
               "cm_from_barrel_end": self.cm_from_barrel_end}
        if self.profile is None:
            out["surface"] = {"kind": "cylinder", "radius": self.radius}
        else:
            p = self.profile
            digest = hashlib.sha256(np.ascontiguousarray(p.z).tobytes()
                                    + np.ascontiguousarray(p.r).tobytes()).hexdigest()
            out["surface"] = {"kind": "profile", "nodes": int(p.z.size), "density": p.density,
                              "knob_end": p.knob_end, "barrel_end": p.barrel_end,
                              "sha256": digest}
        return out


#: Ball presets.
BALL_PRESETS = {
    "baseball": BallSpec(mass=0.145, radius=0.036, inertia_factor=0.4, preset="baseball"),
}


def _cross_nathan_2006():
    return BatSpec(mass=0.989, transverse_inertia=0.046, axial_inertia=4.39e-4,
                   radius=0.03335, length=0.84, cm_from_barrel_end=0.265,
                   preset="cross_nathan_2006")


def _r161():
    from mcbat.bats import r161_profile

    return BatSpec.from_profile(r161_profile(), preset="r161")


_BAT_FACTORIES = {"cross_nathan_2006": _cross_nathan_2006, "r161": _r161}

#: Names of the bat presets.
BAT_PRESETS = tuple(_BAT_FACTORIES)


def ball_preset(name) -> BallSpec:
    """The ball preset ``name`` (KeyError if unknown)."""
    return BALL_PRESETS[name]


def bat_preset(name) -> BatSpec:
    """A new :class:`BatSpec` for the bat preset ``name`` (KeyError if unknown)."""
    return _BAT_FACTORIES[name]()
