"""mcbat calibrate for any study and target: the paper's Sec. V calibration is
one case of it."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from mcbat.errors import InputError
from mcbat.papers.cabo2012 import sec5
from mcbat.papers.cabo2012.calibration import calibrate_restitution
from mcbat.stats.fit.calibrate import calibrate
from mcbat.stats.measurements import synthesize
from mcbat.study import load_study

ROOT = Path(__file__).resolve().parents[2]
SEC5 = """
[study]
name = "sec5_calibration"
samples = 1
seed = 1
[ball]
preset = "baseball"
[bat]
preset = "cross_nathan_2006"
[contact]
from_barrel_end = { value = 15, unit = "cm" }
angle = { value = 0.45, unit = "deg" }      # pi/400
[ball_velocity]
x = -4.0
[friction]
mu = 0.5
"""


def test_sec5_calibration_is_a_special_case(tmp_path):
    path = tmp_path / "sec5.toml"
    path.write_text(SEC5)
    result = calibrate(load_study(path), "exit_speed", sec5.TARGET_SPEED)
    paper = calibrate_restitution()
    assert result.value == pytest.approx(paper.e_star, abs=1e-8)
    assert result.achieved == pytest.approx(sec5.TARGET_SPEED, rel=1e-9)


def test_game_calibration_hits_its_target_and_round_trips():
    study = load_study(ROOT / "studies" / "game_fastball.toml")
    result = calibrate(study, "launch_speed", 95.0, samples=2000)
    assert result.unit == "mph" and abs(result.achieved - 95.0) < 1e-6
    # The mean of a synthetic table made at the calibrated e* is 95 mph up to its noise.
    table = synthesize(study, 2000, seed=study.seed, e=result.value, speed_noise=0.0)
    assert table["launch_speed"].mean() == pytest.approx(95.0, abs=1e-6)


@pytest.mark.parametrize("kwargs, field", [
    ({"column": "exit_speed", "target": 100.0}, "column"),
    ({"column": "launch_speed", "target": 400.0}, "target"),
    ({"column": "launch_speed", "target": 95.0, "parameter": "axial"}, "parameter"),
    ({"column": "launch_speed", "target": 95.0, "samples": 0}, "samples"),
])
def test_bad_calibration_names_its_field(kwargs, field):
    study = load_study(ROOT / "studies" / "game_fastball.toml")
    with pytest.raises(InputError) as err:
        calibrate(study, **kwargs)
    assert err.value.field == field


def test_calibrate_cli_with_a_study():
    out = subprocess.run([sys.executable, "-m", "mcbat", "calibrate", "--study",
                          str(ROOT / "studies" / "game_fastball.toml"), "--column",
                          "launch_speed", "--target", "95", "--samples", "500"],
                         capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    assert result["parameter"] == "e" and abs(result["achieved"] - 95.0) < 1e-6
    bad = subprocess.run([sys.executable, "-m", "mcbat", "calibrate", "--study",
                          str(ROOT / "studies" / "game_fastball.toml"), "--column",
                          "exit_speed", "--target", "95"],
                         capture_output=True, text=True, check=False)
    assert bad.returncode == 2 and "--column" in bad.stderr and bad.stderr.count("\n") == 1
