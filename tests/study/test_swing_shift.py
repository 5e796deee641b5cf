"""What if every swing were another (``[pitches.swing_shift]``, ``mcbat run
--swing-shift``): the same rows and random numbers, each swing moved by the amount."""

import math

import numpy as np
import pytest

from mcbat.cli import main
from mcbat.errors import InputError
from mcbat.study.spec import Study
from tests.study.test_swing_plane import _data, _rows, _study

MPH = 0.44704


def _shifted(tmp_path, shift, **pitches):
    base = _study(tmp_path, swing_plane=True, **pitches)
    moved = _study(tmp_path, swing_plane=True, swing_shift=shift, **pitches)
    return base, moved, base.sample(0, base.samples), moved.sample(0, moved.samples)


@pytest.mark.parametrize("error", [0.0, 2.0])
def test_a_bat_speed_shift_adds_to_every_swing_and_nothing_else(tmp_path, error):
    base, moved, a, b = _shifted(
        tmp_path, {"bat_speed": {"value": 2, "unit": "mph"}},
        swing_error={"bat_speed": {"value": error, "unit": "mph"}})
    np.testing.assert_allclose(b["bat_speed"], a["bat_speed"] + 2 * MPH, atol=1e-12)
    for name in a:
        if name != "bat_speed":
            np.testing.assert_array_equal(a[name], b[name], err_msg=name)
    assert moved.config()["pitches"]["swing_shift"] == {"swing.bat_speed": 2 * MPH}
    assert "swing_shift" not in base.config()["pitches"]
    assert moved.config_hash() != base.config_hash()


def test_the_launch_speed_follows_the_shifted_bat_speed(tmp_path):
    """Through the kernel: 2 mph more swing leaves the ball 1.6-2.6 mph faster at the
    median (the launch speed rises by about 1 + q per unit of bat speed, q ~ 0.1-0.2)."""
    from mcbat.stats.models.simulate import solve_game_inputs

    base, moved, _, _ = _shifted(tmp_path, {"bat_speed": {"value": 2, "unit": "mph"}})
    gain = []
    for study in (base, moved):
        out, ok = solve_game_inputs(study, study.sample_inputs(0, 4000, study.seed))
        gain.append(np.asarray(out["launch_speed"], float)[ok])
    change = np.median(gain[1]) - np.median(gain[0])
    assert 1.6 < change < 2.6


def test_an_attack_angle_shift_moves_the_planes_bat(tmp_path):
    _, moved, a, b = _shifted(tmp_path, {"attack_angle": {"value": -3, "unit": "deg"}})
    np.testing.assert_allclose(b["attack_angle"], a["attack_angle"] - math.radians(3),
                               atol=1e-12)
    j = moved.pitch_rows.draw_rows(moved.seed, 0, moved.samples)
    tilt = moved.pitch_rows.tilt[j]
    measured = np.isfinite(tilt)
    expected = -np.arcsin(np.sqrt(np.maximum(
        np.sin(tilt[measured]) ** 2 - np.sin(b["attack_angle"][measured]) ** 2, 0.0)))
    np.testing.assert_allclose(b["vertical_bat_angle"][measured], expected, atol=1e-12)
    assert np.any(b["vertical_bat_angle"][measured] != a["vertical_bat_angle"][measured])


def test_a_negative_shift_keeps_bat_speeds_at_or_above_zero(tmp_path):
    _, _, _, b = _shifted(tmp_path, {"bat_speed": {"value": -200, "unit": "mph"}})
    assert np.all(b["bat_speed"] == 0.0)


@pytest.mark.parametrize("pitches, field, match", [
    ({"swing_shift": {"bat_speed": {"value": 2, "unit": "mph"}}, "swing": False},
     "pitches.swing_shift", "only with pitches.swing = true"),
    ({"swing_shift": {"bat_speed": {"dist": "normal", "mean": 2, "std": 1, "unit": "mph"}}},
     "pitches.swing_shift.bat_speed", "must be a fixed value"),
    ({"swing_shift": {"pivot": {"value": 2, "unit": "in"}}}, "pitches.swing_shift.pivot",
     "unknown key"),
    ({"swing_shift": 2}, "pitches.swing_shift", "must be a table")])
def test_bad_shifts_name_the_key(tmp_path, pitches, field, match):
    path = tmp_path / "rows.csv"
    from mcbat.stats.population.table import write_pitches

    write_pitches(_rows(), path)
    with pytest.raises(InputError, match=match) as err:
        Study.from_dict(_data(path, **pitches))
    assert err.value.field == field


def test_the_flag_shifts_the_shipped_study(tmp_path, capsys):
    code = main(["run", "bat_tracking", "--swing-shift", "bat_speed=2", "--swing-shift",
                 "attack_angle=-3", "--samples", "500", "--out", str(tmp_path / "w"),
                 "--quiet"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "what if: every drawn swing moved by bat_speed +2.0 mph, attack_angle -3.0 deg" \
        in out
    for bad, words in (("bat_sped=2", "KEY one of"), ("bat_speed=fast", "a number of mph"),
                       ("bat_speed=nan", "finite")):
        code = main(["run", "bat_tracking", "--swing-shift", bad, "--out",
                     str(tmp_path / "x")])
        _, err = capsys.readouterr()
        assert code == 2 and "--swing-shift" in err and words in err
        assert len(err.strip().splitlines()) <= 2  # (the shipped-study note, the error)
    code = main(["run", "game_fastball", "--swing-shift", "bat_speed=2", "--out",
                 str(tmp_path / "x")])
    _, err = capsys.readouterr()
    assert code == 2 and "no [pitches]" in err
    assert not (tmp_path / "x").exists()
