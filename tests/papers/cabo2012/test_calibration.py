"""Calibration of the restitution on the paper's one measured number, with a root finder."""

import json
import subprocess
import sys

import pytest

from mcbat.errors import InputError
from mcbat.papers.cabo2012 import sec5
from mcbat.papers.cabo2012.calibration import calibrate_restitution, exit_speed


def test_recovers_the_papers_loss_fraction():
    result = calibrate_restitution(1.44629)
    # docs/physics.md ("Accuracy of the printed numbers"): the paper's loose stick impulse
    # (4e-4) and its trial-and-error fit leave
    # the printed numbers good to 3-4 digits; e^2 = 0.6183822 is recovered to that.
    assert result.loss_fraction == pytest.approx(0.6183822, abs=5e-4)
    assert result.e_star == pytest.approx(sec5.e_star_paper(), abs=5e-4)
    assert result.exit_speed == pytest.approx(1.44629, abs=1e-10)
    assert result.iterations >= 2


def test_round_trip_to_root_finder_precision():
    speed = exit_speed(0.42)
    assert calibrate_restitution(speed).e_star == pytest.approx(0.42, abs=1e-10)


def test_exit_speed_has_one_rebound_branch():
    # e* = 0: the ball leaves with the bat's contact point; the speed then dips (the ball
    # nearly stops) before rising on the rebound branch, where the root is unique.
    assert exit_speed(0.1) < exit_speed(0.0)
    speeds = [exit_speed(e) for e in (0.3, 0.45, 0.6, 0.75, 0.9, 1.0)]
    assert speeds == sorted(speeds)


def test_unreachable_target_is_a_clear_error():
    with pytest.raises(InputError, match="target_speed"):
        calibrate_restitution(5.0)


def test_cli_prints_json():
    proc = subprocess.run([sys.executable, "-m", "mcbat.cli", "calibrate"],
                          capture_output=True, text=True, check=True)
    result = json.loads(proc.stdout)
    assert result["loss_fraction"] == pytest.approx(0.6183822, abs=5e-4)
