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


def _outlier_study(tmp_path, rows, outliers, samples=40000):
    path = tmp_path / "outlier_rows.csv"
    write_pitches(rows, path)
    data = {"study": {"name": "t", "samples": samples, "seed": 5},
            "ball": {"preset": "baseball"}, "bat": {"preset": "r161"},
            "pitches": {"file": str(path), "swing": True, "swing_error": {
                "bat_speed": {"value": 2, "unit": "mph"},
                **({"bat_speed_outliers": outliers} if outliers is not None else {})}},
            "pitch": {"spin_efficiency": 0.9},
            "swing": {"vertical_bat_angle": {"value": -30, "unit": "deg"}},
            "contact": {"from_barrel_end": {"value": 6, "unit": "in"}, "undercut": 0.0},
            "friction": {"mu": 0.5}}
    return load_pitches(Study.from_dict(data))


def _contaminated_rows(n=6000, share=0.05, excess=13.0, seed=11):
    """Rows whose true bat speeds (mph, returned too) were measured with a 2-mph error,
    and a share of them ``excess`` too fast."""
    rng = np.random.default_rng(seed)
    rows = _rows(n, seed)
    true = rng.normal(70.0, 5.0, n)
    outlier = rng.random(n) < share
    rows["bat_speed"] = true + np.where(outlier, rng.normal(excess, 2.0, n),
                                        rng.normal(0.0, 2.0, n))
    return rows, true


def test_bat_speed_outliers_recover_the_true_speeds(tmp_path):
    rows, true = _contaminated_rows()
    study = _outlier_study(tmp_path, rows, {"fraction": 0.05,
                                            "excess": {"value": 13, "unit": "mph"}})
    _, measured, drawn = _measured_and_drawn(study, "bat_speed")
    j = study.pitch_rows.index[study.pitch_rows.draw_rows(study.seed, 0, study.samples)]
    truth = true[j] * 0.44704
    # the draws follow the true population, not the measured one
    assert drawn.mean() == pytest.approx(truth.mean(), abs=0.15 * 0.44704)
    assert drawn.std() == pytest.approx(truth.std(), rel=0.04)
    # where the outliers dominate (measured far above the population), the draws are as
    # slow as the true swings of those rows, and the plain error would not be
    fast = measured > 81.0 * 0.44704
    assert fast.sum() > 1000
    assert drawn[fast].mean() == pytest.approx(truth[fast].mean(), abs=1.0 * 0.44704)
    plain = _outlier_study(tmp_path, rows, None)
    _, _, plain_drawn = _measured_and_drawn(plain, "bat_speed")
    assert plain_drawn[fast].mean() > truth[fast].mean() + 3.0 * 0.44704
    # and the swings in the bulk keep their measured speed, shrunk as by the plain error
    bulk = np.abs(measured - 70.0 * 0.44704) < 3.0 * 0.44704
    assert drawn[bulk].mean() == pytest.approx(truth[bulk].mean(), abs=0.3 * 0.44704)


def test_zero_outlier_share_is_the_plain_error(tmp_path):
    rows, _ = _contaminated_rows(n=500)
    plain = _outlier_study(tmp_path, rows, None, samples=3000)
    zero = _outlier_study(tmp_path, rows, {"fraction": 0.0,
                                           "excess": {"value": 13, "unit": "mph"}},
                          samples=3000)
    np.testing.assert_allclose(plain.sample()["bat_speed"], zero.sample()["bat_speed"],
                               rtol=0, atol=1e-12)
    assert zero.config()["pitches"]["bat_speed_outliers"]["fraction"] == 0.0
    assert plain.config_hash() != zero.config_hash()


@pytest.mark.parametrize("outliers, errors, field", [
    ({"fraction": 0.6, "excess": {"value": 13, "unit": "mph"}}, None,
     "bat_speed_outliers.fraction"),
    ({"fraction": 0.05, "excess": {"value": 13, "unit": "deg"}}, None,
     "bat_speed_outliers.excess"),
    ({"fraction": 0.05}, None, "bat_speed_outliers.excess"),
    ({"fraction": 0.05, "excess": {"value": 13, "unit": "mph"}, "width": 1}, None,
     "bat_speed_outliers.width"),
    ({"fraction": 0.05, "excess": {"value": 13, "unit": "mph"}},
     {"attack_angle": {"value": 4, "unit": "deg"}}, "bat_speed_outliers"),
])
def test_bad_outliers_name_their_field(tmp_path, outliers, errors, field):
    errors = dict(errors or {"bat_speed": {"value": 2, "unit": "mph"}})
    errors["bat_speed_outliers"] = outliers
    with pytest.raises(InputError) as err:
        _study(tmp_path, errors)
    assert field in str(err.value)


def test_bat_speed_outliers_keep_the_fast_swings_of_a_fast_population(tmp_path):
    # one fast batter's file: his 80-mph swings are common, not outliers
    rows, true = _contaminated_rows(share=0.0)
    rows["bat_speed"] += 6.0
    true = true + 6.0
    study = _outlier_study(tmp_path, rows, {"fraction": 0.05,
                                            "excess": {"value": 13, "unit": "mph"}})
    _, measured, drawn = _measured_and_drawn(study, "bat_speed")
    j = study.pitch_rows.index[study.pitch_rows.draw_rows(study.seed, 0, study.samples)]
    fast = (measured > 80.0 * 0.44704) & (measured < 84.0 * 0.44704)
    assert fast.sum() > 2000
    # (the assumed 5 % of outliers, absent here, cost these rows a few tenths of a mph;
    # a normal population of the rows' mean and variance would take them for outliers and
    # draw many of them several mph slower)
    assert drawn[fast].mean() == pytest.approx(true[j][fast].mean() * 0.44704,
                                               abs=1.0 * 0.44704)


def test_bat_speed_outliers_with_no_measured_bat_speed_keep_the_fallback(tmp_path):
    # a file before bat tracking, every bat speed drawn from the fallback: no measurement
    # to correct, and the fallback's draws are left as drawn
    rows, _ = _contaminated_rows(n=300)
    rows["bat_speed"] = np.nan
    path = tmp_path / "untracked.csv"
    write_pitches(rows, path)
    data = {"study": {"name": "t", "samples": 2000, "seed": 5},
            "ball": {"preset": "baseball"}, "bat": {"preset": "r161"},
            "pitches": {"file": str(path), "swing": True,
                        "fallback": {"bat_speed": {"value": 70, "unit": "mph"}},
                        "swing_error": {"bat_speed": {"value": 2, "unit": "mph"},
                                        "bat_speed_outliers": {
                                            "fraction": 0.05,
                                            "excess": {"value": 13, "unit": "mph"}}}},
            "pitch": {"spin_efficiency": 0.9},
            "swing": {"vertical_bat_angle": {"value": -30, "unit": "deg"}},
            "contact": {"from_barrel_end": {"value": 6, "unit": "in"}, "undercut": 0.0},
            "friction": {"mu": 0.5}}
    cols = load_pitches(Study.from_dict(data)).sample()
    np.testing.assert_array_equal(cols["bat_speed"], 70 * 0.44704)
