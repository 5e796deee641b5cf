"""The vertical bat angle from the measured swing plane (``[pitches] swing_plane``)."""

import math

import numpy as np
import pandas as pd
import pytest

from mcbat.core.swing.frames import BatBody, Swing, swing_state
from mcbat.errors import InputError
from mcbat.runner.pitches import load_pitches
from mcbat.stats.population.table import write_pitches
from mcbat.study.spec import Study
from mcbat.study.swing_plane import vertical_bat_angle

FALLBACK_DEG = -25.0


@pytest.mark.parametrize("hand", [1.0, -1.0])
@pytest.mark.parametrize("tilt, attack, direction", [
    (31.0, 9.0, 0.0), (45.0, -10.0, 15.0), (20.0, 19.0, -30.0), (60.0, 0.0, 5.0),
    (12.0, 25.0, 0.0)])
def test_the_kernels_bat_and_swing_span_a_plane_of_the_measured_tilt(tilt, attack,
                                                                     direction, hand):
    """The model's bat axis and sweet-spot velocity, built from the derived angle, span a
    plane whose angle with the ground is the tilt (level bat where no bat can do it)."""
    a = math.radians(attack)
    b = float(vertical_bat_angle(math.radians(tilt), a))
    assert b <= 0.0
    ok, n, _, w = swing_state(Swing(hand, 30.0, a, math.radians(direction), b, 0.15),
                              BatBody(0.84, 0.56))
    assert ok
    normal = np.asarray(w) / np.linalg.norm(w)  # W ~ n x u: the plane's normal
    got = math.degrees(math.acos(abs(normal[2])))
    if abs(attack) <= tilt:
        assert got == pytest.approx(tilt, abs=1e-9)
        assert math.degrees(math.asin(-n[2])) == pytest.approx(-math.degrees(b), abs=1e-9)
    else:  # (steeper than its plane: the level bat, whose plane tilts by the attack angle)
        assert b == 0.0
        assert got == pytest.approx(abs(attack), abs=1e-9)


def test_nan_tilt_gives_nan():
    out = vertical_bat_angle(np.array([np.nan, 0.5]), np.array([0.1, 0.1]))
    assert np.isnan(out[0]) and np.isfinite(out[1])


def _rows(n=300, seed=4):
    rng = np.random.default_rng(seed)
    tilt = rng.normal(31.0, 7.0, n)
    tilt[::5] = np.nan  # a fifth of the rows without a measured plane
    return pd.DataFrame({
        "pitch_speed": rng.normal(85.0, 4.0, n), "vertical_approach_angle": -6.0,
        "horizontal_approach_angle": 0.0, "spin_rate": 2200.0, "spin_axis": 200.0,
        "bat_speed": rng.normal(70.0, 5.0, n), "attack_angle": rng.normal(9.0, 8.0, n),
        "attack_direction": rng.normal(0.0, 12.0, n), "swing_path_tilt": tilt,
        "handedness": "R", "launch_speed": 90.0, "launch_angle": 10.0})


def _data(path, **pitches):
    return {"study": {"name": "t", "samples": 6000, "seed": 5},
            "ball": {"preset": "baseball"}, "bat": {"preset": "r161"},
            "pitches": {"file": str(path), "swing": True, **pitches},
            "pitch": {"spin_efficiency": 0.9},
            "swing": {"vertical_bat_angle": {"value": FALLBACK_DEG, "unit": "deg"}},
            "contact": {"from_barrel_end": {"value": 6, "unit": "in"}, "undercut": 0.0},
            "friction": {"mu": 0.5}}


def _study(tmp_path, rows=None, **pitches):
    path = tmp_path / "rows.csv"
    write_pitches(_rows() if rows is None else rows, path)
    return load_pitches(Study.from_dict(_data(path, **pitches)))


@pytest.mark.parametrize("error", [0.0, 5.0])
def test_each_row_with_a_tilt_gets_its_planes_bat(tmp_path, error):
    """With or without the attack angle's error, the bat follows the row's tilt and the
    sample's (true) attack angle; rows without a tilt keep the [swing] value."""
    study = _study(tmp_path, swing_plane=True,
                   swing_error={"attack_angle": {"value": error, "unit": "deg"}})
    cols = study.sample(0, study.samples)
    j = study.pitch_rows.draw_rows(study.seed, 0, study.samples)
    tilt = study.pitch_rows.tilt[j]
    measured = np.isfinite(tilt)
    assert 0.7 < measured.mean() < 0.9
    expected = -np.arcsin(np.sqrt(np.maximum(
        np.sin(tilt[measured]) ** 2 - np.sin(cols["attack_angle"][measured]) ** 2, 0.0)))
    np.testing.assert_allclose(cols["vertical_bat_angle"][measured], expected, atol=1e-12)
    np.testing.assert_allclose(cols["vertical_bat_angle"][~measured],
                               math.radians(FALLBACK_DEG), atol=1e-12)
    # the planes' bats spread as the tilts do: this is no constant
    assert np.degrees(cols["vertical_bat_angle"][measured]).std() > 4.0
    assert study.config()["pitches"]["swing_plane"] is True
    assert study.config()["pitches"]["swing_plane_measured"] == int(
        np.isfinite(study.pitch_rows.tilt).sum())


def test_without_the_key_the_tilt_is_not_read(tmp_path):
    study = _study(tmp_path)
    cols = study.sample(0, 500)
    np.testing.assert_allclose(cols["vertical_bat_angle"], math.radians(FALLBACK_DEG))
    assert study.pitch_rows.tilt is None and "swing_plane" not in study.config()["pitches"]


def test_the_draws_do_not_depend_on_the_chunks(tmp_path):
    study = _study(tmp_path, swing_plane=True,
                   swing_error={"attack_angle": {"value": 5, "unit": "deg"}})
    whole = study.sample(0, 3000)["vertical_bat_angle"]
    parts = np.concatenate([study.sample(a, b)["vertical_bat_angle"]
                            for a, b in ((0, 1000), (1000, 2200), (2200, 3000))])
    np.testing.assert_array_equal(whole, parts)


@pytest.mark.parametrize("pitches, match", [
    ({"swing_plane": "yes"}, "must be true or false"),
    ({"swing_plane": True, "swing": False}, "only with pitches.swing = true")])
def test_bad_swing_plane_names_the_key(tmp_path, pitches, match):
    path = tmp_path / "rows.csv"
    write_pitches(_rows(), path)
    with pytest.raises(InputError, match=match) as err:
        Study.from_dict(_data(path, **pitches))
    assert err.value.field == "pitches.swing_plane"


def test_a_file_without_the_tilt_column_is_refused_by_name(tmp_path):
    path = tmp_path / "rows.csv"
    write_pitches(_rows(), path)
    pd.read_csv(path).drop(columns="swing_path_tilt").to_csv(path, index=False)
    study = Study.from_dict(_data(path, swing_plane=True))
    with pytest.raises(InputError, match="no column swing_path_tilt") as err:
        load_pitches(study)
    assert err.value.field == "pitches.file"


def test_a_population_fit_draws_the_planes_bats(tmp_path):
    """The study a population fit rewrites for its table keeps the rows' planes."""
    from mcbat.stats.population.templates import _conditioned_definition

    study = _study(tmp_path, swing_plane=True)
    data = _conditioned_definition(study, tmp_path / "rows.csv")
    rewritten = load_pitches(Study.from_dict(data))
    angles = np.degrees(rewritten.sample(0, 2000)["vertical_bat_angle"])
    assert rewritten.pitch_rows.tilt is not None
    assert angles.std() > 4.0 and np.mean(angles == FALLBACK_DEG) < 0.3


def test_a_run_says_how_many_rows_took_their_planes_bat(tmp_path):
    from mcbat.runner.study_run import run_study

    study = _study(tmp_path, swing_plane=True)
    lines = run_study(study, tmp_path / "ds", samples=600).lines()
    measured = int(np.isfinite(study.pitch_rows.tilt).sum())
    rest = study.pitch_rows.index.size - measured
    assert 0 < rest < measured
    assert (f"vertical bat angle from the measured swing plane on {measured:,} of those "
            f"rows, [swing]'s on the other {rest:,}") in lines


def _with_heights(rows, seed=9):
    rows = rows.copy()
    rows["plate_z"] = np.random.default_rng(seed).uniform(1.0, 4.0, len(rows))
    return rows


def _height_trend(angle=7.2, undercut=None):
    table = {"reference": {"value": 2.5, "unit": "ft"}, "per": {"value": 1, "unit": "ft"},
             "vertical_bat_angle": {"value": angle, "unit": "deg"}}
    if undercut is not None:
        table["undercut"] = {"value": undercut, "unit": "in"}
    return table


_SPREAD = {"dist": "truncnormal", "mean": -28, "std": 7, "low": -50, "high": -2,
           "unit": "deg"}


def test_the_height_trend_moves_the_bat_of_rows_without_a_plane(tmp_path):
    """Rows without a measured plane: the drawn angle moved by the pitch's height and held
    in the range; rows with one: their plane's bat, the trend ignored."""
    rows = _with_heights(_rows())
    path = tmp_path / "rows.csv"
    write_pitches(rows, path)
    plain_data = _data(path, swing_plane=True)
    plain_data["swing"]["vertical_bat_angle"] = dict(_SPREAD)
    plain_data["contact"]["plate_z_trend"] = _height_trend(0.0, undercut=0.0)
    data = _data(path, swing_plane=True)
    data["swing"]["vertical_bat_angle"] = dict(_SPREAD)
    data["contact"]["plate_z_trend"] = _height_trend()
    plain = load_pitches(Study.from_dict(plain_data))
    moved = load_pitches(Study.from_dict(data))
    a, b = plain.sample(), moved.sample()
    j = moved.pitch_rows.draw_rows(moved.seed, 0, moved.samples)
    tilt = moved.pitch_rows.tilt[j]
    z = rows["plate_z"].to_numpy()[moved.pitch_rows.index[j]] * 0.3048
    free = ~np.isfinite(tilt)
    expected = np.clip(a["vertical_bat_angle"][free]
                       + math.radians(7.2) / 0.3048 * (z[free] - 2.5 * 0.3048),
                       math.radians(-50), math.radians(-2))
    np.testing.assert_allclose(b["vertical_bat_angle"][free], expected, atol=1e-12)
    np.testing.assert_array_equal(b["vertical_bat_angle"][~free], a["vertical_bat_angle"][~free])
    high, low = free & (z > 3.25 * 0.3048), free & (z < 1.75 * 0.3048)
    assert np.degrees(b["vertical_bat_angle"][high].mean()
                      - b["vertical_bat_angle"][low].mean()) > 7.0
    config = moved.config()["contact"]["plate_z_trend"]
    assert config["vertical_bat_angle_per_plate_z"] == pytest.approx(
        math.radians(7.2) / 0.3048)
    assert config["undercut_per_plate_z"] == 0.0
    assert plain.config_hash() != moved.config_hash()


@pytest.mark.parametrize("swing, table, field, match", [
    ({"value": -30, "unit": "deg"}, _height_trend(),
     "contact.plate_z_trend.vertical_bat_angle", "as a distribution"),
    (_SPREAD, {"reference": {"value": 2.5, "unit": "ft"}, "per": {"value": 1, "unit": "ft"}},
     "contact.plate_z_trend", "needs undercut or vertical_bat_angle")])
def test_a_bad_height_trend_of_the_bat_names_its_field(tmp_path, swing, table, field, match):
    path = tmp_path / "rows.csv"
    write_pitches(_with_heights(_rows()), path)
    data = _data(path)
    data["swing"]["vertical_bat_angle"] = dict(swing)
    data["contact"]["plate_z_trend"] = table
    with pytest.raises(InputError, match=match) as err:
        Study.from_dict(data)
    assert err.value.field == field


def test_the_swing_length_trend_has_no_bat_angle(tmp_path):
    path = tmp_path / "rows.csv"
    write_pitches(_rows(), path)
    data = _data(path)
    data["contact"]["swing_length_trend"] = {
        "reference": {"value": 7.2, "unit": "ft"}, "per": {"value": 1, "unit": "ft"},
        "undercut": {"value": 0.3, "unit": "in"},
        "vertical_bat_angle": {"value": 5, "unit": "deg"}}
    with pytest.raises(InputError, match="vertical_bat_angle"):
        Study.from_dict(data)


def test_a_population_fit_does_not_free_the_planes_bat_angle(tmp_path):
    from mcbat.stats.population.parameters import parse_free

    study = _study(tmp_path, swing_plane=True)
    with pytest.raises(InputError, match="swing plane") as err:
        parse_free(study, ["swing.vertical_bat_angle.mean"])
    assert err.value.field == "free"
