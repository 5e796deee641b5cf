"""An inference written to Parquet: the measured balls beside their inferred contact and
spin, with units, assumptions and status counts in the schema metadata."""

from __future__ import annotations

import pandas as pd

__all__ = ["CARRIED_COLUMNS", "METADATA_KEY", "write"]

CARRIED_COLUMNS = ("game_pk", "at_bat_number", "pitch_number", "batter", "pitcher",
                   "game_date", "home_team", "elevation", "handedness", "pitch_type",
                   "events", "bb_type", "launch_speed", "launch_angle", "spray_angle",
                   "hit_distance_sc")
"""Columns of the tidy table ``write`` keeps beside the inference's (those present)."""

METADATA_KEY = b"mcbat.inference"
"""The Parquet schema-metadata key of ``write``'s file: JSON with ``units``,
``assumptions`` and ``status_counts``."""


def write(table, spin, path) -> None:
    """Write the balls (``CARRIED_COLUMNS`` of ``table``) and their inferred contact
    and spin (``spin``, from ``infer_spin`` on ``table``) to one Parquet file,
    atomically, with units, assumptions and status counts in the schema metadata; or,
    for a path ending in ``.csv``, to a CSV file with the units in its header
    (:func:`mcbat.dataset.tables.write_table`)."""
    import json

    from mcbat.statcast.files import write_parquet

    carried = [c for c in CARRIED_COLUMNS if c in table.columns]
    df = pd.concat([table[carried], spin], axis=1)
    units = {c: table.attrs.get("units", {}).get(c, "") for c in carried}
    units.update(spin.attrs["units"])
    if str(path).lower().endswith(".csv"):
        from mcbat.dataset.tables import write_table

        write_table(df, path, units)
        return
    info = {"units": units, "assumptions": spin.attrs["assumptions"],
            "status_counts": spin.attrs["status_counts"]}
    write_parquet(df, path, {METADATA_KEY: json.dumps(info).encode()})
