"""Each row's players' contact estimated from their other games
(``mcbat.runner.player_levels``), on real excerpts: Ohtani's 2024 tracked balls in play
(one batter over 41 games) and a day of 2025 (every player in one game)."""

import tomllib
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mcbat.statcast as sc
from mcbat.runner import player_levels as pl
from mcbat.runner.pitches import load_pitches
from mcbat.runner.study_run import run_study
from mcbat.stats.population.table import write_pitches
from mcbat.study.pitches import IDENTIFIERS
from mcbat.study.spec import Study

ROOT = Path(__file__).resolve().parents[2]
EXCERPTS = ROOT / "tests" / "statcast" / "data"
OHTANI = EXCERPTS / "statcast_2024_ohtani_in_play_excerpt.csv"
DAY = EXCERPTS / "statcast_2025-05-01_excerpt.csv"
SHIPPED = ROOT / "studies" / "bat_tracking.toml"
IN = 0.0254


def shipped(pitches, samples=4000):
    """The shipped study, drawing from ``pitches``."""
    data = tomllib.loads(SHIPPED.read_text())
    data["pitches"]["file"] = str(pitches)
    data["study"]["samples"] = samples
    return Study.from_dict(data, source=SHIPPED)


def tidy_copy(path, tmp_path, name="rows.csv", change=None):
    """The excerpt as a tidy table a study reads, its measured outcomes changed by
    ``change(table)`` first."""
    table = sc.read(path)
    table = table[sc.balls_in_play(table) & np.isfinite(table["bat_speed"])].copy()
    if change is not None:
        change(table)
    out = tmp_path / name
    write_pitches(table.reset_index(drop=True), out)
    # (the written table keeps no batted-ball type: every row is a ball in play)
    frame = pd.read_csv(out)
    frame["bb_type"] = table["bb_type"].to_numpy()
    frame.to_csv(out, index=False)
    return out


@pytest.fixture(scope="module")
def ohtani():
    study = load_pitches(shipped(OHTANI))
    return study, pl.estimate_levels(study)


def test_a_batter_who_hits_harder_gets_a_tighter_contact(ohtani):
    # Ohtani's balls leave faster than the league's contact gives his swings (and, in
    # these games of August 2024, higher): every row's level says so, and his contact
    # finds the barrel more often and meets the ball further under its centre
    study, found = ohtani
    speed, angle = found["levels"]
    spread, shift = found["contact"]
    assert found["players"]["batter"] == 1
    assert np.all(speed > 0.3) and np.median(angle) > 1.0
    assert np.all(spread < 1.0)
    lifted = np.abs(angle) > 0.5
    assert lifted.sum() > 100 and np.all(np.sign(shift[lifted]) == np.sign(angle[lifted]))
    # the sensitivities: a tighter contact (negative log spread) is hit harder, a
    # contact further under the ball leaves higher
    sensitivity = found["sensitivity"]
    assert sensitivity[0, 0] < -2.0 and sensitivity[1, 1] > 10.0 / IN * 0.0254


def test_a_games_own_balls_never_enter_its_rows_contact(tmp_path):
    table = sc.read(OHTANI)
    game = int(table["game_pk"].iloc[0])

    def change(t):
        own = t["game_pk"] == game
        t.loc[own, "launch_speed"] += 25.0
        t.loc[own, "launch_angle"] -= 20.0

    found = []
    for name, edit in (("a.csv", None), ("b.csv", change)):
        study = load_pitches(shipped(tidy_copy(OHTANI, tmp_path, name, edit)))
        found.append(pl.estimate_levels(study))
    games = study.pitch_rows.identifiers[IDENTIFIERS.index("game_pk")]
    own = games == game
    assert own.sum() >= 2 and (~own).sum() > 100
    for k in range(2):
        np.testing.assert_allclose(found[1]["contact"][k][own], found[0]["contact"][k][own],
                                   rtol=1e-9, atol=1e-12)
        # ... while every other game's rows learn of them
        assert np.all(found[1]["contact"][k][~own] != found[0]["contact"][k][~own])


def test_every_player_in_one_game_keeps_the_leagues_contact(tmp_path):
    study = load_pitches(shipped(DAY))
    summary = study.config()["pitches"]["player_levels"]
    assert summary["rows_moved"] == 0
    assert summary["batters_with_level"] == summary["pitchers_with_level"] == 0
    league = load_pitches(shipped(DAY), player_levels=False)
    a, b = study.sample(0, 3000), league.sample(0, 3000)
    for name in a:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


def test_the_shrunk_mean_of_the_other_games():
    """One player over three games and one over one game (``_other_games`` against the
    formula written out)."""
    residual = np.array([2.0, 4.0, -1.0, 3.0, np.nan, 10.0])
    player = np.array([7, 7, 7, 7, 7, 8])
    game = np.array([1, 1, 2, 3, 3, 4])
    tau = 1.5
    got, players = pl._other_games(residual, player, game, tau)
    assert players == 1
    for row in range(6):
        if player[row] == 8:
            assert got[row] == 0.0  # (no other game)
            continue
        others = (player == 7) & (game != game[row]) & np.isfinite(residual)
        rest = (game != game[row]) & np.isfinite(residual)
        sigma2 = np.var(residual[rest])
        n = others.sum()
        expected = tau ** 2 / (tau ** 2 + sigma2 / n) * residual[others].mean()
        assert got[row] == pytest.approx(expected, rel=1e-12)
    # in sample (for judging only): over all the player's balls, the row's own too
    got, players = pl._other_games(residual, player, game, tau, own_game=True)
    assert players == 2
    mine = (player == 7) & np.isfinite(residual)
    sigma2 = np.nanvar(residual)
    expected = tau ** 2 / (tau ** 2 + sigma2 / mine.sum()) * residual[mine].mean()
    np.testing.assert_allclose(got[player == 7], expected, rtol=1e-12)
    assert got[5] == pytest.approx(tau ** 2 / (tau ** 2 + sigma2) * 10.0, rel=1e-12)


def test_the_run_reports_and_records_the_levels(tmp_path):
    report = run_study(shipped(OHTANI, samples=3000), tmp_path / "ds", progress=False)
    line = next(s for s in report.lines() if s.startswith("player levels"))
    assert "1 batter and" in line and "120 of the 120 rows" in line
    import mcbat

    attrs = mcbat.load(tmp_path / "ds").attrs["mcbat"]
    levels = attrs["study"]["pitches"]["player_levels"]
    assert levels["rows_moved"] == 120 and levels["spread_range"][1] < 1.0


def test_a_file_without_measured_outcomes_gives_every_row_the_leagues_contact(tmp_path):
    # a table of pitches and swings alone (no launch_speed or launch_angle) is still a
    # study's rows: no player can have a level, and the run says so
    rows = tidy_copy(OHTANI, tmp_path)
    frame = pd.read_csv(rows).drop(columns=["launch_speed", "launch_angle"])
    frame.to_csv(rows, index=False)
    report = run_study(shipped(rows, samples=2000), tmp_path / "ds", progress=False)
    line = next(s for s in report.lines() if s.startswith("player levels"))
    assert "no launch_speed or launch_angle" in line
    league = load_pitches(shipped(rows), player_levels=False)
    import mcbat

    got = mcbat.load(tmp_path / "ds")
    np.testing.assert_array_equal(got["from_barrel_end"].to_numpy(),
                                  league.sample(0, 2000)["from_barrel_end"])


def test_the_league_contact_flag_leaves_the_levels_out(tmp_path, capsys):
    import mcbat
    from mcbat.cli import main

    outs = {}
    for name, extra in (("own", []), ("league", ["--league-contact"])):
        code = main(["run", "bat_tracking", "--pitches", str(OHTANI), "--samples", "3000",
                     "--out", str(tmp_path / name), *extra])
        out, err = capsys.readouterr()
        assert code == 0, err
        assert ("player levels, each from the player's other games" in out) == (name == "own")
        outs[name] = mcbat.load(tmp_path / name)
    # the same rows and random numbers; Ohtani's own contact is tighter along the bat
    spread = [outs[k]["from_barrel_end"].std() for k in ("own", "league")]
    assert spread[0] < spread[1]
    assert outs["own"]["launch_speed"].mean() > outs["league"]["launch_speed"].mean()
    code = main(["run", "real_pitches", "--league-contact", "--out", str(tmp_path / "x")])
    _, err = capsys.readouterr()
    assert code == 2 and "--league-contact: the study has no [pitches.player_levels]" in err
    assert not (tmp_path / "x").exists()


def test_a_contact_whose_traits_act_alike_is_refused():
    # a contact hardly spread along the bat: its spread moves nothing, so no spread and
    # shift give the two levels (a clear error, not a singular matrix)
    data = tomllib.loads(SHIPPED.read_text())
    data["pitches"]["file"] = str(OHTANI)
    data["contact"]["from_barrel_end"].update(std=1e-6)
    from mcbat.errors import InputError

    with pytest.raises(InputError, match="does not move the launch speed and angle apart") \
            as err:
        load_pitches(Study.from_dict(data, source=SHIPPED))
    assert err.value.field == "pitches.player_levels"
