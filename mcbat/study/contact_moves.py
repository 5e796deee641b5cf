"""How each drawn contact of a game study moves with its swing and its pitch.

The contact's distributions (``[contact] from_barrel_end``, ``undercut``) are drawn as
they are written; these trends then move each draw, as functions of what the sample meets
(its true bat speed, where its real pitch crossed the plate). The population fit weighs
the draws before the moves (``mcbat.stats.population.templates``), so a trend is a
constant of the map from inputs to batted balls, chosen, not reweighted.

**The contact and the bat speed** (``[contact.bat_speed_trend]``): a faster swing need not
meet the ball as well. With this table each sample's ``from_barrel_end`` (drawn from its
distribution, or fixed) moves by ``from_barrel_end`` for every ``per`` of the sample's bat
speed above ``reference`` (the true bat speed the sample swings with: with
``[pitches.swing_error]`` the draw given the measured one), and is then held inside the
distribution's support (within the bat for a fixed value): ``d = clip(d0 + s (V - V0))``,
``s = from_barrel_end / per``. The distribution's mean is so the mean at ``reference``.
``from_barrel_end = 0`` (the default without the table) is a contact independent of the
swing. The table's ``undercut`` moves the undercut the same way, ``u = clip(u0 + t (V -
V0))``, ``t = undercut / per`` (positive: a faster swing gets further under the ball and
lifts it, a slow one tops it), after the pitch-height trend's move.

**The contact and the pitch's location** (``[contact.plate_x_trend]``, with ``[pitches]``):
a pitch off the plate is met off the sweet spot, one inside nearer the handle, one away
nearer the barrel end. With ``x`` the row's ``plate_x`` away from the batter less
``reference`` (Statcast's ``plate_x`` for a right-handed batter, its negative for a
left-handed one), the contact moves by ``s sign(x) max(|x| - w, 0)`` (``w`` the
``dead_zone``: the pitches over which the batter's adjustment keeps the contact where it
is; ``s = from_barrel_end / per``, negative: towards the barrel end for a pitch away),
before the bat-speed trend's move and the clip; a row without ``plate_x`` does not move.
With ``[contact.plate_z_trend]`` the undercut moves by ``undercut`` for every ``per`` the
pitch crossed the plate above ``reference`` (Statcast's ``plate_z``; positive: a high
pitch is met further under its centre, so it leaves higher), held inside the undercut's
support. The table's ``vertical_bat_angle`` moves the bat's vertical angle the same way,
held inside the range of ``[swing] vertical_bat_angle``, on the rows without a measured
swing plane (with ``[pitches] swing_plane``, a row's plane sets its bat): a high pitch is
met with a flatter bat, a low one with a steeper one (2025's planes: 7.2 deg per ft,
``docs/bat_tracking.md``, "The swing's plane").

**The contact and the swing's length** (``[contact.swing_length_trend]``, with
``[pitches]``): the undercut moves by ``undercut`` for every ``per`` of the row's measured
``swing_length`` (Statcast's: the distance the bat's head travels from the start of the
swing to contact) above ``reference``, the same form as the height's; a row without
``swing_length`` does not move. Positive: of two swings at the same bat speed, the longer
one meets the ball further under its centre (in the 2025 season's tracked balls in play,
a foot more swing at the same bat speed, attack angle and pitch location leaves 2.9 deg
higher and 1.4 mph slower: ``docs/bat_tracking.md``, "The swing's length").
"""

from __future__ import annotations

import numpy as np

__all__ = ["bat_angle_move", "bat_speed_move", "height_move", "location_move",
           "move_contact", "move_undercut", "trends_config"]


def bat_speed_move(bat_speed, trend) -> np.ndarray:
    """The move along the bat (m) of samples swinging at ``bat_speed`` (m/s):
    ``s (V - V0)``, ``trend = (V0 m/s, s m per m/s)`` (``[contact.bat_speed_trend]``)."""
    reference, slope = trend
    return slope * (bat_speed - reference)


def location_move(away, trend) -> np.ndarray:
    """The move along the bat (m) of samples whose pitch crossed the plate ``away`` (m away
    from the batter; NaN: no move): ``s sign(x) max(|x| - w, 0)``, ``x = away - reference``,
    ``trend = (reference m, w m, s m per m)`` (``[contact.plate_x_trend]``)."""
    reference, zone, slope = trend
    x = np.nan_to_num(away - reference, nan=0.0)
    return slope * np.sign(x) * np.maximum(np.abs(x) - zone, 0.0)


def height_move(plate_z, trend) -> np.ndarray:
    """The undercut's move (m) of samples whose pitch crossed the plate at ``plate_z`` (m;
    NaN: no move): ``s (plate_z - reference)``, ``trend = (reference m, s m per m, ...)``
    (``[contact.plate_z_trend]``, ``[contact.swing_length_trend]``)."""
    reference, slope = trend[:2]
    return slope * np.nan_to_num(plate_z - reference, nan=0.0)


def bat_angle_move(angle, plate_z, trend, support) -> None:
    """Move the vertical bat angles ``angle`` (rad, in place) of samples whose pitch
    crossed the plate at ``plate_z`` (m; NaN: no move) by ``b (plate_z - reference)``,
    ``trend = (reference m, _, b rad per m)`` (``[contact.plate_z_trend]``), and hold them
    inside ``support`` (rad)."""
    reference, _, slope = trend
    angle += slope * np.nan_to_num(plate_z - reference, nan=0.0)
    np.clip(angle, *support, out=angle)


def trends_config(study) -> dict:
    """The trend tables of a game study's ``[contact]`` for its config (SI): name -> its
    values and the form of its move."""
    out = {}
    if study.contact_trend is not None:
        reference, along, under = study.contact_trend
        out["bat_speed_trend"] = {
            "reference": reference, "from_barrel_end_per_bat_speed": along,
            "undercut_per_bat_speed": under,
            "form": "d = clip(d0 + s (V - V0)), u = clip(u0 + t (V - V0)) to the supports"}
    if study.plate_x_trend is not None:
        reference, zone, slope = study.plate_x_trend
        out["plate_x_trend"] = {
            "reference": reference, "dead_zone": zone, "from_barrel_end_per_plate_x": slope,
            "form": "d0 + s sign(x) max(|x| - w, 0), x = plate_x away from the batter "
                    "- reference, before the bat-speed trend"}
    for name in ("plate_z", "swing_length"):
        trend = getattr(study, f"{name}_trend", None)
        if trend is not None:
            out[f"{name}_trend"] = {
                "reference": trend[0], f"undercut_per_{name}": trend[1],
                "form": f"u = clip(u0 + s ({name} - reference)) to the support"}
            if name == "plate_z" and trend[2] != 0.0:
                out["plate_z_trend"].update(
                    vertical_bat_angle_per_plate_z=trend[2],
                    vertical_bat_angle_form="b = clip(b0 + t (plate_z - reference)) to the "
                                            "support, rows without a measured swing plane")
    return out


def move_undercut(study, cols, rows) -> None:
    """Move each sample's undercut (``cols``: a game study's sample columns) with its
    pitch's height (``[contact.plate_z_trend]``), its swing's length
    (``[contact.swing_length_trend]``; ``rows``: the samples' values of those columns, m)
    and its bat speed (``[contact.bat_speed_trend]``), held inside the undercut's support
    (``study``: the game study)."""
    moved = cols["undercut"].copy()
    for name in ("plate_z", "swing_length"):
        trend = getattr(study, f"{name}_trend")
        if trend is not None and name in rows:
            moved += height_move(rows[name], trend)
    if study.contact_trend is not None:
        reference, _, under = study.contact_trend
        moved += bat_speed_move(cols["bat_speed"], (reference, under))
    dist = study.inputs.get("contact.undercut")
    if dist is not None and dist.family != "fixed":
        np.clip(moved, *dist.support(), out=moved)
    cols["undercut"][:] = moved


def move_contact(study, cols, away) -> None:
    """Move each sample's contact along the bat with where its pitch crossed the plate
    (``away``: m away from the batter) and with its bat speed, then hold it inside the
    distribution's support (within the bat for a fixed value; ``study``: the game
    study)."""
    moved = cols["from_barrel_end"].copy()
    if study.plate_x_trend is not None and away is not None:
        moved += location_move(away, study.plate_x_trend)
    if study.contact_trend is not None:
        reference, along, _ = study.contact_trend
        moved += bat_speed_move(cols["bat_speed"], (reference, along))
    dist = study.inputs.get("contact.from_barrel_end")
    fixed = dist is None or dist.family == "fixed"
    low, high = (0.0, study.bat.length) if fixed else dist.support()
    cols["from_barrel_end"][:] = np.clip(moved, max(low, 0.0), min(high, study.bat.length))
