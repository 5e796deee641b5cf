"""Bare numbers in a game or flight case are in the field's units (mph, deg, rpm, ft,
degF, inHg), one table and one function (mcbat.api.contract.FIELD_KEYS, field_spec); a
bare number outside its key's plausible range is refused naming the key, the unit and
the range. A bat-frame case stays SI."""

import json
import math

import pytest

import mcbat
from mcbat.api import case_from_dict, flight_case_from_dict, solve_any, solve_flight
from mcbat.api.contract import FIELD_KEYS, GAME_UNITS, field_spec, field_value
from mcbat.api.flight import FlightCase
from mcbat.errors import InputError
from mcbat.study.flight import FLIGHT_KEYS
from mcbat.study.game import KEYS as GAME_KEYS
from mcbat.study.units import to_si
from tests.conftest import ROOT

MPH, DEG, RPM, FT = 0.44704, math.pi / 180, math.pi / 30, 0.3048

GAME = {"bat": {"preset": "r161"}, "mu": 0.5,
        "pitch": {"speed": 86, "vertical_approach_angle": -6, "spin_rate": 2300,
                  "spin_axis": 210},
        "swing": {"bat_speed": 72, "attack_angle": 10, "vertical_bat_angle": -30},
        "contact": {"undercut": {"value": 0.5, "unit": "in"}}}


def _with_units(case):
    """The game case with every field number written as {value, unit}."""
    out = json.loads(json.dumps(case))
    for section in ("pitch", "swing"):
        for key, value in out[section].items():
            if not isinstance(value, dict):
                out[section][key] = {"value": value, "unit": FIELD_KEYS[f"{section}.{key}"][0]}
    return out


def test_a_bare_flight_number_is_in_the_fields_unit():
    # the four inputs that were read as SI: now the field's units, or refused
    speed_only = flight_case_from_dict({"launch_speed": 103,
                                        "launch_angle": {"value": 27, "unit": "deg"}})
    assert speed_only.launch_speed == pytest.approx(103 * MPH, rel=1e-15)
    ball = flight_case_from_dict({"launch_speed": 103, "launch_angle": 27, "backspin": 2000})
    assert ball.backspin == pytest.approx(2000 * RPM, rel=1e-15)
    assert ball.launch_angle == pytest.approx(27 * DEG, rel=1e-15)
    landing = solve_flight(ball).hit_distance
    assert 330 < landing < 480                      # ft; 103 m/s flew 873 ft
    assert mcbat.solve({"launch_speed": 103, "launch_angle": 27,
                        "backspin": 2000}).hit_distance == landing


def test_a_bare_game_number_is_in_the_fields_unit():
    bare = solve_any(case_from_dict(GAME))
    written = solve_any(case_from_dict(_with_units(GAME)))
    assert bare.to_dict() == written.to_dict()
    speed = math.hypot(*bare.pitch_velocity)
    assert speed == pytest.approx(86 * MPH, rel=1e-12)   # not 86 m/s (192 mph)
    assert 80 < bare.launch_speed < 120


@pytest.mark.parametrize("data, key, unit", [
    ({"launch_speed": 300, "launch_angle": 27}, "launch_speed", "mph"),
    ({"launch_speed": 100, "launch_angle": 95}, "launch_angle", "deg"),
    ({"launch_speed": 100, "launch_angle": 20, "backspin": 20000}, "backspin", "rpm"),
    ({"launch_speed": 100, "launch_angle": 20, "position": [0, 2, 300]}, "position", "ft"),
    ({"launch_speed": 100, "launch_angle": 20, "atmosphere": {"temperature": 294}},
     "atmosphere.temperature", "degF"),
    ({"launch_speed": 100, "launch_angle": 20, "atmosphere": {"pressure": 101325}},
     "atmosphere.pressure", "inHg"),
])
def test_a_bare_flight_number_out_of_its_range_is_refused(data, key, unit):
    with pytest.raises(InputError) as info:
        flight_case_from_dict(data)
    low, high = FIELD_KEYS[key][2]
    assert info.value.field == key
    assert f"in {unit}" in info.value.message and f"[{low:g}, {high:g}] {unit}" in \
        info.value.message


def test_a_bare_game_number_out_of_its_range_is_refused():
    case = json.loads(json.dumps(GAME))
    case["pitch"]["speed"] = 192
    with pytest.raises(InputError) as info:
        case_from_dict(case)
    assert info.value.field == "pitch.speed"
    assert "192 mph" in info.value.message and "[25, 110] mph" in info.value.message


def test_stated_units_are_not_range_checked_as_bare_numbers():
    """A unit written out is the user's word: the physical checks alone apply."""
    fast = flight_case_from_dict({"launch_speed": {"value": 140, "unit": "mph"},
                                  "launch_angle": 20})
    assert fast.launch_speed == pytest.approx(140 * MPH)
    block = flight_case_from_dict({"launch_speed": 140, "launch_angle": 20,
                                   "units": {"launch_speed": "mph"}})
    assert block == fast


def test_vectors_and_the_air_in_field_units():
    case = flight_case_from_dict({"launch_speed": 100, "launch_angle": 25,
                                  "position": [0, 2, 3], "wind": [0, 10, 0],
                                  "landing_height": 6,
                                  "atmosphere": {"temperature": 70, "pressure": 29.92,
                                                 "elevation": 5200}})
    s = case.settings
    assert s.start == pytest.approx((0.0, 2 * FT, 3 * FT), rel=1e-15)
    assert s.wind == pytest.approx((0.0, 10 * MPH, 0.0), rel=1e-15)
    assert s.landing_height == pytest.approx(6 * FT, rel=1e-15)
    assert s.elevation == pytest.approx(5200 * FT, rel=1e-15)
    assert s.temperature == pytest.approx((70 - 32) * 5 / 9 + 273.15, rel=1e-15)
    assert s.pressure == pytest.approx(29.92 * 3386.389, rel=1e-15)


def test_the_table_names_real_keys_in_the_units_of_the_answers():
    pitch = set(GAME_KEYS["pitch"]) | {"release_speed", "extension"}
    flight = {"launch_speed", "launch_angle", "spray_angle", "backspin", "sidespin",
              "gyrospin", *FLIGHT_KEYS, "atmosphere.temperature", "atmosphere.pressure",
              "atmosphere.elevation"}
    for key in FIELD_KEYS:
        section, _, name = key.rpartition(".")
        assert (section == "pitch" and name in pitch) or \
            (section == "swing" and name in GAME_KEYS["swing"]) or key in flight, key
    for key in ("launch_speed", "launch_angle", "spray_angle", "backspin", "sidespin",
                "gyrospin"):  # what a game's answer says its numbers are in
        assert FIELD_KEYS[key][0] == GAME_UNITS[key]
    for key, (unit, quantity, (low, high)) in FIELD_KEYS.items():
        assert low < high and field_spec(high, key) == {"value": high, "unit": unit}
        assert field_value((low + high) / 2, key) == pytest.approx(
            to_si((low + high) / 2, unit, quantity))


def test_a_bat_frame_case_stays_si():
    case = case_from_dict(json.loads((ROOT / "examples" / "cabo2012_sec5.json").read_text()))
    assert case.ball_velocity == (-4.0, 0.0, 0.0)     # m/s, not mph


def test_from_result_reads_the_answers_units():
    game = solve_any(case_from_dict(GAME))
    case = FlightCase.from_result(game)
    assert case.launch_speed == pytest.approx(game.launch_speed * MPH, rel=1e-15)
    assert case == flight_case_from_dict(json.loads(json.dumps(game.to_dict())))


def test_an_integer_beyond_any_float_is_refused_naming_its_key():
    from mcbat.api.contract import field_spec
    from mcbat.errors import InputError

    with pytest.raises(InputError) as err:
        field_spec(10 ** 400, "pitch.vertical_approach_angle")
    assert err.value.field == "pitch.vertical_approach_angle"
    assert "401 digits" in err.value.message
