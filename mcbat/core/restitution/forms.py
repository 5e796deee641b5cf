"""``e*`` as a function of the normal approach speed and of the contact's position.

One form covers the three cases of a study (``README.md`` in this folder)::

    e* = clip((e_ref - e_slope (|v_n| - e_speed_ref)) * location_factor, 0, 1)

* constant ``e*``: ``e_slope = 0``, ``location_factor = 1``;
* linear in the normal approach speed ``|v_n|``: ``e_slope`` per m/s;
* a table ``factor(from_barrel_end)`` times the speed form: ``location_factor`` is read
  from the table (outside the kernel, by linear interpolation) and passed per row.
"""

import math

from mcbat.core.jit import njit

__all__ = ["energetic_restitution"]


@njit
def energetic_restitution(normal_speed, e_ref, e_slope, e_speed_ref, location_factor):
    """``e*`` in [0, 1] (NaN if an input is NaN).

    Parameters
    ----------
    normal_speed : float
        ``|v_n|``, the normal approach speed of the contact points, m/s (>= 0).
    e_ref : float
        ``e*`` at ``e_speed_ref``.
    e_slope : float
        Fall of ``e*`` per m/s of normal speed above ``e_speed_ref`` (1/(m/s)).
    e_speed_ref : float
        m/s.
    location_factor : float
        Multiplies the speed form (1 without a location table).
    """
    e = (e_ref - e_slope * (normal_speed - e_speed_ref)) * location_factor
    if math.isnan(e):
        return math.nan
    return min(1.0, max(0.0, e))
