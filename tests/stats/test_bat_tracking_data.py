"""The shipped excerpt of tracked balls in play (data/statcast_2025-05-01_bat_tracking.csv)
and the study that draws from it (studies/bat_tracking.toml)."""

import hashlib
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

import mcbat.statcast as sc
from mcbat.runner.pitches import load_pitches
from mcbat.study.spec import load_study

ROOT = Path(__file__).resolve().parents[2]
SOURCE = ROOT.parent / "shared" / "data" / "statcast" / "statcast_2025-05-01.csv"
NAME = "statcast_2025-05-01_bat_tracking.csv"
SHA256 = "c9f6f2fb7cb6fced105443570c870fb0db3f69f9472654eb2441f9c261bdde59"
GAMES = [778095, 778097, 778099, 778101, 778107]
KEY = ["game_pk", "at_bat_number", "pitch_number"]


def _excerpt():
    return resources.files("mcbat.data").joinpath(NAME)


def test_excerpt_is_the_file_data_readme_describes():
    data = _excerpt().read_bytes()
    assert hashlib.sha256(data).hexdigest() == SHA256
    assert len(data) < 400_000


def test_excerpt_holds_tracked_balls_in_play_of_its_games():
    with resources.as_file(_excerpt()) as path:
        t = sc.read(path)
    assert len(t) == 263
    assert sorted(t["game_pk"].unique()) == GAMES
    assert t["bb_type"].notna().all() and t["bat_speed"].notna().all()
    assert t["attack_angle"].notna().all() and t["swing_path_tilt"].notna().all()


@pytest.mark.skipif(not SOURCE.exists(), reason="the shared Statcast export is absent")
def test_excerpt_reads_as_the_same_rows_of_the_export():
    with resources.as_file(_excerpt()) as path:
        cut = sc.read(path).sort_values(KEY).reset_index(drop=True)
    full = sc.read(SOURCE)
    games = np.sort(full["game_pk"].unique())
    second = set(games[1::2].tolist())
    assert second == set(GAMES)
    rows = full[full["game_pk"].isin(second) & full["bb_type"].notna()
                & full["bat_speed"].notna()].sort_values(KEY).reset_index(drop=True)
    assert len(rows) == len(cut)
    for column in cut.columns:
        a, b = cut[column], rows[column]
        if a.dtype.kind == "f":
            np.testing.assert_array_equal(a.to_numpy(), b.to_numpy(), err_msg=column)
        else:
            assert a.astype(str).tolist() == b.astype(str).tolist(), column


def test_study_draws_from_the_shipped_excerpt():
    with resources.as_file(resources.files("mcbat.studies").joinpath("bat_tracking.toml")) \
            as path:
        text = Path(path).read_text(encoding="utf-8")
        assert tomllib.loads(text)["pitches"]["file"] == f"../data/{NAME}"
        study = load_pitches(load_study(path))
    assert study.samples == 100_000
    summary = study.pitch_rows.summary
    assert summary["rows_in_file"] == 263
    assert summary["drawn_from"] >= 255  # (the study's range checks may leave a few out)
    cols = study.sample(0, 2000)
    assert np.isfinite(cols["attack_angle"]).all()


@pytest.mark.skipif(not SOURCE.exists(), reason="the shared Statcast export is absent")
def test_parts_of_a_days_games_are_disjoint_and_cover_it():
    from validation.bat_tracking import tracked

    whole = tracked([SOURCE.name])
    parts = [tracked([f"{SOURCE.name}#{k}/2"]) for k in (1, 2)]
    assert sum(len(p) for p in parts) == len(whole) == 572
    games = [set(p["game_pk"]) for p in parts]
    batters = [set(p["batter"]) for p in parts]
    assert not games[0] & games[1]
    assert not batters[0] & batters[1]  # (a day's games share no batter)
    assert games[1] == set(GAMES)
    with pytest.raises(ValueError, match="#k/n"):
        tracked([f"{SOURCE.name}#3/2"])
