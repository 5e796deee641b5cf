"""The rows a population fit uses (mcbat.stats.population.table): the balls in play of the
real Statcast rows shipped in data/, and a table without an observable refused."""

import numpy as np
import pytest

from mcbat.errors import InputError
from mcbat.statcast import read
from mcbat.stats.population.table import population_table
from tests.stats.population_shared import REAL


@pytest.fixture(scope="module")
def pitches():
    table, _ = population_table(read(REAL))
    return table


def test_real_rows_are_the_balls_in_play(pitches):
    # data/statcast_2020-09-03.csv: every used row has a launch, a plate speed and a side
    assert len(pitches) > 300
    assert np.all(np.isfinite(pitches[["launch_speed", "launch_angle", "pitch_speed"]]))
    assert set(pitches["handedness"]) <= {"R", "L"}


def test_table_without_observables(pitches):
    with pytest.raises(InputError, match="launch_angle"):
        population_table(pitches.drop(columns=["launch_angle"]))
    table = pitches.copy()
    table["launch_speed"] = np.nan
    with pytest.raises(InputError, match="no rows with launch_speed"):
        population_table(table)


def test_the_studys_pitch_filters_select_the_rows(pitches):
    # a study drawing the balls in play ([pitches] bb_type = ...) is fitted to those rows
    # only: an export's foul balls have a launch but no bb_type
    table = pitches.copy()
    table.loc[table.index[:40], "bb_type"] = None
    table.loc[table.index[40:60], "bb_type"] = "popup"
    accepted = {"bb_type": ("ground_ball", "line_drive", "fly_ball")}
    used, dropped = population_table(table, filters=accepted)
    assert dropped["not_selected"] == int((~table["bb_type"].isin(accepted["bb_type"])).sum())
    assert dropped["not_selected"] >= 60
    assert set(used["bb_type"]) <= set(accepted["bb_type"])
    assert len(used) == len(table) - dropped["not_selected"]
    numeric = population_table(table, filters={"game_year": (2020,)})[0]
    assert len(numeric) == len(table)
    with pytest.raises(InputError) as err:
        population_table(table.drop(columns=["bb_type"]), filters=accepted)
    assert err.value.field == "pitches.bb_type"
