"""mcbat.api.game: a game case in SI, its batted ball in Statcast's units, the front door."""

import json
import math

import pytest

import mcbat
from mcbat.api import GameCase, GameResult, solve_game
from mcbat.bodies import BALL_PRESETS, bat_preset
from mcbat.errors import InputError

# A 40 m/s (89.5 mph) fastball met by a 31 m/s (69.3 mph) swing 10 deg upwards: SI numbers.
SI = dict(pitch_speed=40.0, bat_speed=31.0, mu=0.5, vertical_approach_angle=-0.1,
          attack_angle=0.17, spin_rate=240.0, undercut=0.01)
# The same case in JSON: SI numbers with their units (a bare number of pitch and swing is
# in the field's units, mph, deg, rpm; the contact's in m).
JSON_CASE = {"bat": {"preset": "r161"}, "mu": 0.5,
             "pitch": {"speed": {"value": 40.0, "unit": "m/s"},
                       "vertical_approach_angle": {"value": -0.1, "unit": "rad"},
                       "spin_rate": {"value": 240.0, "unit": "rad/s"}},
             "swing": {"bat_speed": {"value": 31.0, "unit": "m/s"},
                       "attack_angle": {"value": 0.17, "unit": "rad"}},
             "contact": {"undercut": 0.01}}


def _case(**kw):
    return GameCase(ball=BALL_PRESETS["regulation"], bat=bat_preset("r161"), **{**SI, **kw})


def test_front_door_solves_a_game_as_object_dict_and_file(tmp_path):
    expected = solve_game(_case()).to_dict()
    path = tmp_path / "game.json"
    path.write_text(json.dumps(JSON_CASE))
    for given in (_case(), JSON_CASE, path):
        result = mcbat.solve(given)
        assert type(result) is GameResult
        assert result.to_dict() == expected


def test_the_batted_ball_is_in_statcast_units():
    result = solve_game(_case())
    vx, vy, vz = result.ball_velocity
    assert result.launch_speed == pytest.approx(math.sqrt(vx * vx + vy * vy + vz * vz)
                                                / 0.44704, rel=1e-12)
    assert result.launch_angle == pytest.approx(math.degrees(math.atan2(vz, math.hypot(vx, vy))),
                                                rel=1e-12)
    assert result.spin_rate == pytest.approx(math.sqrt(sum(w * w for w in result.ball_spin))
                                             * 60 / (2 * math.pi), rel=1e-12)


def test_every_game_quantity_has_its_unit_in_the_json_answer():
    d = solve_game(_case()).to_dict()
    units = d["units"]
    for key, value in d.items():
        if key in ("units", "bat_frame") or isinstance(value, str):
            continue
        assert key in units, key
    assert set(d["field"]) == set(units["field"])
    assert units["launch_speed"] == "mph" and units["launch_angle"] == "deg"
    assert units["backspin"] == "rpm" and units["field"]["ball_velocity"] == "m/s"
    assert set(units["bat_frame_case"]) == set(d["bat_frame_case"])
    assert "units" in d["bat_frame"]  # the bat-frame answer carries its own


@pytest.mark.parametrize("field, value, shown", [
    ("attack_angle", 10.0, "10 rad"),             # degrees by mistake
    ("vertical_approach_angle", -6.0, "-6 rad"),
    ("vertical_bat_angle", 2.0, "2 rad"),
    ("pitch_speed", -40.0, "-40"),
    ("bat_speed", -1.0, "-1"),
    ("spin_rate", -2.0, "-2"),
    ("spin_efficiency", 1.5, "1.5"),
    ("mu", -0.1, "-0.1"),
    ("gyro_sign", 2, "2"),
    ("undercut", 0.5, "0.5"),
])
def test_out_of_range_values_are_refused_naming_the_field_and_the_value(field, value, shown):
    with pytest.raises(InputError) as info:
        _case(**{field: value})
    assert info.value.field == field
    assert f"got {shown}" in info.value.message


@pytest.mark.parametrize("field, value", [("ball", "baseball"), ("bat", "r161"),
                                          ("restitution", 0.5)])
def test_bodies_of_the_wrong_type_are_refused_by_name(field, value):
    kw = dict(ball=BALL_PRESETS["baseball"], bat=bat_preset("r161"), **SI)
    kw[field] = value
    with pytest.raises(InputError) as info:
        GameCase(**kw)
    assert info.value.field == field and repr(value) in info.value.message


def test_a_json_case_error_names_the_json_key():
    bad = json.loads(json.dumps(JSON_CASE))
    bad["swing"]["attack_angle"] = {"value": 100, "unit": "deg"}
    with pytest.raises(InputError) as info:
        mcbat.solve(bad)
    assert info.value.field == "swing.attack_angle" and "100 deg" in info.value.message
