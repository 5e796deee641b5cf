"""Every number a command accepts is checked for range and finiteness before use: a
value out of range is exit 2 with one line naming it, and a successful answer holds
numbers, never null, NaN or inf."""

import json
import math
from pathlib import Path

import pytest

from mcbat.cli import main

ROOT = Path(__file__).resolve().parents[1]
DROP = ROOT / "studies" / "cross_nathan_2006.toml"
GAME = ROOT / "studies" / "game_fastball.toml"
EXAMPLE = ROOT / "studies" / "example.toml"
BIG_SEED = str(2**64)


def _one_error(capsys, code, *words):
    out, err = capsys.readouterr()
    assert code == 2, err
    line, = err.strip().splitlines()
    assert "Traceback" not in err and all(word in line for word in words), line
    return out


@pytest.mark.parametrize("argv", [
    ["run", str(EXAMPLE), "--samples", "10", "--quiet"],
    ["synth", "--study", str(DROP), "--rows", "3"],
    ["fit", "--study", str(DROP), "--data", str(ROOT / "data" / "synthetic_cross_nathan_60.csv"),
     "--intervals", "curvature", "--no-compare"],
], ids=["run", "synth", "fit"])
def test_a_seed_beyond_64_bits_is_refused(capsys, tmp_path, monkeypatch, argv):
    monkeypatch.chdir(tmp_path)
    _one_error(capsys, main([*argv, "--seed", BIG_SEED]), "--seed")
    assert not (tmp_path / "results").exists()


@pytest.mark.parametrize("column,table", [
    ("scattering_angle", "drop"), ("spin_out", "drop"), ("spray_angle", "game")])
def test_a_huge_measured_value_is_refused(capsys, tmp_path, column, table):
    if table == "drop":
        header = "impact_parameter,spin_in,exit_speed,scattering_angle,spin_out"
        row = {"impact_parameter": 0.01, "spin_in": 79, "exit_speed": 1.4,
               "scattering_angle": 5, "spin_out": 30}
        study = DROP
    else:
        header = "launch_speed,launch_angle,spray_angle"
        row = {"launch_speed": 95, "launch_angle": 20, "spray_angle": 3}
        study = GAME
    lines = [header]
    for i in range(6):
        values = dict(row, **({column: 1e20} if i == 3 else {}))
        lines.append(",".join(str(values[c]) for c in header.split(",")))
    data = tmp_path / "m.csv"
    data.write_text("\n".join(lines) + "\n")
    code = main(["fit", "--study", str(study), "--data", str(data), "--free", "e",
                 "--intervals", "curvature", "--no-compare"])
    _one_error(capsys, code, column, "row 4")


@pytest.mark.parametrize("flag,value", [
    ("--speed-noise", "inf"), ("--angle-noise", "inf"), ("--spin-noise", "inf"),
    ("--spin-in-noise", "inf"), ("--speed-noise", "1e300"), ("--mu", "1e10"),
    ("--mu", "nan")])
def test_synth_refuses_numbers_that_would_write_inf_nan_or_no_rows(capsys, flag, value):
    code = main(["synth", "--study", str(DROP), "--rows", "5", flag, value])
    _one_error(capsys, code, flag)


def test_synth_rows_are_bounded(capsys):
    _one_error(capsys, main(["synth", "--study", str(DROP), "--rows", str(10**12)]), "--rows")


@pytest.mark.parametrize("case", [
    {"launch_speed": 45, "launch_angle": 0.5, "ball": {"mass": 1e-9, "radius": 0.037}},
    {"launch_speed": {"value": 2e10, "unit": "mph"}, "launch_angle": 0.5},
], ids=["feather", "2e10 mph"])
def test_a_flight_the_model_cannot_carry_is_an_error_not_null(capsys, tmp_path, case):
    path = tmp_path / "f.json"
    path.write_text(json.dumps(case))
    _one_error(capsys, main(["flight", str(path)]), "launch_speed")


def test_a_trajectory_beyond_its_point_limit_is_an_error(capsys, tmp_path):
    path = tmp_path / "f.json"
    path.write_text(json.dumps({"launch_speed": 45, "launch_angle": 0.5}))
    _one_error(capsys, main(["flight", str(path), "--trajectory", "1e-6"]), "--trajectory",
               "100,000")
    # within the limit, the samples reach the landing
    assert main(["flight", str(path), "--trajectory", "1e-4"]) == 0
    answer = json.loads(capsys.readouterr().out)
    t = answer["trajectory"]["t"]
    assert t[-1] == answer["hang_time"] and len(t) == math.ceil(answer["hang_time"] / 1e-4) + 1


@pytest.mark.parametrize("token", ["\x85", "\u2028", "a\nb"])
def test_an_error_that_echoes_a_line_break_stays_one_line(capsys, token):
    code = main(["calibrate", token, "1e20"])
    _, err = capsys.readouterr()
    assert code == 2 and len(err.splitlines()) == 1, repr(err)
