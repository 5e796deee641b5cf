"""Each player's own contact (``[pitches.player_levels]``): the table's checks and how a
row's spread and shift move its draws."""

import math

import numpy as np
import pytest

from mcbat.errors import InputError
from mcbat.runner.pitches import load_pitches
from mcbat.stats.population.table import write_pitches
from mcbat.study.spec import Study
from tests.study.test_swing_plane import _data, _rows

LEVELS = {"batter_launch_speed": {"value": 1.2, "unit": "mph"},
          "batter_launch_angle": {"value": 4.0, "unit": "deg"}}
CONTACT = {"from_barrel_end": {"dist": "truncnormal", "mean": 5, "std": 3, "low": 0.5,
                               "high": 18, "unit": "in"},
           "undercut": {"dist": "truncnormal", "mean": 0.3, "std": 1, "low": -2, "high": 2,
                        "unit": "in"}}


def _loaded(tmp_path, levels=True, **pitches):
    path = tmp_path / "rows.csv"
    write_pitches(_rows(), path)
    data = _data(path, **({"player_levels": LEVELS} if levels else {}), **pitches)
    data["contact"] = CONTACT
    # (the rows are synthetic, each its own game: the runner's estimate moves none)
    return load_pitches(Study.from_dict(data), player_levels=False)


def test_a_rows_spread_and_shift_move_only_its_contact(tmp_path):
    study = _loaded(tmp_path)
    m = study.pitch_rows.index.size
    spread, shift = np.ones(m), np.zeros(m)
    spread[::2], shift[1::2] = 0.5, 0.01  # even rows half the spread, odd ones 1 cm lower
    base = study.sample(0, study.samples)
    moved = study.with_player_contact(spread, shift).sample(0, study.samples)
    j = study.pitch_rows.draw_rows(study.seed, 0, study.samples)
    even, odd = j % 2 == 0, j % 2 == 1
    centre = 5 * 0.0254
    np.testing.assert_allclose(moved["from_barrel_end"][even] - centre,
                               0.5 * (base["from_barrel_end"][even] - centre), atol=1e-12)
    np.testing.assert_array_equal(moved["from_barrel_end"][odd], base["from_barrel_end"][odd])
    np.testing.assert_array_equal(moved["undercut"][even], base["undercut"][even])
    expected = np.clip(base["undercut"][odd] + 0.01, -2 * 0.0254, 2 * 0.0254)
    np.testing.assert_allclose(moved["undercut"][odd], expected, atol=1e-15)
    # the barrel's radius and the restitution follow the moved contact
    assert np.any(moved["bat_radius"][even] != base["bat_radius"][even])
    for name in base:
        if name not in ("from_barrel_end", "undercut", "bat_radius", "bat_slope",
                        "e_location_factor"):
            np.testing.assert_array_equal(moved[name], base[name], err_msg=name)


def test_the_leagues_contact_leaves_every_draw_as_it_was(tmp_path):
    with_table, without = _loaded(tmp_path), _loaded(tmp_path, levels=False)
    m = with_table.pitch_rows.index.size
    a = with_table.with_player_contact(np.ones(m), np.zeros(m)).sample(0, 2000)
    b = without.sample(0, 2000)
    for name in b:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


def test_the_contact_stays_inside_its_support(tmp_path):
    study = _loaded(tmp_path)
    m = study.pitch_rows.index.size
    cols = study.with_player_contact(np.full(m, 2.0), np.full(m, 0.05)).sample(0, 4000)
    assert cols["from_barrel_end"].min() >= 0.5 * 0.0254 - 1e-15
    assert cols["from_barrel_end"].max() <= 18 * 0.0254 + 1e-15
    assert cols["undercut"].max() <= 2 * 0.0254 + 1e-15
    assert np.any(cols["undercut"] == 2 * 0.0254)


def test_the_config_records_the_table(tmp_path):
    study = _loaded(tmp_path)
    levels = study.config()["pitches"]["player_levels"]
    assert levels["draws"] == 64
    np.testing.assert_allclose(levels["spread"]["batter"],
                               [1.2 * 0.44704, math.radians(4.0)])
    assert "pitcher" not in levels["spread"]
    assert study.config_hash() != _loaded(tmp_path, levels=False).config_hash()


@pytest.mark.parametrize("levels, swing, field, match", [
    (LEVELS, False, "pitches.player_levels", "only with pitches.swing = true"),
    ({"batter_launch_speed": {"value": 1.2, "unit": "mph"}}, True,
     "pitches.player_levels.batter_launch_angle", "needed with batter_launch_speed"),
    ({**LEVELS, "batter_launch_speed": {"value": 0, "unit": "mph"}}, True,
     "pitches.player_levels.batter_launch_speed", "must be > 0"),
    ({**LEVELS, "batter_launch_speed": {"value": 1.2, "unit": "deg"}}, True,
     "pitches.player_levels.batter_launch_speed.unit", "unit"),
    ({**LEVELS, "draws": 2}, True, "pitches.player_levels.draws", "8 .. 10000"),
    ({**LEVELS, "umpire_launch_speed": 1}, True, "pitches.player_levels.umpire_launch_speed",
     "unknown key"),
    ({}, True, "pitches.player_levels", "needs the levels' sd"),
    (3, True, "pitches.player_levels", "must be a table")])
def test_bad_tables_name_the_key(tmp_path, levels, swing, field, match):
    path = tmp_path / "rows.csv"
    write_pitches(_rows(), path)
    data = _data(path, player_levels=levels)
    data["pitches"]["swing"] = swing
    data["contact"] = CONTACT
    with pytest.raises(InputError, match=match) as err:
        Study.from_dict(data)
    assert err.value.field == field


def test_a_fixed_contact_is_refused(tmp_path):
    path = tmp_path / "rows.csv"
    write_pitches(_rows(), path)
    data = _data(path, player_levels=LEVELS)  # (its contact: fixed values)
    with pytest.raises(InputError, match="from_barrel_end drawn from a normal") as err:
        Study.from_dict(data)
    assert err.value.field == "pitches.player_levels"
