"""`mcbat impact`: the JSON contract, and bad input -> exit 2 with one line naming the field."""

import copy
import json
import math
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from mcbat.api import ImpactCase, solve
from mcbat.cli import main

ROOT = Path(__file__).resolve().parents[1]
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


def test_bad_input_subprocess_exit_code_and_no_traceback(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(_mutate(["ball", "mass"], -1.0)))
    proc = subprocess.run([sys.executable, "-m", "mcbat.cli", "impact", str(bad)],
                          capture_output=True, text=True, check=False)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.strip() == f"mcbat: error: {bad}: case 0: ball.mass: must be > 0, got -1.0"
    missing = subprocess.run([sys.executable, "-m", "mcbat.cli", "impact",
                              str(tmp_path / "nope.json")],
                             capture_output=True, text=True, check=False)
    assert missing.returncode == 2 and "cannot read input" in missing.stderr
    assert "Traceback" not in missing.stderr


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


def test_internal_error_exits_1_and_debug_shows_the_traceback(capsys, monkeypatch):
    import mcbat.api

    def broken(*args, **kwargs):
        raise RuntimeError("simulated bug")

    monkeypatch.setattr(mcbat.api, "solve", broken)
    code, out, err = run_cli(capsys, monkeypatch, GOOD)
    assert code == 1 and out == ""
    assert err.strip() == ("mcbat: internal error: RuntimeError: simulated bug "
                           "(run with --debug for a traceback)")
    monkeypatch.setattr(sys, "stdin", __import__("io").StringIO(json.dumps(GOOD)))
    code = main(["--debug", "impact", "-"])
    err = capsys.readouterr().err
    assert code == 1 and "Traceback" in err and "simulated bug" in err


def test_version_and_python_dash_m():
    import mcbat

    for command in ([sys.executable, "-m", "mcbat", "--version"],):
        proc = subprocess.run(command, capture_output=True, text=True, check=False)
        assert proc.returncode == 0 and proc.stdout.strip() == f"mcbat {mcbat.__version__}"
    proc = subprocess.run([sys.executable, "-m", "mcbat", "impact",
                           str(ROOT / "examples" / "cabo2012_sec5.json")],
                          capture_output=True, text=True, check=False)
    assert proc.returncode == 0 and json.loads(proc.stdout)["status"] == "ok"


def test_library_errors_name_parameters_and_the_cli_names_flags(tmp_path, capsys):
    from mcbat.errors import InputError
    from mcbat.runner import run_study
    from mcbat.study import load_study

    study = load_study(ROOT / "studies" / "example.toml")
    (tmp_path / "foreign.txt").write_text("not mcbat's")
    with pytest.raises(InputError) as info:
        run_study(study, tmp_path, samples=10, progress=False)
    assert info.value.field == "out"
    with pytest.raises(InputError) as info:
        run_study(study, tmp_path / "new", chunk_size=0, progress=False)
    assert info.value.field == "chunk_size"
    with pytest.raises(InputError) as info:
        run_study(study, tmp_path / "new", workers=2, progress=False)
    assert info.value.field == "workers" and "--" not in str(info.value)
    # The same errors through the command line name the flags.
    assert main(["run", str(ROOT / "studies" / "example.toml"), "--out", str(tmp_path / "n"),
                 "--chunk-size", "0", "--quiet"]) == 2
    assert "error: --chunk-size: must be an integer >= 1" in capsys.readouterr().err
    assert main(["run", str(ROOT / "studies" / "example.toml"), "--out", str(tmp_path / "n"),
                 "--workers", "2", "--quiet"]) == 2
    assert "error: --workers: only with --engine dask" in capsys.readouterr().err
    out = tmp_path / "other"
    assert main(["run", str(ROOT / "studies" / "example.toml"), "--out", str(out),
                 "--samples", "50", "--quiet"]) == 0
    capsys.readouterr()
    assert main(["run", str(ROOT / "studies" / "example.toml"), "--out", str(out),
                 "--samples", "60", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "--out: holds a dataset written with" in err and "pass --overwrite to" in err


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


def _with_solver_tolerance(tmp_path, tolerance):
    """studies/example.toml with ``[solver] tolerance`` written in."""
    path = tmp_path / f"example_{tolerance}.toml"
    text = (ROOT / "studies" / "example.toml").read_text()
    assert "solver" not in tomllib.loads(text)
    path.write_text(f"{text}\n[solver]\ntolerance = {tolerance}\n")
    return path


def test_run_tolerance_flag_is_the_studys_solver_tolerance(tmp_path, capsys):
    """``mcbat run --tolerance T`` writes the rows of the study with ``[solver] tolerance =
    T``, records T in the dataset's config, and is part of it: resuming with another
    tolerance (or none) is refused, with the same one it resumes."""
    import pandas as pd

    import mcbat

    study = str(ROOT / "studies" / "example.toml")
    common = ["--samples", "60", "--quiet"]
    flagged, in_toml, default = tmp_path / "flag", tmp_path / "toml", tmp_path / "default"
    assert main(["run", study, "--out", str(flagged), "--tolerance", "1e-11", *common]) == 0
    assert main(["run", str(_with_solver_tolerance(tmp_path, 1e-11)), "--out", str(in_toml),
                 *common]) == 0
    assert main(["run", study, "--out", str(default), *common]) == 0
    capsys.readouterr()

    manifest = json.loads((flagged / "_mcbat.json").read_text())
    assert manifest["study"]["solver"]["tolerance"] == 1e-11
    reference = json.loads((in_toml / "_mcbat.json").read_text())
    assert manifest["config_hash"] == reference["config_hash"]
    rows = mcbat.load(flagged)
    pd.testing.assert_frame_equal(rows, mcbat.load(in_toml))
    steps, default_steps = rows["rk4_steps"], mcbat.load(default)["rk4_steps"]
    assert (steps >= default_steps).all() and (steps > default_steps).any()  # T was used

    for again in (["--tolerance", "1e-10"], []):
        assert main(["run", study, "--out", str(flagged), *again, *common]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err
        assert "--out: holds a dataset written with a different study config" in err, err
    assert main(["run", study, "--out", str(flagged), "--tolerance", "1e-11", *common]) == 0
    assert "0 computed, 1 kept from before" in capsys.readouterr().out
    assert main(["run", study, "--out", str(tmp_path / "bad"), "--tolerance", "1", *common]) == 2
    assert "mcbat: error: --tolerance: must be > 0 and < 1, got 1.0" in capsys.readouterr().err
    assert not (tmp_path / "bad").exists()
