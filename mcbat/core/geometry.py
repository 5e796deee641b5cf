"""Contact frame of a sphere touching a bat that is a solid of revolution.

Lab frame (``docs/physics.md``, "The lab frame"): origin at the bat's centre of mass, ``z``
along the bat axis towards the barrel end. The contact point sits at axial position
``axial`` (m, from the bat CM) and azimuth ``angle`` (rad, from ``+x`` towards ``+y``) on a
surface of radius ``radius`` = r(axial) with slope ``slope`` = r'(axial) (0 for a cylinder).

``t3`` is the outward bat normal, ``t1`` the azimuthal tangent ``e_phi``, and
``t2 = t3 x t1`` the meridional tangent with ``t2 . k > 0``.
"""

import math

import numba

from mcbat.core.jit import njit

__all__ = ["profile_surfaces", "angle_from_impact_parameter", "angles_from_impact_parameters",
           "ball_centre_radial_distance", "contact_frame", "impact_parameter_from_angle",
           "impact_parameters_from_angles"]


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
    """Inverse of :func:`angle_from_impact_parameter` (m)."""
    return ball_centre_radial_distance(ball_radius, radius, slope) * math.sin(
        angle - approach_azimuth
    )


@njit
def angles_from_impact_parameters(impact_parameter, ball_radius, radius, slope,
                                  approach_azimuth, out):
    """:func:`angle_from_impact_parameter` over arrays (all of length ``n``); writes ``out``."""
    for i in range(out.shape[0]):
        out[i] = angle_from_impact_parameter(impact_parameter[i], ball_radius[i], radius[i],
                                             slope[i], approach_azimuth[i])


@njit
def impact_parameters_from_angles(angle, ball_radius, radius, slope, approach_azimuth, out):
    """:func:`impact_parameter_from_angle` over arrays (all of length ``n``); writes ``out``."""
    for i in range(out.shape[0]):
        out[i] = impact_parameter_from_angle(angle[i], ball_radius[i], radius[i], slope[i],
                                             approach_azimuth[i])


@njit
def _piecewise_polynomial(breaks, coeffs, interval, s):
    """``sum_k coeffs[K-1-k, interval] s**k``, summed from the constant term up with the
    powers built by repeated products: scipy's ``PPoly`` order of operations, so the
    value is bit-identical to ``PchipInterpolator``'s."""
    order = coeffs.shape[0]
    value = 0.0
    power = 1.0
    for k in range(order):
        value = value + coeffs[order - 1 - k, interval] * power
        if k < order - 1:
            power *= s
    return value


@njit(parallel=True)
def profile_surfaces(breaks, radius_coeffs, slope_coeffs, axial, radius, slope):
    """A bat profile's radius and slope at many axial positions (in parallel).

    Parameters
    ----------
    breaks : float64[m + 1]
        The profile's nodes (m from the CM, increasing).
    radius_coeffs, slope_coeffs : float64[4, m], float64[3, m]
        The piecewise cubic r(z) (PCHIP) and its derivative r'(z) in scipy's ``PPoly``
        layout: ``c[k, i]`` multiplies ``(z - breaks[i])**(order - 1 - k)``.
    axial : float64[n]
        Axial positions, m from the CM.
    radius, slope : float64[n]
        Written: r (m) and r' (dimensionless); NaN off the profile's ends.
    """
    m = breaks.shape[0] - 1
    for i in numba.prange(axial.shape[0]):
        z = axial[i]
        if not breaks[0] <= z <= breaks[m]:
            radius[i] = math.nan
            slope[i] = math.nan
            continue
        lo, hi = 0, m  # the interval with breaks[lo] <= z < breaks[lo + 1] (the last: <=)
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if z < breaks[mid]:
                hi = mid
            else:
                lo = mid
        s = z - breaks[lo]
        radius[i] = _piecewise_polynomial(breaks, radius_coeffs, lo, s)
        slope[i] = _piecewise_polynomial(breaks, slope_coeffs, lo, s)
