"""Real pitches and batted balls: Baseball Savant (Statcast) exports in mcbat's frame and
units (``docs/statcast.md``).

``read(path_or_dataframe)`` gives the tidy table, one row per pitch; ``write(df, path)``
stores it as Parquet with its units; ``summarize(df)`` the counts ``mcbat statcast``
prints. The pitch's crossing of the plate and the spray angle are the small pure
functions of ``mcbat.statcast.kinematics``; the parks and their elevations
``mcbat.statcast.parks``.
"""

from mcbat.statcast.collision import (
    collision_columns,
    collision_summary,
    is_bunt,
    squared_up_maximum,
)
from mcbat.statcast.kinematics import plate_crossing, spray_angle
from mcbat.statcast.measured import is_statcast, measurement_table
from mcbat.statcast.reader import (
    COLUMNS,
    OPTIONAL,
    REQUIRED,
    UNITS,
    balls_in_play,
    read,
    write,
)
from mcbat.statcast.summary import attack_direction_check, summarize

__all__ = ["COLUMNS", "OPTIONAL", "REQUIRED", "UNITS", "attack_direction_check",
           "balls_in_play", "collision_columns", "collision_summary", "is_bunt",
           "is_statcast", "squared_up_maximum", "measurement_table", "plate_crossing", "read",
           "spray_angle", "summarize", "write"]
