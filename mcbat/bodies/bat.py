"""The bat: a rigid solid of revolution about ``z``, free during the impact."""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field

import numpy as np

from mcbat.checks import check_real
from mcbat.core.geometry import ball_centre_radial_distance
from mcbat.errors import InputError

OVERLAP_TOLERANCE = 1e-5
"""Largest overlap (m) of a touching ball with a profiled bat away from the contact that
is accepted: 10 um, far below the 1-6 mm of a contact on a knob flare, above what the
profile spline's curvature against the ball's leaves near the contact point."""

__all__ = ["Bat"]


@dataclass(frozen=True)
class Bat:
    """A rigid bat: mass properties about its CM and the surface at the contact.

    Lab frame (``docs/physics.md``): the CM at the origin, ``z`` along the axis towards
    the barrel end. Exactly one of ``radius`` (a cylinder at the contact, slope 0) and
    ``profile`` (a tapered ``mcbat.bodies.profile.BatProfile``) is set.

    Parameters
    ----------
    mass : float
        kg.
    transverse_inertia, axial_inertia : float
        Moments of inertia about the CM, perpendicular to and along the axis, kg m^2.
    radius : float, optional
        Barrel radius (m) of a cylinder at the contact.
    profile : mcbat.bodies.profile.BatProfile, optional
        A tabulated profile r(z) instead of ``radius``; the contact normal then tilts by
        r'(z). Not compared.
    length, cm_from_barrel_end : float, optional
        m; they bound the contact's axial position and convert distances from the barrel
        end (``axial = cm_from_barrel_end - distance``). A profile sets both.
    preset : str, optional
        The preset it came from, for the record; not compared.
    """

    mass: float
    transverse_inertia: float
    axial_inertia: float
    radius: float | None = None
    profile: object | None = field(default=None, compare=False)
    length: float | None = None
    cm_from_barrel_end: float | None = None
    preset: str | None = field(default=None, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "mass", check_real(self.mass, "mass", positive=True))
        object.__setattr__(self, "transverse_inertia",
                           check_real(self.transverse_inertia, "transverse_inertia", positive=True))
        object.__setattr__(self, "axial_inertia",
                           check_real(self.axial_inertia, "axial_inertia", positive=True))
        if (self.radius is None) == (self.profile is None):
            raise InputError("radius", "give exactly one of a barrel radius or a profile")
        if self.radius is not None:
            object.__setattr__(self, "radius",
                               check_real(self.radius, "radius", positive=True))

    def __repr__(self) -> str:
        name = f"{self.preset!r}: " if self.preset else ""
        surface = (f"radius {self.radius:g} m" if self.profile is None else
                   f"profile of {self.profile.z.size} nodes")
        return (f"Bat({name}{self.mass:g} kg, I_t {self.transverse_inertia:g}, "
                f"I_3 {self.axial_inertia:g} kg m^2, {surface})")

    @classmethod
    def from_profile(cls, profile, preset=None) -> Bat:
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

    def surface_at(self, axial: float) -> tuple[float, float]:
        """Radius (m) and slope ``dr/dz`` at one axial position (m from the CM), which
        must lie on the bat (``InputError`` naming ``axial`` otherwise)."""
        if self.profile is None:
            return float(self.radius), 0.0
        lo, hi = self.profile.knob_end, self.profile.barrel_end
        if not lo <= axial <= hi:
            raise InputError("axial", f"must lie on the bat, within [{lo:.4g}, {hi:.4g}] m, "
                             f"got {axial!r}")
        return float(self.profile.radius(axial)), float(self.profile.slope(axial))

    def surface(self, axial):
        """Radius (m) and slope ``dr/dz`` at axial position(s) ``axial``: floats for a
        scalar, else float64 arrays (NaN off a profile's ends)."""
        if self.profile is None:
            if np.ndim(axial) == 0:
                return float(self.radius), 0.0
            n = np.shape(axial)
            return np.full(n, float(self.radius)), np.zeros(n)
        if np.ndim(axial) == 0:
            return self.profile.radius(axial), self.profile.slope(axial)
        return self.profile.surfaces(axial)

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

    def overlap(self, ball_radius, axial) -> float:
        """How far (m) a ball touching the surface at ``axial`` (m from the CM: the
        *contact point's* axial position) reaches into the bat elsewhere; 0 for a cylinder.

        The ball's centre sits at ``R`` along the surface normal, ``rho_c = r + R c``,
        ``z_c = axial - R s c`` (``s = r'``, ``c = 1/sqrt(1 + s^2)``). At height ``z`` the
        ball's cross-section is a disc of radius ``sqrt(R^2 - (z - z_c)^2)`` at ``rho_c``
        from the axis, the bat's a disc of radius ``r(z)`` about the axis: they overlap by
        ``r(z) + sqrt(R^2 - (z - z_c)^2) - rho_c`` where that is positive. The maximum over
        the profile's nodes and a 0.05 mm grid within ``R`` of ``z_c`` (on the bat) is
        returned (0 at the contact itself).
        """
        if self.profile is None:
            return 0.0
        r0, s0 = self.surface_at(axial)
        c = 1.0 / math.sqrt(1.0 + s0 * s0)
        rho_c = r0 + ball_radius * c
        z_c = axial - ball_radius * s0 * c
        lo = max(z_c - ball_radius, self.profile.knob_end)
        hi = min(z_c + ball_radius, self.profile.barrel_end)
        nodes = self.profile.z[(self.profile.z > lo) & (self.profile.z < hi)]
        count = max(2, int(math.ceil((hi - lo) / 5e-5)) + 1)
        z = np.concatenate((np.linspace(lo, hi, count), nodes))
        r = self.profile.radius(z)
        depth = r + np.sqrt(np.maximum(ball_radius ** 2 - (z - z_c) ** 2, 0.0)) - rho_c
        return max(float(np.max(depth)), 0.0)

    def check_no_overlap(self, ball_radius, axial_low, axial_high, name="axial"):
        """``InputError`` naming ``name`` if a ball touching anywhere in
        ``[axial_low, axial_high]`` (1 mm grid and the profile's nodes) would reach more
        than ``OVERLAP_TOLERANCE`` into the bat elsewhere (a tapered profile's flare)."""
        if self.profile is None:
            return
        lo, hi = (float(v) for v in self.clip_axial(np.array([axial_low, axial_high])))
        nodes = self.profile.z[(self.profile.z > lo) & (self.profile.z < hi)]
        grid = np.concatenate((np.linspace(lo, hi, max(2, int(math.ceil((hi - lo) / 1e-3)) + 1)),
                               nodes))
        for z in grid:
            depth = self.overlap(ball_radius, float(z))
            if depth > OVERLAP_TOLERANCE:
                raise InputError(name, f"a ball touching at {z:.6g} m from the bat CM would "
                                 f"overlap the bat by {depth * 1e3:.3g} mm elsewhere (the "
                                 "profile curves into it); keep contacts where the ball "
                                 "touches the bat only there")

    def config(self) -> dict:
        """The bat as plain data (part of a study's config hash; a profile by its digest)."""
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
