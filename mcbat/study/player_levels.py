"""Each batter's and pitcher's own contact: ``[pitches.player_levels]``.

A league's contact, fitted to every batter's balls in play, is each player's only on
average. Over a season a batter's mean launch speed lies 1.2 mph (sd) from what his bat
speed and his pitches predict, and a pitcher's opponents' 0.9 mph; their mean launch
angles 4.0 and 4.4 deg from the league's (Savant searches grouped by player, noise of the
means removed; ``docs/bat_tracking.md``, "Each player's contact"). A pitcher's level is
the same the next season. No column of a pitch-level export measures it, but a player's
other balls in play do.

With this table a study gives each row's batter and pitcher their level, estimated from
their balls in play in the file's *other* games (``mcbat.runner.player_levels``), so that
no ball's own outcome enters its prediction: the mean launch speed and angle of those
balls less the study's own prediction for them, shrunk towards zero by how well that
many balls measure it against the spread of the levels written here (the posterior mean
of a normal prior). The batter's and the pitcher's levels add. Two traits of the contact
carry them through the collision, fitted together for the two levels:

* the contact's spread along the bat: each drawn ``from_barrel_end``'s distance from its
  distribution's centre is multiplied by ``spread`` (a batter who finds the barrel,
  ``spread < 1``, hits harder; a pitcher whose pitches keep the barrel off the ball,
  ``spread > 1``, is hit softer);
* the undercut: each drawn ``undercut`` moves by ``shift`` (a batter who lifts the ball
  meets it further under its centre).

Both act on the draws before the trends of ``mcbat.study.contact_moves`` move them and
are held inside the distributions' supports. A player with no other game in the file
keeps the league's contact (``spread = 1``, ``shift = 0``): a day's export is predicted
exactly as without the table.

::

    [pitches.player_levels]                 # with swing = true
    batter_launch_speed = { value = 1.2, unit = "mph" }   # the sd of the batters' levels
    batter_launch_angle = { value = 4.0, unit = "deg" }
    pitcher_launch_speed = { value = 0.9, unit = "mph" }
    pitcher_launch_angle = { value = 4.4, unit = "deg" }
    draws = 64                              # per row, for the study's own prediction

A kind left out gets no level (both of its keys, or neither).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mcbat.checks import check_keys
from mcbat.errors import InputError
from mcbat.study import units as u
from mcbat.study.dist_types import Normal, TruncNormal, Uniform
from mcbat.study.distributions import fixed_value

__all__ = ["KINDS", "PlayerLevels", "apply_player_contact", "check_contact",
           "parse_player_levels"]

#: The players a row has, as ``IDENTIFIERS`` names them.
KINDS = ("batter", "pitcher")
#: The largest factor the contact's spread takes (and 1 / it the smallest): a level so
#: far out is no contact trait any more.
SPREAD_LIMIT = 2.0
_KEYS = {f"{kind}_{what}": quantity for kind in KINDS
         for what, quantity in (("launch_speed", u.SPEED), ("launch_angle", u.ANGLE))}


@dataclass(frozen=True)
class PlayerLevels:
    """The validated ``[pitches.player_levels]``.

    Attributes
    ----------
    spread : mapping
        ``"batter"`` / ``"pitcher"`` -> ``(launch speed sd m/s, launch angle sd rad)``:
        how far the levels of that kind of player spread (the prior's sd); only the kinds
        given.
    draws : int
        Draws per row of the study's own prediction of each row.
    """

    spread: dict
    draws: int = 64

    def config(self) -> dict:
        """The table as the study's config records it (SI)."""
        return {"spread": {k: list(v) for k, v in self.spread.items()}, "draws": self.draws}


def parse_player_levels(table, swing) -> PlayerLevels | None:
    """``[pitches]``'s ``[pitches.player_levels]`` -> ``PlayerLevels``, or None without
    it. It needs ``swing = true`` (the levels are beyond what each measured swing
    gives)."""
    name = "pitches.player_levels"
    sub = table.get("player_levels")
    if sub is None:
        return None
    if not isinstance(sub, dict):
        raise InputError(name, f"must be a table ([{name}]), got {sub!r}")
    if not swing:
        raise InputError(name, "only with pitches.swing = true (a player's level is what "
                         "his balls in play keep beyond each measured swing)")
    check_keys(sub, name, (), (*_KEYS, "draws"))
    spread = {}
    for kind in KINDS:
        given = [k for k in _KEYS if k.startswith(kind) and k in sub]
        if not given:
            continue
        if len(given) == 1:
            missing = next(k for k in _KEYS if k.startswith(kind) and k not in sub)
            raise InputError(f"{name}.{missing}", f"needed with {given[0]} (the sd of the "
                             f"{kind}s' launch speed and launch angle levels)")
        values = []
        for key in (f"{kind}_launch_speed", f"{kind}_launch_angle"):
            value = fixed_value(sub[key], f"{name}.{key}", _KEYS[key],
                                '{ value = 1.2, unit = "mph" }')
            if not value > 0.0:
                raise InputError(f"{name}.{key}", f"must be > 0 (the sd of the levels), "
                                 f"got {sub[key]!r}")
            values.append(float(value))
        spread[kind] = tuple(values)
    if not spread:
        raise InputError(name, "needs the levels' sd of the batters or the pitchers "
                         "(batter_launch_speed and batter_launch_angle, ...)")
    draws = sub.get("draws", 64)
    if isinstance(draws, bool) or not isinstance(draws, int) or not 8 <= draws <= 10_000:
        raise InputError(f"{name}.draws", f"must be an integer in 8 .. 10000 (draws per "
                         f"row of the study's own prediction), got {draws!r}")
    return PlayerLevels(spread, draws)


def _centre(dist):
    """The centre about which a contact distribution's draws spread."""
    if isinstance(dist, (Normal, TruncNormal)):
        return float(dist.mean)
    if isinstance(dist, Uniform):
        return 0.5 * (float(dist.low) + float(dist.high))
    return None


def check_contact(inputs) -> None:
    """Refuse ``[pitches.player_levels]`` when the contact it acts on is not drawn
    (``inputs``: the study's; ``from_barrel_end`` and ``undercut`` of ``[contact]`` must be
    normal, truncated normal or uniform)."""
    for key in ("from_barrel_end", "undercut"):
        dist = inputs.get(f"contact.{key}")
        if dist is None or _centre(dist) is None:
            raise InputError("pitches.player_levels", f"needs [contact] {key} drawn from "
                             "a normal, truncnormal or uniform distribution (a player's "
                             "level moves the contact's draws)")


def apply_player_contact(cols, row, contact, inputs) -> None:
    """Give each sample its players' contact, in place: ``cols`` (column name -> float64
    array, the study's sample rows), ``row`` (int64: each sample's index into the rows
    drawn from), ``contact`` (``(spread[M], shift[M] m)``, per row), ``inputs`` (the
    study's: the contact's distributions)."""
    spread, shift = contact[:2]
    along, under = inputs["contact.from_barrel_end"], inputs["contact.undercut"]
    centre, factor, drawn = _centre(along), spread[row], cols["from_barrel_end"]
    # (a row of the league's contact keeps its draw bit for bit)
    moved = np.where(factor == 1.0, drawn, centre + factor * (drawn - centre))
    drawn[:] = np.clip(moved, *along.support())
    cols["undercut"][:] = np.clip(cols["undercut"] + shift[row], *under.support())
