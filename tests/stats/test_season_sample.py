"""``python -m validation season_sample``: a season's swings, each given a real pitch.

On the shipped excerpt of 2025-05-01 (``data/statcast_2025-05-01_bat_tracking.csv``,
provenance in ``data/README.md``) read as a swing sample without its pitches."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[2]
EXCERPT = ROOT / "data" / "statcast_2025-05-01_bat_tracking.csv"


def _sample(raw):
    """The excerpt as a season sample gives it: the swing, the batted ball, the hands."""
    return pd.DataFrame({
        "launch_speed": raw["launch_speed"], "launch_angle": raw["launch_angle"],
        "bat_speed": raw["bat_speed"], "swing_length": raw["swing_length"],
        "attack_angle": raw["attack_angle"], "swing_path_tilt": raw["swing_path_tilt"],
        "plate_x": raw["plate_x"], "plate_z": raw["plate_z"],
        "is_stand_left": (raw["stand"] == "L").astype(int),
        "is_throw_left": (raw["p_throws"] == "L").astype(int)})


def test_each_swing_gets_a_real_pitch_of_its_pitchers_hand():
    from validation.season_sample import SWING_COLUMNS, pair

    raw = pd.read_csv(EXCERPT)
    raw = raw[raw["bb_type"].notna() & raw["bat_speed"].notna()].reset_index(drop=True)
    sample = _sample(raw)
    out = pair(sample, raw, seed=3)
    assert len(out) == len(sample)
    # the rows come grouped by the pitcher's hand: match them back by hand and order
    for hand, flag in (("R", 0), ("L", 1)):
        mine = sample[sample["is_throw_left"] == flag]
        theirs = out[out["p_throws"] == hand]
        assert len(mine) == len(theirs) > 0
        for column in SWING_COLUMNS:
            np.testing.assert_array_equal(theirs[column].to_numpy(), mine[column].to_numpy())
        np.testing.assert_array_equal(theirs["stand"].to_numpy(),
                                      np.where(mine["is_stand_left"] == 1, "L", "R"))
        # the pitch is one of the file's own, thrown by a pitcher of that hand
        pool = raw[raw["p_throws"] == hand]
        assert set(theirs["release_speed"]) <= set(pool["release_speed"])
        assert theirs["attack_direction"].isna().all()
    keys = out[["game_pk", "at_bat_number", "pitch_number"]]
    assert not keys.duplicated().any()


def test_a_hand_without_pitches_names_it():
    from validation.season_sample import pair

    raw = pd.read_csv(EXCERPT)
    raw = raw[raw["bb_type"].notna() & raw["bat_speed"].notna()]
    with pytest.raises(ValueError, match="throwing L"):
        pair(_sample(raw), raw[raw["p_throws"] == "R"])


def test_bins_compare_the_model_with_the_rows_they_meet():
    from validation.season_sample import binned, chi2

    key = np.array([1.0, 1.5, 2.5, 2.6] * 20)
    measured = np.array([10.0, 12.0, 20.0, 22.0] * 20)
    row = np.repeat(np.arange(key.size), 3)
    draws = measured[row] + 1.0  # the model 1 above every row
    bins = binned(key, (0.0, 2.0, 3.0), measured, row, draws)
    assert [b["rows"] for b in bins] == [40, 40]
    assert [b["measured"] for b in bins] == [11.0, 21.0]
    assert [b["model"] for b in bins] == [12.0, 22.0]
    assert chi2(bins) == pytest.approx(2 * (1.0 / (1.0 / np.sqrt(40))) ** 2)


def test_swing_length_slopes_recover_a_known_dependence_with_the_rest_held():
    from validation.season_sample import swing_length_slopes

    rng = np.random.default_rng(4)
    n = 4000
    bat = rng.normal(72.0, 5.0, n)
    # a swing length correlated with the bat speed and the height, as a season's are
    plate_z = rng.normal(2.4, 0.6, n)
    length = 7.2 + 0.05 * (bat - 72.0) - 0.4 * (plate_z - 2.4) + rng.normal(0.0, 0.5, n)
    table = pd.DataFrame({"bat_speed": bat, "swing_length": length, "plate_z": plate_z,
                          "plate_x": rng.uniform(-1.0, 1.0, n),
                          "handedness": rng.choice(["R", "L"], n),
                          "attack_angle": np.nan})
    speed = 90.0 + 1.0 * (bat - 72.0) - 1.5 * (length - 7.2) + rng.normal(0.0, 2.0, n)
    angle = 12.0 + 20.0 * (plate_z - 2.5) + 3.0 * (length - 7.2) + rng.normal(0.0, 5.0, n)
    data = swing_length_slopes(table, speed, angle)
    assert abs(data["speed"][0] + 1.5) < 3 * data["speed"][1]
    assert abs(data["angle"][0] - 3.0) < 3 * data["angle"][1]
    assert data["speed"][1] < 0.2
    # the model's draws map to their rows: three draws of each, the same dependence
    row = np.repeat(np.arange(n), 3)
    model = swing_length_slopes(table, speed[row], angle[row], row)
    assert model["speed"][0] == pytest.approx(data["speed"][0])
    # a regression on the length alone would mistake the bat speed's part for it
    naive = np.polyfit(length, speed, 1)[0]
    assert naive > data["speed"][0] + 1.0


def test_the_contact_is_fitted_to_a_sample_without_its_excluded_balls(tmp_path):
    # the excerpt read as a season sample, less the balls of a file of its own first rows:
    # those never reach the fit, and the fit frees the study's contact
    from validation.bat_tracking import FREE
    from validation.season_sample import UNREACHED, fit_contact

    raw = pd.read_csv(EXCERPT)
    raw = raw[raw["bb_type"].notna() & raw["bat_speed"].notna()].reset_index(drop=True)
    sample = tmp_path / "sample.csv"
    _sample(raw).to_csv(sample, index=False)
    excluded = tmp_path / "excluded.csv"
    raw.head(40).to_csv(excluded, index=False)
    result, unreached = fit_contact(str(sample), str(EXCERPT), 3, [str(excluded)])
    high = (raw["launch_angle"] > UNREACHED[0]) & (raw["launch_speed"] > UNREACHED[1])
    assert unreached == int(high.iloc[40:].sum())
    assert result.rows == len(raw) - 40 - unreached
    assert [p["name"] for p in result.parameters] == list(FREE)
    assert np.isfinite(result.chi2) and result.dof > 0


def test_backspin_slopes_compare_the_draws_with_nathans_model_on_the_same_balls():
    from mcbat.statcast.spin import nathan_average_spin
    from validation.bat_tracking import backspin_slopes

    rng = np.random.default_rng(2)
    n = 5000
    spin = {"launch_angle": rng.uniform(-20.0, 60.0, n), "spray_angle": rng.normal(0, 20, n),
            "handedness": rng.choice(["R", "L"], n)}
    nathan, _ = nathan_average_spin(spin["launch_angle"], spin["spray_angle"],
                                    spin["handedness"])
    spin["backspin"] = 1.1 * nathan
    model, theirs, ratio = backspin_slopes(spin)
    assert theirs == pytest.approx(120.0, abs=3.0)  # spray and side average out
    assert model == pytest.approx(1.1 * theirs)
    assert ratio == pytest.approx(1.1)
    # too few balls in 10-40 deg: no slope rather than a noisy one
    few = {k: v[:50] for k, v in spin.items()}
    assert all(np.isnan(x) for x in backspin_slopes(few))


@pytest.mark.parametrize("draws", [20, 40, 175])
def test_an_exact_models_share_beyond_its_rows_p90_at_few_draws(draws):
    # the measured value drawn from the row's own distribution: the share above the p90
    # and below the p10 of its draws is what exact_model_share says, not 10 %
    from validation.bat_tracking import exact_model_share

    rng = np.random.default_rng(draws)
    rows = 40000
    sims = rng.normal(size=(rows, draws))
    measured = rng.normal(size=rows)
    lo, hi = np.quantile(sims, [0.1, 0.9], axis=1)
    expected = exact_model_share(draws)
    se = np.sqrt(expected * (1 - expected) / rows)
    assert abs(np.mean(measured > hi) - expected) < 4 * se
    assert abs(np.mean(measured < lo) - expected) < 4 * se
    assert expected > 0.1 + 4 * se or draws == 175


def test_the_summary_row_says_which_targets_hold():
    from validation.bat_tracking import summary_table

    r = {"rows": 400, "ks_launch_speed": 0.06, "ks_launch_angle": 0.03,
         "ks_launch_speed_p": 0.11, "ks_launch_angle_p": 0.86, "ks_exact_median": 0.041,
         "launch_speed_above_p90": 0.10, "launch_speed_below_p10": 0.14,
         "launch_angle_above_p90": 0.09, "launch_angle_below_p10": 0.11,
         "bat_speed_bins": [{"bin": "65-70", "rows": 150, "model": 88.0, "measured": 86.5},
                            {"bin": "75-80", "rows": 120, "model": 95.0, "measured": 92.5},
                            {"bin": "80+", "rows": 40, "model": 99.0, "measured": 90.0}]}
    header, rule, row = summary_table([("day.csv", r)])
    assert header.count("|") == rule.count("|") == row.count("|")
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[0] == "day.csv" and cells[1] == "400"
    assert cells[2] == "0.060 (0.11) / 0.030 (0.86)" and cells[3] == "0.041"
    assert cells[6] == "65-70: +1.5, 75-80: +2.5"  # the 40-row bin is not held to 2 mph
    # KS launch angle, three of the four shares and one bin hold; KS launch speed, the
    # 14 % share and the 75-80 bin do not
    assert cells[7] == "5 of 8"
