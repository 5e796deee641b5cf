"""mcbat.api.flight: a flight case in SI, the route from a game's batted ball, the front door."""

import json
import math
from pathlib import Path

import pytest

import mcbat
from mcbat.api import FlightCase, FlightResult, GameCase, flight_case_from_dict, solve_flight
from mcbat.bodies import BALL_PRESETS, Ball, bat_preset
from mcbat.errors import InputError
from mcbat.study import load_study
from mcbat.study.flight import FlightSettings

STUDIES = Path(__file__).resolve().parents[2] / "studies"

MPH, DEG, RPM = 0.44704, math.pi / 180.0, 2.0 * math.pi / 60.0
# The launch of docs/flight.md's sensitivities: 103 mph, 27 deg, 2000 rpm of backspin.
STATCAST = {"launch_speed": {"value": 103, "unit": "mph"},
            "launch_angle": {"value": 27, "unit": "deg"},
            "spray_angle": {"value": -10, "unit": "deg"},
            "backspin": {"value": 2000, "unit": "rpm"}}


def _si_case(**kw):
    return FlightCase(launch_speed=103 * MPH, launch_angle=27 * DEG, spray_angle=-10 * DEG,
                      backspin=2000 * RPM, **kw)


def test_front_door_flies_a_ball_as_object_dict_and_file(tmp_path):
    expected = solve_flight(_si_case())
    path = tmp_path / "flight.json"
    path.write_text(json.dumps(STATCAST))
    for given in (_si_case(), STATCAST, path):
        result = mcbat.solve(given)
        assert type(result) is FlightResult
        assert result.hit_distance == pytest.approx(expected.hit_distance, rel=1e-12)
        assert result.hang_time == pytest.approx(expected.hang_time, rel=1e-12)
    assert 400 < expected.hit_distance < 450  # ft: a long fly ball (docs/flight.md: 430.6)
    with pytest.raises(InputError) as info:
        mcbat.solve(_si_case(), settings=mcbat.SolverSettings())
    assert info.value.field == "settings"


def test_every_flight_quantity_has_its_unit_in_the_json_answer():
    d = solve_flight(_si_case(), trajectory=0.5).to_dict()
    units = d.pop("units")
    assert set(d) == set(units)
    assert units["hit_distance"] == "ft" and units["hit_distance_m"] == "m"
    assert units["trajectory"] == {"t": "s", "x": "m", "y": "m", "z": "m"}


def _game():
    case = GameCase(ball=Ball(mass=0.142, radius=0.0368), bat=bat_preset("r161"),
                    pitch_speed=40.0, bat_speed=31.0, mu=0.5, vertical_approach_angle=-0.1,
                    attack_angle=0.17, spin_rate=240.0, undercut=0.01)
    return mcbat.solve(case)


def test_the_flight_of_a_game_equals_the_flight_of_its_numbers_converted_by_hand():
    game = _game()
    settings = FlightSettings(elevation=1600 * 0.3048)
    by_hand = FlightCase(launch_speed=game.launch_speed * MPH,
                         launch_angle=math.radians(game.launch_angle),
                         spray_angle=math.radians(game.spray_angle),
                         backspin=game.backspin * RPM, sidespin=game.sidespin * RPM,
                         gyrospin=game.gyrospin * RPM, ball=game.case.ball, settings=settings)
    route = FlightCase.from_result(game, settings)
    assert route.ball == game.case.ball and route.settings == settings
    expected = solve_flight(by_hand).hit_distance
    assert solve_flight(route).hit_distance == pytest.approx(expected, rel=1e-12)
    # the mistake the route prevents: mph read as m/s
    wrong = FlightCase(launch_speed=game.launch_speed, launch_angle=by_hand.launch_angle,
                       ball=game.case.ball, settings=settings)
    assert solve_flight(wrong).hit_distance > 1.5 * expected
    # and the JSON route: the game's answer, as `mcbat impact` prints it
    answer = json.loads(json.dumps(game.to_dict()))
    assert flight_case_from_dict(answer) == FlightCase.from_result(game)
    assert mcbat.solve(answer).hit_distance == pytest.approx(
        solve_flight(FlightCase.from_result(game)).hit_distance, rel=1e-12)


def test_from_result_takes_only_a_game():
    with pytest.raises(InputError) as info:
        FlightCase.from_result(_game().impact)
    assert info.value.field == "result" and "ImpactResult" in info.value.message


@pytest.mark.parametrize("field, value, shown", [
    ("launch_angle", 27.0, "27 rad"),       # degrees by mistake
    ("launch_angle", -2.0, "-2 rad"),
    ("spray_angle", 200.0, "200 rad"),
    ("launch_speed", 0.0, "0 m/s"),
    ("launch_speed", -30.0, "-30 m/s"),
    ("backspin", math.nan, "nan"),
])
def test_out_of_range_values_are_refused_naming_the_field_and_the_value(field, value, shown):
    kw = {"launch_speed": 40.0, "launch_angle": 0.4, field: value}
    with pytest.raises(InputError) as info:
        FlightCase(**kw)
    assert info.value.field == field
    assert f"got {shown}" in info.value.message


def test_a_flight_case_takes_a_ball_and_flight_settings():
    with pytest.raises(InputError) as info:
        FlightCase(launch_speed=40.0, launch_angle=0.4, ball="baseball")
    assert info.value.field == "ball"
    assert FlightCase(launch_speed=40.0, launch_angle=0.4).ball == BALL_PRESETS["regulation"]


def test_the_flight_tolerance_travels_in_the_one_solver_settings(tmp_path):
    # A flight case's and a game study's [flight] tolerance is the flight_tolerance of a
    # SolverSettings, which is what reaches the integrator; a tighter one moves the answer.
    loose = flight_case_from_dict({"launch_speed": 103, "launch_angle": 27,
                                   "backspin": 2000, "tolerance": 1e-3})
    tight = flight_case_from_dict({"launch_speed": 103, "launch_angle": 27,
                                   "backspin": 2000, "tolerance": 1e-9})
    assert isinstance(tight.settings.solver, mcbat.SolverSettings)
    assert tight.settings.solver.flight_tolerance == 1e-9
    assert tight.settings.params(0.145, 0.036).tolerance == 1e-9
    assert solve_flight(loose).hit_distance != solve_flight(tight).hit_distance
    with pytest.raises(InputError) as info:
        flight_case_from_dict({"launch_speed": 103, "launch_angle": 27, "tolerance": 0.5})
    assert info.value.field == "tolerance"
    text = (STUDIES / "game_fastball.toml").read_text()
    assert "\n[flight]\n" in text
    study = tmp_path / "s.toml"
    study.write_text(text.replace("\n[flight]\n", "\n[flight]\ntolerance = 1e-7\n"))
    settings = load_study(study).solver_settings
    assert settings.flight_tolerance == 1e-7
    shipped = load_study(STUDIES / "game_fastball.toml").solver_settings
    assert settings.tolerance == shipped.tolerance
    assert shipped.flight_tolerance == FlightSettings().tolerance
