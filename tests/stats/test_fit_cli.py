"""`mcbat fit`, `synth` and `calibrate`: every bad input exits 2 with one line naming the
option or column, and `--json` is strict JSON. The commands run in this process (the
``cli`` fixture); one test runs the real command."""

import json
import math
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[2]
STUDY = str(ROOT / "studies" / "cross_nathan_2006.toml")
DATA = ROOT / "data" / "synthetic_cross_nathan_60.csv"


def _table(tmp_path, name, change):
    df = pd.read_csv(DATA, comment="#")
    change(df)
    path = tmp_path / f"{name}.csv"
    df.to_csv(path, index=False)
    return str(path)


def _mph(df):
    df["exit_speed"] *= 2.23694
    df["exit_speed_err"] *= 2.23694


def _huge(df):
    df.loc[4, "exit_speed"] = 1e6


def _edge(df):
    df["impact_parameter"] = 0.036 + 0.03335  # the reach R + r_b: grazing


def _unusable_err(df):
    df["spin_in_err"] = 0.5
    del df["spin_in"]


BAD_FITS = {
    # name: (table change or None, extra flags, words in the one line)
    "speeds in mph": (_mph, [], ["exit_speed:", "wrong unit", "mph"]),
    "speed of 1e6": (_huge, [], ["exit_speed:", "row 5 (1e+06)"]),
    "every row at the reach": (_edge, [], ["impact_parameter:", "grazing"]),
    "study without impact parameter": (None, ["--study", str(ROOT / "studies" /
                                                            "throughput.toml")],
                                       ["impact_parameter:", "throughput", "contact.angle"]),
    "repeated free parameter": (None, ["--free", "e,e"], ["--free:", "'e' given twice"]),
    "unknown free parameter": (None, ["--free", "e,gravity"], ["--free:", "'gravity'"]),
    "empty free list": (None, ["--free", ","], ["--free:"]),
    "bootstrap 1": (None, ["--bootstrap", "1"], ["--bootstrap:", "got 1"]),
    "bootstrap -1": (None, ["--bootstrap", "-1"], ["--bootstrap:", "got -1"]),
    "residuals in a missing directory": (None, ["--residuals", "/nonexistent/dir/r.png"],
                                         ["--residuals:", "no such directory"]),
    "residuals of an unknown type": (None, ["--residuals", "r.txt"],
                                     ["--residuals:", "'.txt'"]),
    "draws 1": (None, ["--draws", "1"], ["--draws:", ">= 4"]),
    "err column without its value": (_unusable_err, [], ["spin_in_err:", "without its value"]),
}


class FitStarted(BaseException):
    """Raised by a fit that should never have started (not an ``Exception``: ``main``
    would turn that into exit 1; this one escapes and fails the test)."""


def _no_fit(*args, **kwargs):
    raise FitStarted("the fit started before the options were checked")


@pytest.mark.parametrize("name", BAD_FITS)
def test_bad_fit_input_exits_2_with_one_line(tmp_path, name, cli, monkeypatch):
    change, flags, words = BAD_FITS[name]
    data = _table(tmp_path, "m", change) if change else str(DATA)
    if flags and flags[0] != "--study":  # options are checked before any work
        monkeypatch.setattr("mcbat.stats.fit.estimate.fit", _no_fit)
    out = cli("fit", "--study", STUDY, "--data", data, "--no-compare", *flags, cwd=tmp_path)
    assert out.returncode == 2, out.stderr
    line = out.stderr.strip()
    assert "\n" not in line and "Traceback" not in line and line.startswith("mcbat: error:")
    for word in words:
        assert word in line, line
    assert out.stdout == ""
    assert not (tmp_path / "r.txt").exists()


def test_the_real_command_exits_2_with_one_line(tmp_path):
    """The installed entry point: exit status 2 from the process, one line, no traceback."""
    out = subprocess.run([sys.executable, "-m", "mcbat", "fit", "--study", STUDY, "--data",
                          str(DATA), "--bootstrap", "1"], capture_output=True, text=True,
                         check=False, cwd=tmp_path)
    assert out.returncode == 2, out.stderr
    assert out.stderr.strip().startswith("mcbat: error: --bootstrap:")
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
    assert out.stdout == "" and list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("flags, words", [
    (["--out", "/nonexistent/dir/m.csv"], ["--out:", "no such directory"]),
    (["--out", "m.xlsx"], ["--out:", "'.xlsx'"]),
    (["--rows", "0"], ["--rows:", ">= 1"]),
    (["--impact-parameter-noise", "-0.001"], ["--impact-parameter-noise:"]),
    (["--spin-in-noise", "nan"], ["--spin-in-noise:"]),
])
def test_bad_synth_input_exits_2_with_one_line(tmp_path, cli, flags, words):
    out = cli("synth", "--study", STUDY, *flags, cwd=tmp_path)
    assert out.returncode == 2, out.stderr
    line = out.stderr.strip()
    assert "\n" not in line and "Traceback" not in line
    for word in words:
        assert word in line, line
    assert out.stdout == "" and list(tmp_path.iterdir()) == []  # no table written


@pytest.mark.parametrize("target", ["nan", "inf", "-1"])
def test_bad_calibrate_target_exits_2(cli, target):
    out = cli("calibrate", "--target", target)
    assert out.returncode == 2 and "--target:" in out.stderr
    assert out.stderr.strip().count("\n") == 0


def _strict(text):
    def refuse(name):
        raise ValueError(f"non-finite {name} in JSON")
    return json.loads(text, parse_constant=refuse)


def test_json_is_strict_and_reports_a_one_sided_limit(cli, tmp_path):
    """The shipped table has mu = 0.5: every drop sticks, the data bound mu from below only.
    The old output wrote "stderr": Infinity here. With the default model comparison (its
    fit of the rigid model is the one ``--no-compare`` prints alone) and a residual plot."""
    out = cli("fit", "--study", STUDY, "--data", DATA, "--json", "--residuals",
              tmp_path / "r.png")
    assert out.returncode == 0, out.stderr
    result = _strict(out.stdout)
    assert set(result) >= {"params", "chi2", "dof", "p_value"}
    assert (tmp_path / "r.png").stat().st_size > 10_000
    comparison = result["model_comparison"]
    assert comparison["preferred"] in ("rigid", "compliant")
    assert set(comparison) >= {"delta_aic", "delta_bic", "likelihood_ratio", "lr_p_value"}
    assert "e_x" in comparison["compliant"]["params"]
    assert "e_x" not in comparison["rigid"]["params"]
    mu, e = result["params"]["mu"], result["params"]["e"]
    assert mu["status"] == "lower_limit" and mu["stderr"] is None
    assert mu["upper_error"] is None and 0.05 < mu["limit"] < 0.5
    assert e["status"] == "measured"
    assert e["lower_error"] > 0 and e["upper_error"] > 0 and math.isfinite(e["stderr"])
    assert abs(e["value"] - 0.6178) < 3 * max(e["lower_error"], e["upper_error"])
    assert result["unconstrained"] == ["mu"]


def test_synth_input_noise_round_trip(tmp_path, cli):
    path = tmp_path / "m.csv"
    out = cli("synth", "--study", STUDY, "--rows", "20", "--impact-parameter-noise",
                 "0.002", "--spin-in-noise", "2", "--out", str(path))
    assert out.returncode == 0, out.stderr
    df = pd.read_csv(path)
    assert (df["impact_parameter_err"] == 0.002).all() and (df["spin_in_err"] == 2).all()
