"""Contact frame of a sphere touching a bat that is a solid of revolution.

Lab frame (``docs/physics.md``, "The lab frame"): origin at the bat's centre of mass, ``z``
along the bat axis towards the barrel end. The contact point sits at axial position
``axial`` (m, from the bat CM) and azimuth ``angle`` (rad, from ``+x`` towards ``+y``) on a
surface of radius ``radius`` = r(axial) with slope ``slope`` = r'(axial) (0 for a cylinder).

``t3`` is the outward bat normal, ``t1`` the azimuthal tangent ``e_phi``, and
``t2 = t3 x t1`` the meridional tangent with ``t2 . k > 0``.
"""

import math
from typing import NamedTuple

import numba
import numpy as np

from mcbat.core.jit import njit

__all__ = ["ProfileTable", "angle_from_impact_parameter", "angles_from_impact_parameters",
           "ball_centre_radial_distance", "contact_frame", "impact_parameter_from_angle",
           "impact_parameters_from_angles", "profile_surface", "profile_surfaces",
           "profile_surfaces_serial", "profile_table"]


@njit
def contact_frame(axial, angle, radius, slope):
    """Contact basis and contact point on a surface of revolution.

    Parameters
    ----------
    axial : float
        Axial coordinate of the contact point from the bat CM, m.
    angle : float
        Azimuth of the contact point, rad (0 means the ``+x`` side of the bat).
    radius : float
        Bat radius r(axial) at the contact, m.
    slope : float
        Profile slope dr/dz at the contact (dimensionless); 0 for a cylinder.

    Returns
    -------
    t1, t2, t3, r_c : tuple of 3-tuples
        Unit vectors (azimuthal, meridional, outward normal) and the contact point (m).
    """
    c = math.cos(angle)
    s = math.sin(angle)
    inv = 1.0 / math.sqrt(1.0 + slope * slope)
    # The normal of r = r(z) tilts against the taper: n ~ e_r - r'(z) k.
    t3 = (c * inv, s * inv, -slope * inv)
    t1 = (-s, c, 0.0)
    t2 = (slope * c * inv, slope * s * inv, inv)
    r_c = (radius * c, radius * s, axial)
    return t1, t2, t3, r_c


@njit
def ball_centre_radial_distance(ball_radius, radius, slope):
    """Distance (m) of the ball centre from the bat axis when touching at radius r(z)."""
    return radius + ball_radius / math.sqrt(1.0 + slope * slope)


@njit
def angle_from_impact_parameter(impact_parameter, ball_radius, radius, slope, approach_azimuth):
    """Contact azimuth for a ball arriving along a line offset from the bat axis.

    The ball moves perpendicular to the bat axis, towards the axis, coming from the side at
    azimuth ``approach_azimuth`` (0: it comes from ``+x`` and moves along ``-x``, as in the
    paper's Sec. V). ``impact_parameter`` (m) is the signed offset of its line from the axis,
    positive towards increasing azimuth. For a cylinder this is ``b = (R + r_b) sin(theta)``
    (``docs/physics.md``, printing error 2; the paper's ``cos`` is a misprint).

    Returns NaN when ``|b|`` exceeds the reach ``R/sqrt(1+r'^2) + r`` (the ball misses).
    """
    reach = ball_centre_radial_distance(ball_radius, radius, slope)
    ratio = impact_parameter / reach
    if not (abs(ratio) <= 1.0):
        return math.nan
    return approach_azimuth + math.asin(ratio)


@njit
def impact_parameter_from_angle(angle, ball_radius, radius, slope, approach_azimuth):
    """Inverse of ``angle_from_impact_parameter`` (m)."""
    return ball_centre_radial_distance(ball_radius, radius, slope) * math.sin(
        angle - approach_azimuth
    )


@njit
def angles_from_impact_parameters(impact_parameter, ball_radius, radius, slope,
                                  approach_azimuth, out):
    """``angle_from_impact_parameter`` over arrays (all of length ``n``); writes ``out``."""
    for i in range(out.shape[0]):
        out[i] = angle_from_impact_parameter(impact_parameter[i], ball_radius[i], radius[i],
                                             slope[i], approach_azimuth[i])


@njit
def impact_parameters_from_angles(angle, ball_radius, radius, slope, approach_azimuth, out):
    """``impact_parameter_from_angle`` over arrays (all of length ``n``); writes ``out``."""
    for i in range(out.shape[0]):
        out[i] = impact_parameter_from_angle(angle[i], ball_radius[i], radius[i], slope[i],
                                             approach_azimuth[i])


class ProfileTable(NamedTuple):
    """A bat profile's piecewise polynomials, for ``profile_surfaces``.

    ``breaks`` (float64[m + 1], m from the CM, increasing) are the nodes;
    ``radius_coeffs`` (float64[4, m]) the PCHIP cubic r(z) and ``slope_coeffs``
    (float64[3, m]) its derivative r'(z), in scipy's ``PPoly`` layout: ``c[k, i]``
    multiplies ``(z - breaks[i])**(order - 1 - k)``. ``cell_start`` (int64[c]) is the
    interval at the left edge of each of ``c`` equal cells of ``[breaks[0], breaks[m]]``
    and ``cell_scale`` the cells per metre: the interval of ``z`` is found from its cell in
    a step or two, with no binary search (whose unpredictable branches were most of the
    evaluation's time).
    """

    breaks: np.ndarray
    radius_coeffs: np.ndarray
    slope_coeffs: np.ndarray
    cell_start: np.ndarray
    cell_scale: float


def profile_table(breaks, radius_coeffs, slope_coeffs, cells_per_interval=4) -> ProfileTable:
    """The ``ProfileTable`` of a piecewise cubic and its derivative."""
    m = breaks.shape[0] - 1
    cells = cells_per_interval * m
    scale = cells / (breaks[m] - breaks[0])
    edges = breaks[0] + np.arange(cells) / scale
    start = np.clip(np.searchsorted(breaks, edges, side="right") - 1, 0, m - 1)
    return ProfileTable(breaks, radius_coeffs, slope_coeffs, start.astype(np.int64),
                        float(scale))


@njit(inline="always")
def _surface(table, z):
    """``(r, r')`` of the profile at ``z`` (NaN off its ends)."""
    breaks, rc, sc = table.breaks, table.radius_coeffs, table.slope_coeffs
    m = breaks.shape[0] - 1
    if not breaks[0] <= z <= breaks[m]:
        return math.nan, math.nan
    # The interval with breaks[lo] <= z < breaks[lo + 1] (the last: <=), from the cell of
    # z; the steps back and forth make it exact whatever the cell's rounding.
    lo = table.cell_start[min(int((z - breaks[0]) * table.cell_scale),
                              table.cell_start.shape[0] - 1)]
    while lo > 0 and z < breaks[lo]:
        lo -= 1
    while lo < m - 1 and z >= breaks[lo + 1]:
        lo += 1
    s = z - breaks[lo]
    s2 = s * s
    # (0.0 + c: PPoly's sum starts from 0.0, which turns a -0.0 term into +0.0)
    radius = ((0.0 + rc[3, lo]) + rc[2, lo] * s) + rc[1, lo] * s2 + rc[0, lo] * (s2 * s)
    slope = ((0.0 + sc[2, lo]) + sc[1, lo] * s) + sc[0, lo] * s2
    return radius, slope


@njit
def profile_surface(table, z):
    """``(r, r')`` of the profile ``table`` at one axial position ``z`` (m from the CM; NaN
    off its ends): the very values ``profile_surfaces`` writes, for jitted callers that
    move along the bat (the contact inference)."""
    return _surface(table, z)


@njit(parallel=True)
def profile_surfaces(table, axial, radius, slope):
    """A bat profile's radius and slope at many axial positions (in parallel).

    Parameters
    ----------
    table : ProfileTable
        The profile's polynomials (``profile_table``).
    axial : float64[n]
        Axial positions, m from the CM.
    radius, slope : float64[n]
        Written: r (m) and r' (dimensionless); NaN off the profile's ends.

    Notes
    -----
    Each polynomial is summed from its constant term up with the powers built by
    repeated products: scipy's ``PPoly`` order of operations, so the values are
    bit-identical to ``PchipInterpolator``'s.
    """
    for i in numba.prange(axial.shape[0]):
        radius[i], slope[i] = _surface(table, axial[i])


@njit
def profile_surfaces_serial(table, axial, radius, slope):
    """``profile_surfaces`` on one thread, for a few positions: starting the parallel
    loop costs more than it saves there (milliseconds when the other core is busy)."""
    for i in range(axial.shape[0]):
        radius[i], slope[i] = _surface(table, axial[i])
