"""The measurement errors of the measured swing (``[pitches.swing_error]``)."""

import math

import numpy as np
import pandas as pd
import pytest

from mcbat.errors import InputError
from mcbat.runner.pitches import load_pitches
from mcbat.stats.population.table import population_table, write_pitches
from mcbat.study.spec import Study


def _rows(n=400, seed=3):
    rng = np.random.default_rng(seed)
    return pd.DataFrame({
        "pitch_speed": rng.normal(85.0, 4.0, n), "vertical_approach_angle": -6.0,
        "horizontal_approach_angle": 0.0, "spin_rate": 2200.0, "spin_axis": 200.0,
        "bat_speed": rng.normal(70.0, 5.0, n), "attack_angle": rng.normal(9.0, 8.0, n),
        "attack_direction": rng.normal(0.0, 12.0, n), "handedness": "R",
        "launch_speed": 90.0, "launch_angle": 10.0})


def _study(tmp_path, errors=None, swing=True):
    path = tmp_path / "rows.csv"
    write_pitches(_rows(), path)
    pitches = {"file": str(path), "swing": swing}
    if errors is not None:
        pitches["swing_error"] = errors
    data = {"study": {"name": "t", "samples": 20000, "seed": 5},
            "ball": {"preset": "baseball"}, "bat": {"preset": "r161"},
            "pitches": pitches, "pitch": {"spin_efficiency": 0.9},
            "swing": {"vertical_bat_angle": {"value": -30, "unit": "deg"}} if swing else
            {"bat_speed": {"value": 70, "unit": "mph"},
             "attack_angle": {"value": 10, "unit": "deg"},
             "vertical_bat_angle": {"value": -30, "unit": "deg"}},
            "contact": {"from_barrel_end": {"value": 6, "unit": "in"}, "undercut": 0.0},
            "friction": {"mu": 0.5}}
    return load_pitches(Study.from_dict(data))


def _measured_and_drawn(study, name):
    cols = study.sample(0, study.samples)
    rows = study.pitch_rows
    j = rows.draw_rows(study.seed, 0, study.samples)
    k = rows.keys.index(f"swing.{name}")
    return rows.values[k], rows.values[k, j], cols[name]


def test_zero_error_leaves_the_measured_swing(tmp_path):
    study = _study(tmp_path, {"attack_angle": {"value": 0, "unit": "deg"}})
    _, measured, drawn = _measured_and_drawn(study, "attack_angle")
    np.testing.assert_array_equal(measured, drawn)


def test_error_shrinks_towards_the_mean_and_scatters(tmp_path):
    s = math.radians(4.0)
    study = _study(tmp_path, {"attack_angle": {"value": 4, "unit": "deg"}})
    population, measured, drawn = _measured_and_drawn(study, "attack_angle")
    k = 1.0 - s * s / population.var()
    slope = np.polyfit(measured, drawn, 1)[0]
    assert slope == pytest.approx(k, abs=0.02)
    residual = drawn - (population.mean() + k * (measured - population.mean()))
    assert residual.std() == pytest.approx(math.sqrt(k) * s, rel=0.03)
    # the draws' spread is the population's true spread, sqrt(v - s^2)
    assert drawn.std() == pytest.approx(math.sqrt(population.var() - s * s), rel=0.03)


def test_bat_speed_error_in_mph(tmp_path):
    study = _study(tmp_path, {"bat_speed": {"value": 2, "unit": "mph"}})
    population, measured, drawn = _measured_and_drawn(study, "bat_speed")
    s = 2.0 * 0.44704
    assert np.polyfit(measured, drawn, 1)[0] == pytest.approx(1 - s * s / population.var(),
                                                              abs=0.02)


def test_swing_error_needs_measured_swings(tmp_path):
    with pytest.raises(InputError, match="pitches.swing_error"):
        _study(tmp_path, {"attack_angle": {"value": 4, "unit": "deg"}}, swing=False)


@pytest.mark.parametrize("spec", [{"value": -1, "unit": "deg"},
                                  {"dist": "uniform", "low": 0, "high": 2, "unit": "deg"}])
def test_swing_error_must_be_a_fixed_sd(tmp_path, spec):
    with pytest.raises(InputError, match="pitches.swing_error.attack_angle"):
        _study(tmp_path, {"attack_angle": spec})


def test_swing_error_unknown_key(tmp_path):
    with pytest.raises(InputError, match="pitches.swing_error"):
        _study(tmp_path, {"spin_rate": {"value": 4, "unit": "rpm"}})


def test_population_table_with_swing_needs_bat_speed():
    rows = _rows(10)
    rows.loc[:2, "bat_speed"] = np.nan
    used, dropped = population_table(rows, swing=True)
    assert len(used) == 7 and dropped["no_bat_speed"] == 3
    used, _ = population_table(rows)
    assert len(used) == 10
