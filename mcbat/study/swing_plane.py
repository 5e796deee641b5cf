"""The bat's vertical angle at contact from the measured swing plane.

Statcast's ``swing_path_tilt`` (2025 on) is the angle between the ground and the plane
the sweet spot sweeps over the last part of the swing. The game model's bat rotates about
a point on its axis (``mcbat.core.swing.frames.swing_state``), so the axis ``n`` and the
sweet spot's velocity ``u`` are perpendicular and both lie in that plane. Its normal
``n x u`` then has the vertical component ``cos(tilt)``, and with ``u``'s elevation the
attack angle ``a`` and ``n``'s the vertical bat angle ``b``,

    sin^2(tilt) = sin^2(b) + sin^2(a),

so the bat's angle below the horizontal is ``b = -asin(sqrt(sin^2 tilt - sin^2 a))``
(the barrel below the hands, as in every swing Statcast tracks). A swing whose attack
angle is steeper than its plane's tilt (a measurement error in either) has no such bat:
it is taken level (``b = 0``), the nearest angle the geometry allows. With the MLB
averages (tilt about 31 deg, attack angle about 9 deg) the bat lies about 29 deg below the
horizontal, close to the 30 deg bat-sensor studies report at contact.

``[pitches] swing_plane = true`` (with ``swing = true``) gives each row with a measured
tilt this bat angle, from its (true, ``[pitches.swing_error]``) attack angle; the rows
without one (2024 exports) keep the draws of ``[swing] vertical_bat_angle``.
"""

from __future__ import annotations

import math

import numpy as np

from mcbat.errors import InputError

__all__ = ["MAX_TILT", "fill_vertical_bat_angle", "measured_tilt", "parse_swing_plane",
           "vertical_bat_angle"]

MAX_TILT = 0.5 * math.pi - 1e-6
"""The steepest tilt (rad) taken as a measurement; a vertical plane has no bat angle
the model can swing (``|tan a tan b| < 1``)."""


def vertical_bat_angle(tilt, attack_angle) -> np.ndarray:
    """The vertical bat angle (rad, at most 0) of a swing in a plane of ``tilt`` (rad)
    whose sweet spot moves at ``attack_angle`` (rad) above the horizontal; NaN where
    ``tilt`` is NaN."""
    tilt = np.asarray(tilt, np.float64)
    attack = np.asarray(attack_angle, np.float64)
    with np.errstate(invalid="ignore"):
        square = np.sin(tilt) ** 2 - np.sin(attack) ** 2
        return -np.arcsin(np.sqrt(np.maximum(square, 0.0)))


def fill_vertical_bat_angle(cols, tilt) -> None:
    """Write the samples' ``vertical_bat_angle`` from their rows' ``tilt`` (rad, NaN
    where not measured: the drawn value stays) and their ``attack_angle`` (``cols``:
    the game kernel's input columns)."""
    angle = vertical_bat_angle(tilt, cols["attack_angle"])
    np.copyto(cols["vertical_bat_angle"], angle, where=np.isfinite(angle))


def parse_swing_plane(table, swing) -> bool:
    """``[pitches] swing_plane`` (default false): a boolean, and only with ``swing``."""
    value = table.get("swing_plane", False)
    if not isinstance(value, bool):
        raise InputError("pitches.swing_plane", f"must be true or false, got {value!r}")
    if value and not swing:
        raise InputError("pitches.swing_plane", "only with pitches.swing = true (the bat "
                         "angle follows from the measured tilt and attack angle)")
    return value


def measured_tilt(column, index) -> np.ndarray:
    """The selected rows' (``index``) tilts, deg in the table, as rad; NaN where a row has
    none or a plane too steep for a bat (``MAX_TILT``)."""
    tilt = np.radians(np.asarray(column, np.float64)[index])
    with np.errstate(invalid="ignore"):
        tilt[~(np.abs(tilt) <= MAX_TILT)] = np.nan
    return tilt
