"""mcbat.stats.compare.comparison: a simulated dataset against a measured table, column by column,
with units converted or refused and rows without a value dropped and counted."""

import numpy as np
import pandas as pd
import pytest

from mcbat.errors import InputError
from mcbat.stats.compare.comparison import compare, ks_test


def _sim(n=4000, seed=0):
    rng = np.random.default_rng(seed)
    df = pd.DataFrame({"launch_speed": rng.normal(90, 12, n),
                       "launch_angle": rng.normal(12, 25, n),
                       "pitch_speed": rng.normal(38.4, 1.2, n),  # m/s, as datasets store it
                       "handedness": np.ones(n), "sample_id": np.arange(n)})
    df.attrs["units"] = {"launch_speed": "mph", "launch_angle": "deg", "pitch_speed": "m/s",
                         "handedness": "1 (+1 R, -1 L)", "sample_id": "1"}
    return df


def _measured(n=300, seed=1, units=None, **shift):
    rng = np.random.default_rng(seed)
    df = pd.DataFrame({"launch_speed": rng.normal(90, 12, n) + shift.get("speed", 0.0),
                       "launch_angle": rng.normal(12, 25, n),
                       "pitch_speed": rng.normal(86, 2.7, n),  # mph, as Statcast has it
                       "handedness": np.ones(n)})
    df.attrs["units"] = units if units is not None else {"pitch_speed": "mph"}
    return df


def test_compare_converts_stated_units_and_leaves_out_codes():
    result = compare(_sim(), _measured(), permutations=50)
    columns = {c["column"]: c for c in result.columns}
    assert set(columns) == {"launch_speed", "launch_angle", "pitch_speed"}
    # the measured table's mph is the unit of comparison: 38.4 m/s = 85.9 mph
    pitch = columns["pitch_speed"]
    assert pitch["unit"] == "mph" and pitch["converted_from"] == "m/s"
    assert pitch["simulated"]["median"] == pytest.approx(38.4 / 0.44704, rel=0.01)
    assert pitch["ks"]["statistic"] < 0.15  # the same distribution, once converted
    assert [c["column"] for c in result.not_compared] == ["handedness"]
    assert result.plane["columns"] == ["launch_speed", "launch_angle"]
    assert result.plane["simulated_rows"] == 2000 and result.plane["measured_rows"] == 300


def test_launch_speed_in_m_s_is_caught_or_converted():
    sim = _sim()
    meas = _measured()
    meas["launch_speed"] *= 0.44704  # the table holds m/s but states no unit
    with pytest.raises(InputError, match="wrong unit") as err:
        compare(sim, meas, permutations=10)
    assert err.value.field == "launch_speed" and "m/s" in err.value.message
    # the advised parameter is data, so a command line can spell it as its flag
    assert err.value.mentions == {"units": {"launch_speed": "m/s"}}
    assert "(units={'launch_speed': 'm/s'})" in err.value.message
    # stated, it is converted and agrees
    result = compare(sim, meas, ["launch_speed"], units={"launch_speed": "m/s"},
                     permutations=10)
    assert result.columns[0]["ks"]["p_value"] > 0.01
    assert result.columns[0]["unit"] == "m/s"
    # a unit of another quantity is refused when asked for
    with pytest.raises(InputError, match="units differ") as err:
        compare(sim, meas, ["launch_speed"], units={"launch_speed": "deg"}, permutations=10)
    assert err.value.field == "launch_speed"


def test_nan_rows_are_dropped_per_column_and_counted():
    sim, meas = _sim(), _measured()
    sim.loc[:9, "launch_speed"] = np.nan
    meas.loc[:4, "launch_angle"] = np.nan
    result = compare(sim, meas, ["launch_speed", "launch_angle"], permutations=10)
    speed, angle = result.columns
    assert (speed["simulated"]["rows"], speed["simulated"]["dropped"]) == (3990, 10)
    assert (speed["measured"]["rows"], speed["measured"]["dropped"]) == (300, 0)
    assert (angle["measured"]["rows"], angle["measured"]["dropped"]) == (295, 5)
    assert result.plane["simulated_available"] == 3990
    assert result.plane["measured_available"] == 295


def test_subsampling_caps_the_energy_test_only():
    sim, meas = _sim(), _measured()
    result = compare(sim, meas, ["launch_speed"], permutations=20, max_rows=1000)
    column = result.columns[0]
    assert column["energy"]["rows"] == [1000, 300] and column["energy"]["subsampled"]
    assert column["simulated"]["rows"] == 4000  # KS and Wasserstein use every row
    assert column["ks"] == ks_test(sim["launch_speed"], meas["launch_speed"])
    # a column's result does not depend on which other columns are compared
    alone = compare(sim, meas, ["launch_angle"], permutations=20, max_rows=1000)
    both = compare(sim, meas, ["launch_speed", "launch_angle"], permutations=20,
                   max_rows=1000)
    assert alone.columns[0] == both.columns[1]


@pytest.mark.parametrize("columns, measured, words", [
    (["spray_angle"], None, ["spray_angle", "not a column of the simulated"]),
    (None, pd.DataFrame({"foo": [1.0]}), ["shares no column"]),
    (None, pd.DataFrame({"launch_speed": []}, dtype=float), ["no rows"]),
    (["launch_speed"], pd.DataFrame({"launch_speed": [np.nan, np.nan]}),
     ["launch_speed", "no finite value"]),
])
def test_bad_comparisons_name_their_column(columns, measured, words):
    if measured is None:
        measured = _measured()
    with pytest.raises(InputError) as err:
        compare(_sim(), measured, columns, permutations=10)
    for word in words:
        assert word in str(err.value)
