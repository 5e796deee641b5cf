"""``mcbat flight``: one ball or an array, units, the trajectory, and bad inputs (exit 2,
one line naming the key)."""

import json
import math
import subprocess
import sys

import pytest

from mcbat.api import flight_case_from_dict, solve_flight
from tests.conftest import ROOT

BALL = {"launch_speed": {"value": 103, "unit": "mph"},
        "launch_angle": {"value": 27, "unit": "deg"},
        "backspin": {"value": 2000, "unit": "rpm"}}


def _mcbat(*args, stdin=None):
    return subprocess.run([sys.executable, "-m", "mcbat", *args], input=stdin,
                          capture_output=True, text=True, cwd=ROOT)


def _strict(text):
    def refuse(name):
        raise ValueError(f"non-strict JSON constant {name}")
    return json.loads(text, parse_constant=refuse)


def test_one_ball_and_an_array_in_the_same_order(cli):
    one = cli("flight", "-", stdin=json.dumps(BALL))
    assert one.returncode == 0, one.stderr
    single = _strict(one.stdout)
    assert 380 < single["hit_distance"] < 440
    assert single["hit_distance_m"] == pytest.approx(single["hit_distance"] * 0.3048)
    slower = {**BALL, "launch_speed": {"value": 93, "unit": "mph"}}
    many = cli("flight", "-", stdin=json.dumps([slower, BALL]))
    assert many.returncode == 0, many.stderr
    results = _strict(many.stdout)
    assert results[1] == single and results[0]["hit_distance"] < single["hit_distance"]


def test_units_are_those_of_studies_and_a_bare_number_is_in_the_fields_unit():
    si = {"launch_speed": {"value": 103 * 0.44704, "unit": "m/s"},
          "launch_angle": {"value": 27 * math.pi / 180, "unit": "rad"},
          "backspin": {"value": 2000 * 2 * math.pi / 60, "unit": "rad/s"},
          "atmosphere": {"temperature": {"value": 294.26111111111111, "unit": "K"},
                         "pressure": {"value": 101320.75888, "unit": "Pa"},
                         "elevation": {"value": 0.0, "unit": "m"}}}
    written = {**BALL, "atmosphere": {"temperature": {"value": 70, "unit": "degF"},
                                      "pressure": {"value": 29.92, "unit": "inHg"},
                                      "elevation": {"value": 0, "unit": "ft"}}}
    bare = {"launch_speed": 103, "launch_angle": 27, "backspin": 2000,
            "atmosphere": {"temperature": 70, "pressure": 29.92, "elevation": 0}}
    a = solve_flight(flight_case_from_dict(si)).hit_distance
    b = solve_flight(flight_case_from_dict(written)).hit_distance
    assert a == pytest.approx(b, rel=1e-12)
    assert flight_case_from_dict(bare) == flight_case_from_dict(written)


def test_trajectory_samples_every_dt_to_the_landing(cli):
    proc = cli("flight", "--trajectory", "0.5", "-", stdin=json.dumps(BALL))
    assert proc.returncode == 0, proc.stderr
    out = _strict(proc.stdout)
    t = out["trajectory"]["t"]
    assert t[0] == 0.0 and t[1] == 0.5 and t[-1] == pytest.approx(out["hang_time"])
    assert out["trajectory"]["z"][-1] == 0.0
    assert max(out["trajectory"]["z"]) <= out["apex_m"] + 1e-9
    assert out["trajectory"]["z"][0] == pytest.approx(0.9144)  # (0, 2, 3) ft


@pytest.mark.parametrize("change,key", [
    ({"atmosphere": {"relative_humidity": -5}}, "atmosphere.relative_humidity"),
    ({"position": {"value": [0, 2, -1], "unit": "ft"}}, "position"),
    ({"model": "magic"}, "model"),
    ({"launch_speed": "fast"}, "launch_speed"),
    ({"spin_decay_time": -1}, "spin_decay_time"),
    ({"model": "constant"}, "drag"),
    ({"colour": "red"}, "colour"),
    ({"atmosphere": {"temperature": {"value": 70, "unit": "mph"}}},
     "atmosphere.temperature.unit"),
    ({"launch_speed": 300}, "launch_speed"),            # beyond 130 mph: another unit
    ({"atmosphere": {"temperature": 294}}, "atmosphere.temperature"),   # kelvins, bare
])
def test_bad_flight_inputs_exit_2_naming_the_key(change, key, cli):
    proc = cli("flight", "-", stdin=json.dumps({**BALL, **change}))
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and f"case 0: {key}:" in lines[0], lines
    assert proc.stdout == ""


def test_nan_and_a_bad_trajectory_step_exit_2(cli):
    # the real command, its stdin a pipe: exit status 2, one line, no traceback
    nan = _mcbat("flight", "-", stdin='{"launch_speed": NaN, "launch_angle": 0.3}')
    assert nan.returncode == 2 and len(nan.stderr.strip().splitlines()) == 1
    assert "Traceback" not in nan.stderr and nan.stdout == ""
    bad = cli("flight", "--trajectory", "0", "-", stdin=json.dumps(BALL))
    assert bad.returncode == 2 and "--trajectory" in bad.stderr



def test_landing_height_and_scales_in_a_case(tmp_path, capsys):
    # In this process (main), from files: a catch height ends the flight earlier and
    # shorter than the ground; a ball that never rises to it is refused naming the key.
    from mcbat.cli import main

    def run(case):
        path = tmp_path / "case.json"
        path.write_text(json.dumps(case))
        code = main(["flight", str(path)])
        out = capsys.readouterr()
        return code, (_strict(out.out) if code == 0 else None), out.err

    _, ground, _ = run(BALL)
    _, caught, _ = run({**BALL, "landing_height": {"value": 6, "unit": "ft"}})
    assert 0 < ground["hit_distance"] - caught["hit_distance"] < 10
    _, less_drag, _ = run({**BALL, "drag_scale": 0.9})
    assert less_drag["hit_distance"] > ground["hit_distance"]
    # launched 3 ft up nearly level: it never rises to a 6 ft catch height
    code, _, err = run({"launch_speed": 10, "launch_angle": 3, "landing_height": 6})
    assert code == 2 and "landing_height" in err and len(err.strip().splitlines()) == 1
    code, _, err = run({**BALL, "model": "constant", "drag": 0.3, "lift": 0.2,
                        "lift_scale": 1.1})
    assert code == 2 and "lift_scale" in err
