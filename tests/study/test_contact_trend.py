"""The contact's bat-speed trend (``[contact.bat_speed_trend]``), its pitch-location trends
(``[contact.plate_x_trend]``, ``[contact.plate_z_trend]``), its swing-length trend
(``[contact.swing_length_trend]``) and measurement errors that apply to measured swings
only (not to values drawn from ``[pitches.fallback]``)."""

import math

import numpy as np
import pandas as pd
import pytest

from mcbat.errors import InputError
from mcbat.runner.pitches import load_pitches
from mcbat.stats.population.table import write_pitches
from mcbat.study.spec import Study

MPH, INCH = 0.44704, 0.0254


def _rows(n=400, seed=3, attack=True):
    rng = np.random.default_rng(seed)
    return pd.DataFrame({
        "plate_x": rng.uniform(-1.5, 1.5, n), "plate_z": rng.uniform(1.0, 4.0, n),
        "handedness": rng.choice(["R", "L"], n),
        "pitch_speed": rng.normal(85.0, 4.0, n), "vertical_approach_angle": -6.0,
        "horizontal_approach_angle": 0.0, "spin_rate": 2200.0, "spin_axis": 200.0,
        "bat_speed": rng.normal(70.0, 5.0, n),
        "attack_angle": rng.normal(9.0, 8.0, n) if attack else np.nan,
        "attack_direction": rng.normal(0.0, 12.0, n),
        "launch_speed": 90.0, "launch_angle": 10.0})


def _data(tmp_path, rows, contact=None, **pitches):
    path = tmp_path / "rows.csv"
    write_pitches(rows, path)
    return {"study": {"name": "t", "samples": 20000, "seed": 5},
            "ball": {"preset": "baseball"}, "bat": {"preset": "r161"},
            "pitches": {"file": str(path), "swing": True, **pitches},
            "pitch": {"spin_efficiency": 0.9},
            "swing": {"vertical_bat_angle": {"value": -30, "unit": "deg"}},
            "contact": contact or {"from_barrel_end": {"dist": "truncnormal", "mean": 7,
                                                       "std": 3, "low": 0.5, "high": 18,
                                                       "unit": "in"},
                                   "undercut": 0.0},
            "friction": {"mu": 0.5},
            "restitution": {"e_ref": 0.555, "e_slope": 0.00165,
                            "e_speed_ref": {"value": 85, "unit": "ft/s"}, "e_x": 0.28,
                            "location": "assumed"}}


def _trend(shift=1.0, reference=70.0, per=10.0):
    return {"reference": {"value": reference, "unit": "mph"},
            "per": {"value": per, "unit": "mph"},
            "from_barrel_end": {"value": shift, "unit": "in"}}


def test_trend_moves_the_contact_with_the_bat_speed(tmp_path):
    plain = _data(tmp_path, _rows())
    moved = _data(tmp_path, _rows())
    moved["contact"]["bat_speed_trend"] = _trend(1.5)
    a = load_pitches(Study.from_dict(plain)).sample()
    b = load_pitches(Study.from_dict(moved)).sample()
    np.testing.assert_array_equal(a["bat_speed"], b["bat_speed"])
    expected = np.clip(a["from_barrel_end"] + 1.5 * INCH / (10 * MPH)
                       * (a["bat_speed"] - 70 * MPH), 0.5 * INCH, 18 * INCH)
    np.testing.assert_allclose(b["from_barrel_end"], expected, rtol=0, atol=1e-15)
    # the restitution's location factor and the barrel's radius follow the moved contact
    assert not np.array_equal(a["e_location_factor"], b["e_location_factor"])
    fast = a["bat_speed"] > 75 * MPH
    assert np.mean(b["from_barrel_end"][fast]) > np.mean(a["from_barrel_end"][fast]) + 0.5 * INCH


def test_zero_trend_is_no_trend_and_changes_the_config(tmp_path):
    plain = load_pitches(Study.from_dict(_data(tmp_path, _rows())))
    data = _data(tmp_path, _rows())
    data["contact"]["bat_speed_trend"] = _trend(0.0)
    zero = load_pitches(Study.from_dict(data))
    np.testing.assert_array_equal(plain.sample()["from_barrel_end"],
                                  zero.sample()["from_barrel_end"])
    assert plain.config_hash() != zero.config_hash()
    again = load_pitches(Study.from_dict(zero.definition()))
    assert again.config() == zero.config()
    assert zero.config()["contact"]["bat_speed_trend"]["from_barrel_end_per_bat_speed"] == 0


def test_trend_on_a_fixed_contact_stays_on_the_bat(tmp_path):
    data = _data(tmp_path, _rows(), contact={"from_barrel_end": {"value": 1, "unit": "in"},
                                             "undercut": 0.0,
                                             "bat_speed_trend": _trend(-20.0)})
    cols = load_pitches(Study.from_dict(data)).sample()
    assert cols["from_barrel_end"].min() >= 0.0
    assert np.any(cols["from_barrel_end"] == 0.0)


@pytest.mark.parametrize("key, value, field", [
    ("per", {"value": 0, "unit": "mph"}, "contact.bat_speed_trend.per"),
    ("from_barrel_end", {"dist": "normal", "mean": 1, "std": 1, "unit": "in"},
     "contact.bat_speed_trend.from_barrel_end"),
    ("reference", {"value": 70, "unit": "in"}, "contact.bat_speed_trend.reference"),
])
def test_bad_trend_names_its_field(tmp_path, key, value, field):
    data = _data(tmp_path, _rows())
    data["contact"]["bat_speed_trend"] = {**_trend(), key: value}
    with pytest.raises(InputError) as err:
        Study.from_dict(data)
    assert field in str(err.value)


@pytest.mark.parametrize("key, message", [
    ("per", "per"),
    # without its only shift the trend moves nothing: it must have one of the two
    ("from_barrel_end", "from_barrel_end or undercut"),
])
def test_trend_missing_key_names_it(tmp_path, key, message):
    data = _data(tmp_path, _rows())
    trend = _trend()
    del trend[key]
    data["contact"]["bat_speed_trend"] = trend
    with pytest.raises(InputError, match=message):
        Study.from_dict(data)


def test_swing_error_leaves_fallback_draws_alone(tmp_path):
    # rows without an attack angle (2024 exports) take the fallback distribution: those
    # draws are the true values' distribution, not measurements, and keep their width
    rows = _rows(attack=False)
    rows.loc[:199, "attack_angle"] = np.random.default_rng(1).normal(9.0, 8.0, 200)
    fallback = {"attack_angle": {"dist": "truncnormal", "mean": 8.7, "std": 8.3, "low": -35,
                                 "high": 35, "unit": "deg"}}
    errors = {"attack_angle": {"value": 6, "unit": "deg"}}
    plain = load_pitches(Study.from_dict(_data(tmp_path, rows, fallback=fallback)))
    noisy = load_pitches(Study.from_dict(_data(tmp_path, rows, fallback=fallback,
                                               swing_error=errors)))
    a, b = plain.sample()["attack_angle"], noisy.sample()["attack_angle"]
    j = plain.pitch_rows.draw_rows(plain.seed, 0, plain.samples)
    from_fallback = ~np.isfinite(plain.pitch_rows.values[
        plain.pitch_rows.keys.index("swing.attack_angle"), j])
    assert 0.3 < from_fallback.mean() < 0.7
    np.testing.assert_array_equal(a[from_fallback], b[from_fallback])
    assert math.degrees(np.std(b[from_fallback])) == pytest.approx(8.3, rel=0.05)
    # the measured ones are shrunk towards their mean and scattered
    assert not np.array_equal(a[~from_fallback], b[~from_fallback])


def _assert_weighed_as_drawn(plain, moved, column, observable, draws=3000):
    """A population fit reweights the drawn contact by its distribution's density: the
    templates hand it the draws before the trend moved them (the same random numbers),
    and the batted balls of the moved contact."""
    from mcbat.stats.population.templates import _solve_memory

    a, obs_a, _ = _solve_memory(plain, draws, 9, [column], [observable])
    b, obs_b, _ = _solve_memory(moved, draws, 9, [column], [observable])
    np.testing.assert_array_equal(a[column], b[column])
    assert not np.allclose(obs_a[observable], obs_b[observable], equal_nan=True)


def test_population_templates_weigh_the_contact_before_the_trend(tmp_path):
    plain = Study.from_dict(_data(tmp_path, _rows()))
    data = _data(tmp_path, _rows())
    data["contact"]["bat_speed_trend"] = _trend(2.0)
    _assert_weighed_as_drawn(plain, Study.from_dict(data), "from_barrel_end", "launch_speed")


def test_population_fit_with_a_trend_refuses_other_engines(tmp_path):
    from mcbat.stats.population.parameters import parse_free
    from mcbat.stats.population.templates import TemplateSimulator

    data = _data(tmp_path, _rows())
    data["contact"]["bat_speed_trend"] = _trend(1.0)
    study = Study.from_dict(data)
    keys, _, _ = parse_free(study, ("contact.from_barrel_end.mean",))
    key = keys["contact.from_barrel_end"]
    sim = TemplateSimulator(study, _rows(), 100, 1, "local", tmp_path / "work")
    try:
        with pytest.raises(InputError, match="memory"):
            sim.run({"contact.from_barrel_end": (key, key.mean, key.std)}, {},
                    ["from_barrel_end"], ["launch_speed"])
    finally:
        sim.close()


FT = 0.3048


def _location(shift=-8.0, zone=4.0, reference=2.0):
    return {"reference": {"value": reference, "unit": "in"},
            "dead_zone": {"value": zone, "unit": "in"}, "per": {"value": 1, "unit": "ft"},
            "from_barrel_end": {"value": shift, "unit": "in"}}


def test_plate_x_trend_moves_the_contact_with_where_the_pitch_crossed(tmp_path):
    rows = _rows()
    rows.loc[:9, "plate_x"] = np.nan  # a row without a location does not move
    plain = load_pitches(Study.from_dict(_data(tmp_path, rows)))
    data = _data(tmp_path, rows)
    data["contact"]["plate_x_trend"] = _location()
    moved = load_pitches(Study.from_dict(data))
    a, b = plain.sample(), moved.sample()
    j = plain.pitch_rows.draw_rows(plain.seed, 0, plain.samples)
    hand = np.where(rows["handedness"].to_numpy()[plain.pitch_rows.index[j]] == "R", 1, -1)
    np.testing.assert_array_equal(a["handedness"], hand)
    x = hand * rows["plate_x"].to_numpy()[plain.pitch_rows.index[j]] * FT - 2 * INCH
    shift = np.nan_to_num(-8 * INCH / FT * np.sign(x) * np.maximum(np.abs(x) - 4 * INCH, 0))
    expected = np.clip(a["from_barrel_end"] + shift, 0.5 * INCH, 18 * INCH)
    np.testing.assert_allclose(b["from_barrel_end"], expected, rtol=0, atol=1e-15)
    # a pitch well away from the batter is met nearer the barrel end, one inside nearer
    # the handle, one over the plate where it was
    away, inside = x > 8 * INCH, x < -8 * INCH
    assert np.mean(b["from_barrel_end"][away]) < np.mean(a["from_barrel_end"][away]) - INCH
    assert np.mean(b["from_barrel_end"][inside]) > np.mean(a["from_barrel_end"][inside]) + INCH
    middle = np.abs(x) <= 4 * INCH
    np.testing.assert_array_equal(b["from_barrel_end"][middle], a["from_barrel_end"][middle])
    assert moved.config()["contact"]["plate_x_trend"]["dead_zone"] == pytest.approx(4 * INCH)
    assert plain.config_hash() != moved.config_hash()


@pytest.mark.parametrize("name", ["plate_x_trend", "plate_z_trend", "swing_length_trend"])
def test_a_location_trend_needs_the_rows_of_pitches(tmp_path, name):
    data = _data(tmp_path, _rows())
    del data["pitches"]
    data["pitch"] = {"speed": {"value": 90, "unit": "mph"}}
    data["swing"]["bat_speed"] = {"value": 70, "unit": "mph"}
    data["contact"][name] = _location() if name == "plate_x_trend" else _height()
    with pytest.raises(InputError) as err:
        Study.from_dict(data)
    assert err.value.field == f"contact.{name}"


def test_plate_x_trend_names_a_file_without_plate_x(tmp_path):
    rows = _rows().drop(columns=["plate_x"])
    data = _data(tmp_path, rows)
    data["contact"]["plate_x_trend"] = _location()
    with pytest.raises(InputError, match="plate_x") as err:
        load_pitches(Study.from_dict(data))
    assert err.value.field == "pitches.file"


@pytest.mark.parametrize("key, value, field", [
    ("dead_zone", {"value": -1, "unit": "in"}, "contact.plate_x_trend.dead_zone"),
    ("per", {"value": 0, "unit": "ft"}, "contact.plate_x_trend.per"),
    ("reference", {"value": 70, "unit": "mph"}, "contact.plate_x_trend.reference"),
])
def test_bad_plate_x_trend_names_its_field(tmp_path, key, value, field):
    data = _data(tmp_path, _rows())
    data["contact"]["plate_x_trend"] = {**_location(), key: value}
    with pytest.raises(InputError) as err:
        Study.from_dict(data)
    assert field in str(err.value)


def test_population_templates_weigh_the_contact_before_the_location_moved_it(tmp_path):
    plain = Study.from_dict(_data(tmp_path, _rows()))
    data = _data(tmp_path, _rows())
    data["contact"]["plate_x_trend"] = _location()
    _assert_weighed_as_drawn(plain, Study.from_dict(data), "from_barrel_end", "launch_speed")


def _height(shift=0.4, reference=2.5):
    return {"reference": {"value": reference, "unit": "ft"}, "per": {"value": 1, "unit": "ft"},
            "undercut": {"value": shift, "unit": "in"}}


def _length(shift=0.3, reference=7.2):
    return {"reference": {"value": reference, "unit": "ft"}, "per": {"value": 1, "unit": "ft"},
            "undercut": {"value": shift, "unit": "in"}}


@pytest.mark.parametrize("column, table, shift, reference, beyond, margin", [
    # a high pitch is met further under its centre
    ("plate_z", _height, 0.4, 2.5, 3.5, 0.3),
    # of two swings at one bat speed, the longer meets the ball further under its centre
    ("swing_length", _length, 0.3, 7.2, 8.0, 0.2),
])
def test_a_row_trend_moves_the_undercut_with_its_rows_column(tmp_path, column, table, shift,
                                                            reference, beyond, margin):
    rows = _rows()
    if column == "swing_length":
        rows["swing_length"] = np.random.default_rng(8).normal(7.2, 0.8, len(rows))
    rows.loc[:9, column] = np.nan  # a row without the value does not move
    contact = {"from_barrel_end": {"value": 6, "unit": "in"},
               "undercut": {"dist": "truncnormal", "mean": 0.3, "std": 1.0, "low": -2,
                            "high": 2, "unit": "in"}}
    plain = load_pitches(Study.from_dict(_data(tmp_path, rows, contact=dict(contact))))
    data = _data(tmp_path, rows, contact=dict(contact))
    data["contact"][f"{column}_trend"] = table()
    moved = load_pitches(Study.from_dict(data))
    a, b = plain.sample(), moved.sample()
    j = plain.pitch_rows.draw_rows(plain.seed, 0, plain.samples)
    x = rows[column].to_numpy()[plain.pitch_rows.index[j]] * FT
    expected = np.clip(a["undercut"] + np.nan_to_num(shift * INCH / FT * (x - reference * FT)),
                       -2 * INCH, 2 * INCH)
    np.testing.assert_allclose(b["undercut"], expected, rtol=0, atol=1e-15)
    assert np.isnan(x).any()
    np.testing.assert_array_equal(b["undercut"][np.isnan(x)], a["undercut"][np.isnan(x)])
    np.testing.assert_array_equal(a["from_barrel_end"], b["from_barrel_end"])
    far = x > beyond * FT
    assert np.mean(b["undercut"][far]) > np.mean(a["undercut"][far]) + margin * INCH
    assert moved.config()["contact"][f"{column}_trend"][f"undercut_per_{column}"] == \
        pytest.approx(shift * INCH / FT)
    assert plain.config_hash() != moved.config_hash()
    # the population fit weighs the undercut as drawn, before the move
    _assert_weighed_as_drawn(plain, moved, "undercut", "launch_angle", draws=2000)


def test_swing_length_trend_names_a_bad_key(tmp_path):
    data = _data(tmp_path, _rows())
    data["contact"]["swing_length_trend"] = {**_length(), "per": {"value": 0, "unit": "ft"}}
    with pytest.raises(InputError) as err:
        Study.from_dict(data)
    assert "contact.swing_length_trend.per" in str(err.value)


def test_bat_speed_trend_moves_the_undercut_too(tmp_path):
    rows = _rows()
    contact = {"from_barrel_end": {"value": 6, "unit": "in"},
               "undercut": {"dist": "truncnormal", "mean": 0.3, "std": 1.0, "low": -2,
                            "high": 2, "unit": "in"}}
    plain = load_pitches(Study.from_dict(_data(tmp_path, rows, contact=dict(contact))))
    data = _data(tmp_path, rows, contact=dict(contact))
    trend = _trend(0.0)
    del trend["from_barrel_end"]
    trend["undercut"] = {"value": 0.3, "unit": "in"}
    data["contact"]["bat_speed_trend"] = trend
    moved = load_pitches(Study.from_dict(data))
    a, b = plain.sample(), moved.sample()
    np.testing.assert_array_equal(a["bat_speed"], b["bat_speed"])
    expected = np.clip(a["undercut"] + 0.3 * INCH / (10 * MPH) * (a["bat_speed"] - 70 * MPH),
                       -2 * INCH, 2 * INCH)
    np.testing.assert_allclose(b["undercut"], expected, rtol=0, atol=1e-15)
    # without its from_barrel_end the contact stays where it was drawn
    np.testing.assert_array_equal(a["from_barrel_end"], b["from_barrel_end"])
    fast = a["bat_speed"] > 75 * MPH
    assert np.mean(b["undercut"][fast]) > np.mean(a["undercut"][fast]) + 0.1 * INCH
    config = moved.config()["contact"]["bat_speed_trend"]
    assert config["undercut_per_bat_speed"] == pytest.approx(0.3 * INCH / (10 * MPH))
    assert config["from_barrel_end_per_bat_speed"] == 0
    # a faster swing meets the ball further under its centre: it leaves higher
    from mcbat.stats.models.simulate import solve_game_inputs

    la_plain = solve_game_inputs(plain, plain.sample_inputs(0, 4000))[0]["launch_angle"]
    la_moved = solve_game_inputs(moved, moved.sample_inputs(0, 4000))[0]["launch_angle"]
    fast = a["bat_speed"][:4000] > 75 * MPH
    assert np.mean(la_moved[fast]) > np.mean(la_plain[fast]) + 1.0
    # the population fit weighs the undercut as drawn, before the move
    from mcbat.stats.population.templates import _solve_memory

    p, _, _ = _solve_memory(plain, 2000, 9, ["undercut"], ["launch_angle"])
    q, _, _ = _solve_memory(moved, 2000, 9, ["undercut"], ["launch_angle"])
    np.testing.assert_array_equal(p["undercut"], q["undercut"])
