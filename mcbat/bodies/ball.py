"""The ball: a sphere of uniform-inertia factor."""

from __future__ import annotations

from dataclasses import dataclass, field

from mcbat.checks import check_real

__all__ = ["Ball"]


@dataclass(frozen=True)
class Ball:
    """A sphere.

    Parameters
    ----------
    mass : float
        kg.
    radius : float
        m.
    inertia_factor : float
        ``f`` in ``I = f m R^2`` (0.4 for a uniform solid sphere).
    preset : str, optional
        The preset it came from (``mcbat.bodies.presets.BALL_PRESETS``), for the
        record; not compared.
    """

    mass: float
    radius: float
    inertia_factor: float = 0.4
    preset: str | None = field(default=None, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "mass", check_real(self.mass, "mass", positive=True))
        object.__setattr__(self, "radius", check_real(self.radius, "radius", positive=True))
        object.__setattr__(self, "inertia_factor",
                           check_real(self.inertia_factor, "inertia_factor", positive=True))

    def config(self) -> dict:
        """The ball as plain data (part of a study's config hash)."""
        return {"preset": self.preset, "mass": self.mass, "radius": self.radius,
                "inertia_factor": self.inertia_factor}

    def __repr__(self) -> str:
        name = f"{self.preset!r}: " if self.preset else ""
        return (f"Ball({name}{self.mass:g} kg, radius {self.radius:g} m, "
                f"I = {self.inertia_factor:g} m R^2)")
