"""The columns of a measurement table, with their units and roles: a bat-frame (drop-test)
table's and a game table's (Statcast's names and units)."""

from __future__ import annotations

__all__ = ["BAT_FRAME_COLUMNS", "GAME_TABLE_COLUMNS", "GAME_WRITTEN", "UNITS_HINT",
           "column_roles", "table_columns"]


def column_roles(**roles: dict[str, str]) -> dict[str, tuple[str, str]]:
    """A measurement table's columns as ``{name: (unit, role)}``, from ``{name: unit}`` per
    role (``input``: a measured input; ``observable``: fitted; ``optional``), in the order
    given."""
    return {name: (unit, role) for role, units in roles.items()
            for name, unit in units.items()}


BAT_FRAME_COLUMNS = column_roles(
    input={"impact_parameter": "m", "spin_in": "rad/s"},
    observable={"exit_speed": "m/s", "scattering_angle": "deg", "spin_out": "rad/s"})
"""Columns of a bat-frame measurement table (a drop test), with their units."""
GAME_TABLE_COLUMNS = column_roles(
    input={"pitch_speed": "mph", "bat_speed": "mph", "attack_angle": "deg", "undercut": "m",
           "from_barrel_end": "m"},
    observable={"launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg",
                "spin_rate": "rpm", "backspin": "rpm", "sidespin": "rpm"})
"""Columns of a game measurement table (Statcast's names and units where it has them)."""
UNITS_HINT = {
    "exit_speed": "wrong unit? exit_speed is in m/s (mph would be 2.24 times larger, km/h "
                  "3.6 times)",
    "scattering_angle": "wrong unit? scattering_angle is in degrees (radians would be 57 "
                        "times smaller)",
    "spin_out": "wrong unit or sign convention? spin_out is in rad/s about the bat axis (rpm "
                "would be 9.55 times larger)",
    "launch_speed": "wrong unit? launch_speed is in mph (m/s would be 2.24 times smaller, "
                    "km/h 1.6 times larger)",
    "launch_angle": "wrong unit or convention? launch_angle is the elevation in degrees",
    "spray_angle": "wrong unit or convention? spray_angle is in degrees, positive towards "
                   "right field (docs/batting.md)",
    "spin_rate": "wrong unit? spin_rate is in rpm (rad/s would be 9.55 times smaller)",
    "backspin": "wrong unit or sign? backspin is in rpm, positive for backspin",
    "sidespin": "wrong unit or sign? sidespin is in rpm (docs/batting.md)",
    "hit_distance_sc": "wrong unit? hit_distance_sc is in ft (m would be 3.28 times smaller)",
}
"""What to check when a column lies far outside anything the model gives."""


def table_columns(game: bool) -> dict:
    """The measurement columns of a game (True) or a bat-frame (False) study."""
    return GAME_TABLE_COLUMNS if game else BAT_FRAME_COLUMNS


GAME_WRITTEN = ("pitch_speed", "bat_speed", "attack_angle", "undercut")
"""The measured inputs ``mcbat.stats.measurements.synthesize`` writes into a game
table."""
