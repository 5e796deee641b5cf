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
    {"launch_speed": 45, "launch_angle": 0.5, "ball": {"mass": 0.145, "radius": 36_600}},
], ids=["feather", "2e10 mph", "36.6 km radius"])
def test_a_flight_the_model_cannot_carry_is_an_error_not_null(capsys, tmp_path, case):
    path = tmp_path / "f.json"
    path.write_text(json.dumps(case))
    _one_error(capsys, main(["flight", str(path)]), "launch_speed", "ball.radius",
               "outside the range the model is made for")


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


EXAMPLES = {name: json.loads((ROOT / "examples" / name).read_text())
            for name in ("cabo2012_sec5.json", "game_fastball.json")}
#: The keys an impact answer documents as null: a contact that never stuck.
NULL_OK = {"stick_impulse", "stick_criterion"}


def _numeric_fields(tree, prefix=()):
    """Paths to every number of a case (a vector's components, a quantity's value)."""
    items = tree.items() if isinstance(tree, dict) else enumerate(tree)
    out = []
    for key, value in items:
        if isinstance(value, bool):
            continue
        if isinstance(value, int | float):
            out.append((*prefix, key))
        elif isinstance(value, dict | list):
            out.extend(_numeric_fields(value, (*prefix, key)))
    return out


def _with(case, path, value):
    case = json.loads(json.dumps(case))
    parent = case
    for key in path[:-1]:
        parent = parent[key]
    parent[path[-1]] = value
    return case


def _field_name(path):
    """The dotted key an error names (a vector by its name, a quantity without .value)."""
    keys = [str(k) for k in path if not isinstance(k, int) and k != "value"]
    return ".".join(keys)


IMPACT_FIELDS = [(name, path) for name, case in EXAMPLES.items()
                 for path in _numeric_fields(case)]


def _nulls(value, key=None):
    if value is None:
        return [] if key in NULL_OK else [key]
    if isinstance(value, dict):
        return [n for k, v in value.items() for n in _nulls(v, k)]
    if isinstance(value, list):
        return [n for v in value for n in _nulls(v, key)]
    return []


def _strict(text):
    def refuse(name):
        raise AssertionError(f"non-finite number {name} in the answer")
    return json.loads(text, parse_constant=refuse)


@pytest.mark.parametrize("example,path", IMPACT_FIELDS,
                         ids=[f"{n.split('_')[0]}-{_field_name(p)}"
                              f"{''.join(f'[{k}]' for k in p if isinstance(k, int))}"
                              for n, p in IMPACT_FIELDS])
def test_every_number_of_an_impact_case_at_the_extremes(capsys, tmp_path, example, path):
    """1e300, -1e300 and the infinities (1e400 in JSON) in each number of the shipped impact
    examples: an answer of finite numbers (exit 0), or exit 2 with one line naming the
    field; never exit 1, a traceback, NaN/inf or null in the answer."""
    for value in (1e300, -1e300, "INF", "-INF"):
        text = json.dumps(_with(EXAMPLES[example], path, 0.0 if isinstance(value, str)
                                else value))
        if isinstance(value, str):  # JSON has no infinity: 1e400 parses to it
            text = _replace_number(text, path, "1e400" if value == "INF" else "-1e400",
                                   EXAMPLES[example])
        source = tmp_path / "case.json"
        source.write_text(text)
        code = main(["impact", str(source)])
        out, err = capsys.readouterr()
        assert code in (0, 2), (value, err)
        if code == 2:
            line, = err.strip().splitlines()
            assert _field_name(path) in line, (value, line)
        else:
            answer = _strict(out)
            assert not _nulls(answer), (value, _nulls(answer))


def _replace_number(text, path, literal, case):
    """``text`` (a case with 0.0 at ``path``) with that 0.0 spelled as ``literal``."""
    marker = 12345.678901234
    marked = json.dumps(_with(case, path, marker))
    assert marked.count(repr(marker)) == 1
    return marked.replace(repr(marker), literal)


@pytest.mark.parametrize("example,path", IMPACT_FIELDS,
                         ids=[f"{n.split('_')[0]}-{_field_name(p)}"
                              f"{''.join(f'[{k}]' for k in p if isinstance(k, int))}"
                              for n, p in IMPACT_FIELDS])
def test_a_nan_in_any_number_of_an_impact_case_is_refused_by_name(example, path):
    """The Python API takes NaN (JSON cannot carry it): refused, naming the field."""
    from mcbat.api import case_from_dict, solve_any
    from mcbat.errors import InputError

    for value in (math.nan, math.inf, -math.inf):
        with pytest.raises(InputError) as raised:
            solve_any(case_from_dict(_with(EXAMPLES[example], path, value)), json_keys=True)
        assert _field_name(path) in str(raised.value), str(raised.value)
