"""``python -m validation batter_swing_means``: the within- and between-batter split of
launch speed on bat speed with each batter's mean over his other tracked swings.

Checked on synthetic tables whose variance components and slopes are known."""

import numpy as np
import pandas as pd
import pytest


def _table(between_sd, within_sd, batters, swings, within_slope, between_slope, seed):
    rng = np.random.default_rng(seed)
    true_mean = 72.0 + between_sd * rng.standard_normal(batters)
    batter = np.repeat(np.arange(batters), swings)
    bat = true_mean[batter] + within_sd * rng.standard_normal(batter.size)
    pitch = 90.0 + 3.0 * rng.standard_normal(batter.size)
    launch = (90.0 + within_slope * (bat - true_mean[batter])
              + between_slope * (true_mean[batter] - 72.0) + 0.2 * (pitch - 90.0)
              + 0.5 * rng.standard_normal(batter.size))
    in_play = rng.random(batter.size) < 0.5
    return pd.DataFrame({"batter": batter, "bat_speed": bat, "pitch_speed": pitch,
                         "launch_speed": np.where(in_play, launch, np.nan),
                         "bb_type": np.where(in_play, "line_drive", None),
                         "description": np.where(in_play, "hit_into_play", "foul")})


def test_the_variances_between_and_within_batters_are_recovered():
    from validation.batter_swing_means import variances

    between, within, n0 = variances(_table(3.0, 6.0, 400, 10, 1.0, 1.0, seed=1), 6)
    assert n0 == pytest.approx(10.0)
    assert np.sqrt(within) == pytest.approx(6.0, rel=0.05)
    assert np.sqrt(between) == pytest.approx(3.0, rel=0.15)


def test_a_batters_mean_leaves_his_own_swing_out():
    from validation.batter_swing_means import swing_means

    table = _table(3.0, 6.0, 5, 8, 1.0, 1.0, seed=2)
    balls = swing_means(table, 6)
    for index, ball in balls.iterrows():
        others = table[(table["batter"] == ball["batter"]) & (table.index != index)]
        assert ball["batter_mean"] == pytest.approx(others["bat_speed"].mean())
        assert ball["swings"] == len(others) + 1


@pytest.mark.parametrize("between_slope", [0.3, 1.0])
def test_the_slopes_within_and_between_batters_are_recovered_through_the_means_noise(
        between_slope):
    from validation.batter_swing_means import slopes, swing_means, variances

    table = _table(3.0, 6.0, 3000, 8, 1.0, between_slope, seed=3)
    between, within, _ = variances(table, 6)
    balls = swing_means(table, 6)
    within_fit, between_fit = slopes(balls, between, within)
    assert within_fit == pytest.approx(1.0, abs=0.05)
    assert between_fit == pytest.approx(between_slope, abs=0.1)
    if between_slope == 1.0:
        return  # equal slopes: least squares is unbiased too (launch speed is linear in V)
    # a least-squares fit on the left-out mean is biased by its noise: the moments are not
    x = np.column_stack([np.ones(len(balls)), balls["bat_speed"] - balls["batter_mean"],
                         balls["batter_mean"]])
    naive = np.linalg.lstsq(x, balls["launch_speed"].to_numpy(float), rcond=None)[0][2]
    assert abs(naive - between_slope) > 2 * abs(between_fit - between_slope)


def test_a_leaderboards_between_batter_slope_is_recovered(tmp_path):
    from validation.batter_swing_means import leaderboard

    rng = np.random.default_rng(4)
    bat = 72.0 + 2.7 * rng.standard_normal(300)
    velocity = 89.5 + 0.5 * rng.standard_normal(300)
    board = pd.DataFrame({"player_name": [f"p{i}" for i in range(300)], "bat_speed": bat,
                          "launch_speed": 40.0 + 0.7 * bat + 0.1 * velocity
                          + 0.3 * rng.standard_normal(300),
                          "velocity": velocity, "bip": rng.integers(50, 450, 300)})
    board.loc[0, "bat_speed"] = None  # a batter without bat tracking is left out
    path = tmp_path / "board.csv"
    board.to_csv(path, index=False)
    lines = leaderboard(path, 150, 100, 0)
    kept = int((board["bip"] >= 150).sum() - (board.loc[0, "bip"] >= 150))
    assert f"{kept} players" in lines[0]
    slope = float(lines[1].split(":")[1].split("+-")[0])
    assert slope == pytest.approx(0.7, abs=0.03)


@pytest.mark.parametrize("lasting", [True, False])
def test_a_lasting_level_covaries_between_seasons_and_a_passing_one_does_not(tmp_path,
                                                                               lasting):
    from validation.batter_swing_means import season_levels

    rng = np.random.default_rng(5)
    players = 2000
    level = 1.0 * rng.standard_normal(players)  # true sd 1 mph: variance 1 mph^2
    paths = []
    for season in (1, 2):
        bip = rng.integers(200, 600, players)
        true = level if lasting else 1.0 * rng.standard_normal(players)
        bat = 72.0 + 2.7 * rng.standard_normal(players)
        velocity = 89.5 + 0.5 * rng.standard_normal(players)
        mean = (40.0 + 0.7 * bat + 0.1 * velocity + true
                + 14.5 / np.sqrt(bip) * rng.standard_normal(players))
        board = pd.DataFrame({"player_id": np.arange(players), "bat_speed": bat,
                              "launch_speed": mean, "velocity": velocity, "bip": bip,
                              "spin_rate": 2300.0 + 150.0 * rng.standard_normal(players)
                              - (600.0 * true if lasting else 0.0)})
        paths.append(tmp_path / f"season{season}.csv")
        board.to_csv(paths[-1], index=False)
    from validation.batter_swing_means import season_to_season

    n, cov, var1, var2 = season_levels(*paths, 150)
    # a lasting level that a pitch characteristic carries shows in its correlation
    spin = next(line for line in season_to_season(*paths, 150) if "spin_rate" in line)
    r = [float(v) for v in spin.split("r ")[1].split(", ")]
    # (lasting: r = -600 / sqrt(150^2 + 600^2) / sqrt(1 + noise 0.5) = -0.79)
    assert all(v < -0.65 for v in r) if lasting else all(abs(v) < 0.1 for v in r)
    assert n == players
    assert var1 == pytest.approx(1.0, abs=0.15) and var2 == pytest.approx(1.0, abs=0.15)
    assert cov == pytest.approx(1.0 if lasting else 0.0, abs=0.12)
