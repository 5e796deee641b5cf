"""`mcbat impact`: the JSON contract, and bad input -> exit 2 with one line naming the field."""

import copy
import json
import math
import subprocess
import sys

import pytest

from mcbat.api import ImpactCase, solve
from mcbat.cli import main
from tests.conftest import ROOT

EXAMPLE = ROOT / "examples" / "cabo2012_sec5.json"
GOOD = json.loads(EXAMPLE.read_text())


def run_cli(capsys, monkeypatch, payload, *args):
    """Run ``mcbat impact -`` in-process with ``payload`` on stdin."""
    text = payload if isinstance(payload, str) else json.dumps(payload)
    monkeypatch.setattr(sys, "stdin", __import__("io").StringIO(text))
    code = main(["impact", "-", *args])
    out, err = capsys.readouterr()
    return code, out, err


def test_example_file_end_to_end():
    proc = subprocess.run([sys.executable, "-m", "mcbat.cli", "impact", str(EXAMPLE)],
                          capture_output=True, text=True, check=False)
    assert proc.returncode == 0, proc.stderr
    result = json.loads(proc.stdout)
    assert result["status"] == "ok" and result["end_state"] == "stuck"
    assert round(result["exit_speed"], 3) == 1.446
    expected = solve(ImpactCase.from_dict(GOOD)).to_dict()
    assert result["ball_velocity"] == pytest.approx(expected["ball_velocity"], rel=1e-15)
    required = {"ball_velocity", "ball_spin", "bat_velocity", "bat_spin", "normal_impulse",
                "stick_impulse", "compression_impulse", "friction_work", "normal_work",
                "end_state", "energy_in", "energy_out", "status"}
    assert required <= set(result)


def test_array_in_same_order(capsys, monkeypatch):
    cases = []
    for w0 in (79.0, 0.0, -72.0):
        case = copy.deepcopy(GOOD)
        case["ball_spin"] = [0.0, 0.0, w0]
        cases.append(case)
    code, out, err = run_cli(capsys, monkeypatch, cases)
    assert code == 0 and err == ""
    results = json.loads(out)
    assert isinstance(results, list) and len(results) == 3
    for case, result in zip(cases, results):
        assert result["ball_spin"] == pytest.approx(
            solve(ImpactCase.from_dict(case)).to_dict()["ball_spin"], rel=1e-15)
    # Different spins give different outgoing spins: the order is really preserved.
    assert len({round(r["ball_spin"][2], 6) for r in results}) == 3


def test_tangential_restitution_in_json(capsys, monkeypatch):
    """restitution.e_x reaches the kernel: it reverses part of the slip, so the outgoing
    spin grows in magnitude (the ball sticks in the Sec. V case)."""
    spins = []
    for e_x in (None, 0.0, 0.16):
        case = copy.deepcopy(GOOD)
        if e_x is not None:
            case["restitution"] = {**case["restitution"], "e_x": e_x}
        code, out, err = run_cli(capsys, monkeypatch, case)
        assert code == 0, err
        spins.append(json.loads(out)["ball_spin"][2])
    assert spins[0] == spins[1]  # e_x = 0 is the default, the rigid model
    assert abs(spins[2]) > abs(spins[1])


def test_no_stick_gives_null_and_defaults(capsys, monkeypatch):
    case = copy.deepcopy(GOOD)
    case["mu"] = 0.0
    del case["restitution"], case["ball_spin"]
    code, out, _ = run_cli(capsys, monkeypatch, case)
    result = json.loads(out)
    assert code == 0
    assert result["stick_impulse"] is None and result["stick_criterion"] is None
    assert result["energy_out"] == pytest.approx(result["energy_in"], rel=1e-12)  # e* = 1


def _mutate(path, value):
    case = copy.deepcopy(GOOD)
    target = case
    for key in path[:-1]:
        target = target[key]
    if value is KeyError:
        del target[path[-1]]
    else:
        target[path[-1]] = value
    return case


BAD = [
    ("not json", "{nope", None, "not valid JSON"),
    ("empty array", [], None, "non-empty array"),
    ("case not object", [1], "case 0", "must be an object"),
    ("missing ball", _mutate(["ball"], KeyError), "ball", "missing required key"),
    ("missing mass", _mutate(["ball", "mass"], KeyError), "ball.mass", "missing"),
    ("missing mu", _mutate(["mu"], KeyError), "mu", "missing"),
    ("unknown key", dict(GOOD, colour="red"), "colour", "unknown key"),
    ("unknown nested key", _mutate(["bat", "length"], 0.84), "bat.length", "unknown key"),
    ("NaN literal", json.dumps(GOOD).replace('"mu": 0.5', '"mu": NaN'), None, "NaN"),
    ("infinite", json.dumps(GOOD).replace('"mu": 0.5', '"mu": 1e999'), "mu", "finite"),
    ("string number", _mutate(["ball", "radius"], "0.036"), "ball.radius", "number"),
    ("zero mass", _mutate(["ball", "mass"], 0.0), "ball.mass", "> 0"),
    ("negative bat mass", _mutate(["bat", "mass"], -1.0), "bat.mass", "> 0"),
    ("zero radius", _mutate(["bat", "radius"], 0.0), "bat.radius", "> 0"),
    ("negative inertia", _mutate(["bat", "axial_inertia"], -4e-4), "bat.axial_inertia", "> 0"),
    ("zero inertia factor", _mutate(["ball", "inertia_factor"], 0), "ball.inertia_factor",
     "> 0"),
    ("negative mu", _mutate(["mu"], -0.1), "mu", ">= 0"),
    ("e above 1", _mutate(["restitution"], {"e": 1.2}), "restitution.e", "<= 1"),
    ("e below 0", _mutate(["restitution"], {"e": -0.2}), "restitution.e", ">= 0"),
    ("loss fraction above 1", _mutate(["restitution"], {"loss_fraction": 2}),
     "restitution.loss_fraction", "<= 1"),
    ("e_x above 1", _mutate(["restitution"], {"e": 0.6, "e_x": 1.5}), "restitution.e_x",
     "<= 1"),
    ("short vector", _mutate(["ball_velocity"], [1.0, 2.0]), "ball_velocity", "3 numbers"),
    ("receding", _mutate(["ball_velocity"], [4.0, 0.0, 0.0]), "ball_velocity",
     "not approaching"),
    ("grazing", _mutate(["ball_velocity"], [0.0, 0.0, -4.0]), "ball_velocity",
     "not approaching"),
    ("ball misses", _mutate(["contact"], {"axial": 0.1, "impact_parameter": 0.5}),
     "contact.impact_parameter", "misses"),
]


@pytest.mark.parametrize("payload, field, words", [b[1:] for b in BAD],
                         ids=[b[0] for b in BAD])
def test_bad_input_one_line_exit_2(capsys, monkeypatch, payload, field, words):
    cases = payload if isinstance(payload, str) or payload == [] or payload == [1] \
        else [GOOD, payload]
    code, out, err = run_cli(capsys, monkeypatch, cases)
    assert code == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("mcbat: error: <stdin>")
    assert "Traceback" not in err
    assert words in lines[0]
    if field is not None:
        assert f" {field}:" in lines[0]
    if isinstance(payload, dict):
        assert "case 1:" in lines[0]  # the second case of the array is the bad one


def test_bad_input_subprocess_exit_code_and_no_traceback(tmp_path, cli):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(_mutate(["ball", "mass"], -1.0)))
    proc = subprocess.run([sys.executable, "-m", "mcbat.cli", "impact", str(bad)],
                          capture_output=True, text=True, check=False)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.strip() == f"mcbat: error: {bad}: case 0: ball.mass: must be > 0, got -1.0"
    missing = cli("impact", tmp_path / "nope.json")
    assert missing.returncode == 2 and "cannot read input" in missing.stderr
    assert "Traceback" not in missing.stderr and missing.stderr.count("\n") == 1


def test_impact_parameter_contact_matches_angle(capsys, monkeypatch):
    theta = 0.3
    b = (0.036 + 0.03335) * math.sin(theta)
    by_b = _mutate(["contact"], {"axial": 0.115, "impact_parameter": b})
    by_angle = _mutate(["contact"], {"axial": 0.115, "angle": theta})
    code, out, _ = run_cli(capsys, monkeypatch, [by_b, by_angle])
    assert code == 0
    r_b, r_a = json.loads(out)
    assert r_b["ball_velocity"] == pytest.approx(r_a["ball_velocity"], rel=1e-12)
    assert r_a["impact_parameter"] == pytest.approx(b, rel=1e-12)


# ---------------------------------------------------------------- --tolerance


def test_impact_tolerance_flag_reaches_the_kernel(capsys, monkeypatch):
    """``--tolerance`` is the kernel's: a tighter one takes more slip steps (the same as the
    API's at that tolerance) and moves the answer at most in its last digits (the default
    is good to a few 1e-9; on this case, whose slip direction is constant, not at all)."""
    from mcbat.api import SolverSettings

    code, out, err = run_cli(capsys, monkeypatch, GOOD)
    assert code == 0, err
    default = json.loads(out)
    code, out, err = run_cli(capsys, monkeypatch, GOOD, "--tolerance", "1e-11")
    assert code == 0 and err == "", err
    tight = json.loads(out)
    expected = solve(ImpactCase.from_dict(GOOD), SolverSettings(tolerance=1e-11)).to_dict()
    assert tight["ball_velocity"] == expected["ball_velocity"]
    assert tight["rk4_steps"] == expected["rk4_steps"] > default["rk4_steps"]
    speed = math.hypot(*default["ball_velocity"])
    for key in ("ball_velocity", "bat_velocity"):
        assert tight[key] == pytest.approx(default[key], rel=0, abs=1e-8 * speed), key
    assert tight["exit_speed"] == pytest.approx(default["exit_speed"], rel=1e-8)
    assert tight["ball_spin"] == pytest.approx(default["ball_spin"], rel=1e-8)


@pytest.mark.parametrize("value", ["0", "nan", "2", "-1e-9", "inf", "1"])
def test_impact_bad_tolerance_one_line_exit_2(capsys, monkeypatch, value):
    # (argparse reads "-1e-9" after a space as a flag: a negative value needs "=")
    code, out, err = run_cli(capsys, monkeypatch, GOOD, f"--tolerance={value}")
    if not value.startswith("-"):
        assert (code, out, err) == run_cli(capsys, monkeypatch, GOOD, "--tolerance", value)
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith("mcbat: error: --tolerance: must be"), err
    assert ("finite" if value in ("nan", "inf") else "> 0 and < 1") in lines[0]


# ---------------------------------------------------------------- game cases

# bare numbers of pitch and swing: the field's units (mph)
BASE = {"bat": {"preset": "r161"}, "mu": 0.5, "pitch": {"speed": 90}, "swing": {"bat_speed": 70}}


def _with(section, **values):
    case = json.loads(json.dumps(BASE))
    case.setdefault(section, {}).update(values)
    return case


@pytest.mark.parametrize("case,key", [
    (_with("swing", attack_angle={"value": 50, "unit": "deg"},
           vertical_bat_angle={"value": -45, "unit": "deg"}), "swing.vertical_bat_angle"),
    (_with("contact", undercut={"value": 3, "unit": "in"}), "contact.undercut"),
    (_with("contact", from_barrel_end={"value": 40, "unit": "in"}), "contact.from_barrel_end"),
    (_with("pitch", horizontal_approach_angle={"value": 120, "unit": "deg"}),
     "pitch.horizontal_approach_angle"),
    (_with("pitch", speed=-40), "pitch.speed"),
    (_with("pitch", speed=192), "pitch.speed"),             # 86 m/s written as mph
    (_with("swing", attack_angle=120), "swing.attack_angle"),
    (_with("pitch", release_speed=94), "pitch.speed"),      # both speeds
    (_with("pitch", extension=6.5), "pitch.extension"),     # without a release speed
])
def test_bad_game_case_exits_2_naming_the_key(case, key, cli):
    proc = cli("impact", "-", stdin=json.dumps(case))
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and f"case 0: {key}:" in lines[0]
    assert proc.stdout == ""


def test_game_case_and_bat_frame_case_in_one_file(tmp_path, cli):
    game = json.loads((ROOT / "examples" / "game_fastball.json").read_text())
    bat_frame = json.loads((ROOT / "examples" / "cabo2012_sec5.json").read_text())
    path = tmp_path / "cases.json"
    path.write_text(json.dumps([game, bat_frame]))
    proc = cli("impact", str(path))
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert 90 < out[0]["launch_speed"] < 120 and "exit_speed" in out[1]


def test_help_describes_both_kinds_of_case(capsys):
    """A bat-frame case is SI in the bat's frame; a game case has units and the field
    frame, and its batted ball comes out in Statcast's units."""
    with pytest.raises(SystemExit) as info:
        main(["impact", "--help"])
    assert info.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "lab frame" not in text
    assert "bat-frame case" in text and "bat's CM at the origin" in text
    assert "game case" in text and "field frame" in text and "launch_speed mph" in text
