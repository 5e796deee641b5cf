"""Bat profiles: solids of revolution r(z) and their uniform-density mass properties.

Lab frame (``docs/physics.md``, "The lab frame"): origin at the bat's centre of mass (CM),
``z`` along the bat axis towards the barrel end. A ``BatProfile`` holds the radius
``r`` at nodes ``z`` in that
frame. Two readings of the same nodes are used, each where it matters:

* mass properties (``mass_properties``) take the radius as piecewise *linear* between
  nodes (a stack of truncated cones) and integrate it exactly;
* contact geometry (``BatProfile.radius``, ``BatProfile.slope``) uses a
  shape-preserving cubic (PCHIP) through the same nodes, so the slope r'(z), which tilts
  the contact normal ``t3 ~ e_r - r'(z) k``, is continuous along the bat.

Both pass through every node; they differ only between nodes, by far less than the
table's own precision for a smooth profile.

This module is pure: no file I/O (see ``mcbat.bodies.tables`` for reading tables).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from mcbat.core.geometry import profile_surfaces, profile_surfaces_serial, profile_table

__all__ = ["BatProfile", "mass_properties", "pchip_coefficients"]

# Gauss-Legendre nodes and weights on [0, 1]. Three points integrate polynomials of degree
# <= 5 exactly; the integrands here (r^4 and z^2 r^2 with r linear in z) have degree 4.
_GL_X, _GL_W = np.polynomial.legendre.leggauss(3)
_GL_T = 0.5 * (_GL_X + 1.0)
_GL_W = 0.5 * _GL_W


def _as_1d(values, name):
    """A finite 1-D float array, or ValueError naming ``name``."""
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name}: must be an array of numbers ({exc})") from None
    if arr.ndim != 1:
        raise ValueError(f"{name}: must be 1-D, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        bad = int(np.flatnonzero(~np.isfinite(arr))[0])
        raise ValueError(f"{name}: must be finite, got {arr[bad]!r} at index {bad}")
    return arr


def _check_profile(z, r):
    """Validated ``(z, r)`` arrays: same length >= 2, z strictly increasing, r >= 0."""
    z = _as_1d(z, "z")
    r = _as_1d(r, "r")
    if z.shape != r.shape:
        raise ValueError(f"z and r: lengths differ ({z.size} and {r.size})")
    if z.size < 2:
        raise ValueError(f"z: needs at least 2 nodes, got {z.size}")
    steps = np.diff(z)
    if not np.all(steps > 0.0):
        i = int(np.flatnonzero(~(steps > 0.0))[0])
        raise ValueError(
            f"z: must be strictly increasing, got z[{i}] = {z[i]!r} then z[{i + 1}] = {z[i + 1]!r}"
        )
    if np.any(r < 0.0):
        i = int(np.flatnonzero(r < 0.0)[0])
        raise ValueError(f"r: must be >= 0, got r[{i}] = {r[i]!r}")
    if not np.any(r > 0.0):
        raise ValueError("r: all radii are zero, the solid has no volume")
    return z, r


def _check_density(density):
    if isinstance(density, bool):
        raise ValueError(f"density: must be a number, got {density!r}")
    try:
        value = float(density)
    except (TypeError, ValueError):
        raise ValueError(f"density: must be a number, got {density!r}") from None
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"density: must be finite and > 0 kg/m^3, got {density!r}")
    return value


def mass_properties(z, r, density):
    """Mass, centre of mass and moments of inertia of a uniform solid of revolution.

    The radius is ``r[i]`` at ``z[i]`` and linear in ``z`` between nodes (a stack of
    truncated cones, flat end faces at ``z[0]`` and ``z[-1]``). On each segment the
    integrands are polynomials of degree <= 4 in ``z``, so 3-point Gauss-Legendre
    quadrature per segment is exact up to rounding.

    Parameters
    ----------
    z : array_like, shape (n,)
        Axial node positions, m, strictly increasing, ``n >= 2``.
    r : array_like, shape (n,)
        Radius at each node, m, ``>= 0`` (not all zero).
    density : float
        Uniform density, kg/m^3, ``> 0``.

    Returns
    -------
    mass : float
        ``M = rho pi int r^2 dz``, kg.
    z_cm : float
        Centre of mass on the axis, m, in the same coordinate as ``z``.
    transverse_inertia : float
        ``I_t = rho pi int (r^4/4 + r^2 (z - z_cm)^2) dz``, kg m^2: about an axis
        perpendicular to the bat axis through the CM.
    axial_inertia : float
        ``I_3 = rho pi int r^4/2 dz``, kg m^2: about the bat axis.

    Raises
    ------
    ValueError
        Naming the argument: ``z`` not strictly increasing or not finite, ``r`` negative,
        ``z`` and ``r`` of different lengths, ``density`` not > 0.
    """
    z, r = _check_profile(z, r)
    rho = _check_density(density)

    h = np.diff(z)[:, None]                                  # segment lengths, (n-1, 1)
    zq = z[:-1, None] + h * _GL_T                           # quadrature points, (n-1, 3)
    rq = r[:-1, None] + (r[1:] - r[:-1])[:, None] * _GL_T
    w = h * _GL_W                                           # quadrature weights in z
    area = np.pi * rq * rq

    mass = rho * float(np.sum(w * area))
    z_cm = rho * float(np.sum(w * area * zq)) / mass
    # Second moments about the CM directly (no parallel-axis subtraction, no cancellation).
    dz = zq - z_cm
    transverse = rho * float(np.sum(w * area * (0.25 * rq * rq + dz * dz)))
    axial = rho * float(np.sum(w * area * 0.5 * rq * rq))
    return mass, z_cm, transverse, axial


def _pchip_end_slope(h0, h1, m0, m1):
    """PCHIP's slope at an end node: the one-sided three-point estimate, set to 0 if its
    sign differs from the end interval's and capped at 3 m0 where the data turn."""
    d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
    if np.sign(d) != np.sign(m0):
        return 0.0
    if np.sign(m0) != np.sign(m1) and abs(d) > 3.0 * abs(m0):
        return 3.0 * m0
    return d


def pchip_coefficients(z, r):
    """The piecewise cubic of shape-preserving (PCHIP, Fritsch-Carlson) interpolation
    through the nodes ``(z, r)``, in scipy's ``PPoly`` layout: ``c[k, i]`` multiplies
    ``(x - z[i])**(3 - k)`` on ``[z[i], z[i + 1]]``.

    The node slopes are the weighted harmonic means of the neighbouring secants (0 where
    they change sign or one is 0), Fritsch & Butland (1984), with the three-point end
    rule: ``scipy.interpolate.PchipInterpolator``'s formulas in its order of operations,
    so the coefficients are the same to the bit (tested), without importing
    scipy.interpolate at start-up (~0.4 s).

    Parameters
    ----------
    z, r : float64[n]
        Increasing nodes (m) and the values there (``n >= 2``).

    Returns
    -------
    float64[4, n - 1]
    """
    z, r = np.asarray(z, np.float64), np.asarray(r, np.float64)
    h = np.diff(z)
    secant = np.diff(r) / h
    slopes = np.empty_like(r)
    if r.size == 2:
        slopes[:] = secant[0]
    else:
        turn = ((np.sign(secant[1:]) != np.sign(secant[:-1])) | (secant[1:] == 0.0)
                | (secant[:-1] == 0.0))
        w1, w2 = 2.0 * h[1:] + h[:-1], h[1:] + 2.0 * h[:-1]
        with np.errstate(divide="ignore", invalid="ignore"):
            harmonic = (w1 / secant[:-1] + w2 / secant[1:]) / (w1 + w2)
            slopes[1:-1] = np.where(turn, 0.0, 1.0 / harmonic)
        slopes[0] = _pchip_end_slope(h[0], h[1], secant[0], secant[1])
        slopes[-1] = _pchip_end_slope(h[-1], h[-2], secant[-1], secant[-2])
    # The cubic Hermite form of each interval.
    t = (slopes[:-1] + slopes[1:] - 2.0 * secant) / h
    coeffs = np.empty((4, r.size - 1))
    coeffs[0] = t / h
    coeffs[1] = (secant - slopes[:-1]) / h - t
    coeffs[2] = slopes[:-1]
    coeffs[3] = r[:-1]
    return coeffs


def _readonly(values):
    arr = np.array(values, dtype=float)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class BatProfile:
    """A bat as a uniform solid of revolution, in the lab frame (origin at its CM).

    Build it with ``from_knob_table`` from a table measured from the knob, or
    directly when ``z`` is already measured from the CM. The mass properties are computed
    on construction (``mass_properties``, radius linear between nodes).

    Parameters
    ----------
    z : array_like, shape (n,)
        Axial node positions, m, measured from the bat's CM towards the barrel end,
        strictly increasing (``z[0]`` is the knob end, ``z[-1]`` the barrel end). The CM
        of the profile must be at ``z = 0`` (to 1e-9 of the length).
    r : array_like, shape (n,)
        Radius at each node, m, ``>= 0``.
    density : float
        Uniform density, kg/m^3.

    Attributes
    ----------
    mass : float
        Bat mass, kg.
    transverse_inertia : float
        ``I_t``, moment of inertia about a transverse axis through the CM, kg m^2.
    axial_inertia : float
        ``I_3``, moment of inertia about the bat axis, kg m^2.

    Notes
    -----
    ``z`` and ``r`` are stored as read-only copies and left out of the repr. The object
    compares by identity.
    """

    z: np.ndarray = field(repr=False)
    r: np.ndarray = field(repr=False)
    density: float
    mass: float = field(init=False)
    transverse_inertia: float = field(init=False)
    axial_inertia: float = field(init=False)
    _radius_coeffs: np.ndarray = field(init=False, repr=False)
    _slope_coeffs: np.ndarray = field(init=False, repr=False)
    _table: object = field(init=False, repr=False)  # the kernel's ProfileTable

    def __post_init__(self):
        z, r = _check_profile(self.z, self.r)
        rho = _check_density(self.density)
        mass, z_cm, transverse, axial = mass_properties(z, r, rho)
        length = z[-1] - z[0]
        if abs(z_cm) > 1e-9 * length:
            raise ValueError(
                f"z: must be measured from the centre of mass, but the CM is at z = {z_cm!r} m "
                "(use BatProfile.from_knob_table to shift a table)"
            )
        radius_coeffs = pchip_coefficients(z, r)
        set_ = object.__setattr__
        set_(self, "z", _readonly(z))
        set_(self, "r", _readonly(r))
        set_(self, "density", rho)
        set_(self, "mass", mass)
        set_(self, "transverse_inertia", transverse)
        set_(self, "axial_inertia", axial)
        set_(self, "_radius_coeffs", _readonly(radius_coeffs))
        set_(self, "_slope_coeffs", _readonly(radius_coeffs[:-1] * np.array([[3.0], [2.0],
                                                                            [1.0]])))
        set_(self, "_table", profile_table(self.z, self._radius_coeffs, self._slope_coeffs))

    @classmethod
    def from_knob_table(cls, distance_from_knob_m, diameter_m, density):
        """Build a profile from diameters tabulated by distance from the knob end.

        The mass properties fix the CM; ``z = distance - cm_from_knob`` then puts the origin
        at the CM with ``+z`` towards the barrel (the knob is the end with the smallest
        distance). A table listed from the barrel (distance decreasing) is reversed first.

        Parameters
        ----------
        distance_from_knob_m : array_like, shape (n,)
            Distance of each row from the knob end, m, strictly monotonic.
        diameter_m : array_like, shape (n,)
            Bat diameter at each row, m, ``>= 0``.
        density : float
            Uniform density, kg/m^3.

        Returns
        -------
        BatProfile
            With ``z`` from the CM towards the barrel, ``r = diameter / 2``.

        Raises
        ------
        ValueError
            Naming the argument, for non-monotonic distances, negative diameters,
            mismatched lengths or a non-positive density.
        """
        d = _as_1d(distance_from_knob_m, "distance_from_knob_m")
        dia = _as_1d(diameter_m, "diameter_m")
        if d.shape != dia.shape:
            raise ValueError(
                f"distance_from_knob_m and diameter_m: lengths differ ({d.size} and {dia.size})"
            )
        if d.size < 2:
            raise ValueError(f"distance_from_knob_m: needs at least 2 rows, got {d.size}")
        if np.all(np.diff(d) < 0.0):
            d, dia = d[::-1], dia[::-1]
        if not np.all(np.diff(d) > 0.0):
            raise ValueError("distance_from_knob_m: must be strictly monotonic")
        if np.any(dia < 0.0):
            i = int(np.flatnonzero(dia < 0.0)[0])
            raise ValueError(f"diameter_m: must be >= 0, got {dia[i]!r} at index {i}")
        r = 0.5 * dia
        _, cm_from_knob, _, _ = mass_properties(d, r, density)
        return cls(z=d - cm_from_knob, r=r, density=density)

    @property
    def knob_end(self):
        """Axial position of the knob end, m (negative: the knob side of the CM)."""
        return float(self.z[0])

    @property
    def barrel_end(self):
        """Axial position of the barrel end, m (positive)."""
        return float(self.z[-1])

    @property
    def length(self):
        """Bat length, m."""
        return float(self.z[-1] - self.z[0])

    @property
    def cm_from_knob(self):
        """Distance of the CM from the knob end, m."""
        return -float(self.z[0])

    @property
    def kernel_table(self):
        """The profile as ``mcbat.core.geometry.ProfileTable``, for jitted callers
        (``mcbat.core.geometry.profile_surface``)."""
        return self._table

    @property
    def cm_from_barrel(self):
        """Distance of the CM from the barrel end, m."""
        return float(self.z[-1])

    def mass_properties(self):
        """``(mass, transverse_inertia, axial_inertia)`` in kg, kg m^2, kg m^2 (about the CM)."""
        return self.mass, self.transverse_inertia, self.axial_inertia

    def surfaces(self, z, out=None):
        """``(radius, slope)`` at the axial positions ``z`` (float64 arrays, m from the
        CM; computed in parallel), NaN off the ends; written into ``out`` (two contiguous
        float64 arrays of ``z``'s size) if given."""
        z = np.asarray(z, dtype=np.float64)
        flat = np.ascontiguousarray(z.ravel())
        if out is None:
            out = np.empty_like(flat), np.empty_like(flat)
        radius, slope = out
        # (in parallel only where it pays: a scalar took ~8 ms on a busy 2-core machine)
        kernel = profile_surfaces if flat.size >= 16384 else profile_surfaces_serial
        kernel(self._table, flat, radius.reshape(-1), slope.reshape(-1))
        return radius.reshape(z.shape), slope.reshape(z.shape)

    def _evaluate(self, which, z):
        values = self.surfaces(z)[which]
        return float(values) if np.ndim(values) == 0 else values

    def radius(self, z):
        """Radius r(z), m, by shape-preserving cubic (PCHIP) interpolation of the nodes.

        Parameters
        ----------
        z : float or array_like
            Axial position(s) from the CM, m.

        Returns
        -------
        float or ndarray
            r(z), m; NaN outside ``[knob_end, barrel_end]``.
        """
        return self._evaluate(0, z)

    def slope(self, z):
        """Profile slope dr/dz (dimensionless), continuous in z (PCHIP is C^1).

        Parameters
        ----------
        z : float or array_like
            Axial position(s) from the CM, m.

        Returns
        -------
        float or ndarray
            r'(z); NaN outside ``[knob_end, barrel_end]``. Positive where the bat widens
            towards the barrel. The outward contact normal is ``(e_r - r' k)/sqrt(1 + r'^2)``.
        """
        return self._evaluate(1, z)
