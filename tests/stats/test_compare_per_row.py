"""Per-row calibration (``mcbat compare`` on a dataset drawn from the measured pitches):
each measured value ranked among its own row's draws. An exact model reads 10 % above the
90th percentile at any number of draws a row, a too-narrow one reads more; real study
against its own export through the command line."""

import json

import numpy as np
import pandas as pd
import pytest

from mcbat.cli import main
from mcbat.runner import run_study
from mcbat.statcast import balls_in_play, read
from mcbat.stats.compare.per_row import PITCH_KEY, per_row_calibration
from mcbat.study import load_study
from tests.conftest import ROOT

UNITS = {"launch_speed": ("mph", "mph")}


def _frames(rows, draws, spread, seed=1, decimals=None):
    """``rows`` measured pitches with a true value each, and ``draws`` draws a row from a
    model of scatter ``spread`` (1 is exact)."""
    rng = np.random.default_rng(seed)
    centre = rng.normal(90, 8, rows)
    keys = pd.DataFrame({"game_pk": 7000 + np.arange(rows) // 50,
                         "at_bat_number": np.arange(rows) % 50 + 1, "pitch_number": 1})
    measured = keys.assign(launch_speed=centre + rng.normal(0, 1, rows))
    simulated = keys.loc[np.repeat(np.arange(rows), draws)].reset_index(drop=True)
    simulated["launch_speed"] = (np.repeat(centre, draws)
                                 + rng.normal(0, spread, rows * draws))
    if decimals is not None:
        for frame in (measured, simulated):
            frame["launch_speed"] = frame["launch_speed"].round(decimals)
    return simulated, measured


def _numpy_linear_share(simulated, measured):
    """The share above numpy's default 90th percentile of each row's draws."""
    p90 = simulated.groupby(list(PITCH_KEY))["launch_speed"].quantile(0.9)
    joined = measured.join(p90.rename("p90"), on=list(PITCH_KEY))
    return float(np.mean(joined["launch_speed"] > joined["p90"]))


def test_an_exact_model_reads_ten_percent_at_twenty_draws_a_row():
    simulated, measured = _frames(rows=6000, draws=20, spread=1.0)
    result = per_row_calibration(simulated, measured, UNITS)
    (column,) = result["columns"]
    assert result["met"] == column["rows"] == 6000
    assert result["draws_per_row"] == 20
    # binomial sd of a share of 6,000 rows: 0.39 %; 3.5 sd
    assert column["above_p90"] == pytest.approx(0.10, abs=0.014)
    assert column["below_p10"] == pytest.approx(0.10, abs=0.014)
    assert sum(column["histogram"]) == 6000
    # numpy's linear percentile of 20 draws reads (0.1 n + 0.9) / (n + 1) = 13.8 % instead
    assert _numpy_linear_share(simulated, measured) == pytest.approx(0.138, abs=0.014)


def test_a_too_narrow_model_reads_more_in_both_tails():
    simulated, measured = _frames(rows=3000, draws=40, spread=0.7)
    (column,) = per_row_calibration(simulated, measured, UNITS)["columns"]
    assert column["above_p90"] > 0.15 and column["below_p10"] > 0.15


def test_ties_are_spread_so_rounded_values_still_read_ten_percent():
    # Statcast's launch speeds come to 0.1 mph; here to 1 mph against a spread of 1
    simulated, measured = _frames(rows=6000, draws=30, spread=1.0, decimals=0)
    (column,) = per_row_calibration(simulated, measured, UNITS)["columns"]
    assert column["above_p90"] == pytest.approx(0.10, abs=0.014)
    assert column["below_p10"] == pytest.approx(0.10, abs=0.014)


def test_rows_not_met_are_counted_and_a_repeated_pitch_is_not_judged():
    simulated, measured = _frames(rows=200, draws=12, spread=1.0)
    few = simulated["game_pk"] == simulated["game_pk"].iloc[0]  # 50 rows
    simulated = pd.concat([simulated[~few], simulated[few].iloc[::2]])  # 6 draws each
    result = per_row_calibration(simulated, measured, UNITS)
    assert result["rows"] == 200 and result["met"] == 150
    assert result["columns"][0]["rows"] == 150
    assert per_row_calibration(simulated.drop(columns="game_pk"), measured, UNITS) is None
    twice = pd.concat([measured, measured.iloc[:1]])
    assert "given twice" in per_row_calibration(simulated, twice, UNITS)["not_judged"]
    # a measured row without its identifiers (two of them) is simply not met
    gaps = measured.astype({"at_bat_number": float})
    gaps.loc[[100, 101], "at_bat_number"] = np.nan
    assert per_row_calibration(simulated, gaps, UNITS)["met"] == 148
    named = measured.astype({"pitch_number": object})
    named.loc[5, "pitch_number"] = "first"
    assert "whole numbers" in per_row_calibration(simulated, named, UNITS)["not_judged"]


def test_bins_of_a_measured_column_carry_their_rows_means():
    simulated, measured = _frames(rows=1000, draws=15, spread=1.0)
    measured["bat_speed"] = np.random.default_rng(3).normal(71, 6, len(measured))
    result = per_row_calibration(simulated, measured, UNITS, by=("bat_speed", (65, 70, 75)))
    bins = result["columns"][0]["bins"]
    assert [b["bin"] for b in bins] == ["< 65", "65 to 70", "70 to 75", ">= 75"]
    assert sum(b["rows"] for b in bins) == 1000
    # independently: the rows' measured mean, and the mean of each row's own draw mean
    row_means = simulated.groupby(list(PITCH_KEY))["launch_speed"].mean()
    joined = measured.join(row_means.rename("model"), on=list(PITCH_KEY))
    grouped = joined.groupby(pd.cut(joined["bat_speed"], [-np.inf, 65, 70, 75, np.inf],
                                    right=False), observed=True)
    for b, (_, group) in zip(bins, grouped):
        assert b["rows"] == len(group)
        assert b["measured"] == pytest.approx(group["launch_speed"].mean(), rel=1e-12)
        assert b["model"] == pytest.approx(group["model"].mean(), rel=1e-12)
        assert b["se"] == pytest.approx(group["launch_speed"].sem(), rel=1e-9)


@pytest.fixture(scope="module")
def tracked(tmp_path_factory):
    out = tmp_path_factory.mktemp("per_row") / "tracked"
    run_study(load_study(ROOT / "studies" / "bat_tracking.toml"), out, samples=8000,
              chunk_size=4000, progress=False)
    return str(out)


def test_the_study_against_its_own_export(tracked, capsys, tmp_path):
    export = str(ROOT / "data" / "statcast_2025-05-01_bat_tracking.csv")
    figure = tmp_path / "per_row.png"
    code = main(["compare", tracked, export, "--json", "--permutations", "0",
                 "--columns", "launch_speed,launch_angle", "--figure", str(figure)])
    out, err = capsys.readouterr()
    assert code == 0, err
    per_row = json.loads(out)["per_row"]
    real = read(export)
    real = real[balls_in_play(real)]
    assert per_row["rows"] == per_row["met"] == len(real)
    # independently: the shares lie between the rows certainly above the 90th percentile
    # (at least 0.9 (n + 1) draws below) and those possibly above (one tie-break away)
    from mcbat import load

    sim = load(tracked, columns=[*PITCH_KEY, "launch_speed", "launch_angle"])
    for column in per_row["columns"]:
        name = column["column"]
        joined = sim.merge(real[[*PITCH_KEY, name]], on=list(PITCH_KEY),
                           suffixes=("", "_measured"))
        below = (joined[name] < joined[f"{name}_measured"]).groupby(
            [joined[k] for k in PITCH_KEY]).agg(["sum", "size"])
        certain = np.mean(below["sum"] >= 0.9 * (below["size"] + 1))
        possible = np.mean(below["sum"] + 1 > 0.9 * (below["size"] + 1))
        assert certain <= column["above_p90"] <= possible
        assert 0.03 < column["above_p90"] < 0.2 and 0.03 < column["below_p10"] < 0.2
    assert figure.read_bytes()[:4] == b"\x89PNG"
    code = main(["compare", tracked, export, "--permutations", "0",
                 "--columns", "launch_speed"])
    out, _ = capsys.readouterr()
    assert code == 0 and "per row: each of 263 measured pitches" in out
    line = next(s for s in out.splitlines() if s.startswith("  launch_speed "))
    assert f"{100 * per_row['columns'][0]['above_p90']:.1f}%" in line
    # by the bat-speed bins of docs/bat_tracking.md
    code = main(["compare", tracked, export, "--permutations", "0", "--columns",
                 "launch_speed", "--by", "bat_speed:65,70,75,80", "--json"])
    out, _ = capsys.readouterr()
    bins = json.loads(out)["per_row"]["columns"][0]["bins"]
    assert code == 0 and [b["bin"] for b in bins][1:4] == ["65 to 70", "70 to 75", "75 to 80"]
    assert sum(b["rows"] for b in bins) == len(real)
    for bad, words in (("bat_sped", "not a column"), ("bat_speed:70,65", "increasing"),
                       ("bat_speed:x", "numbers")):
        code = main(["compare", tracked, export, "--permutations", "0", "--by", bad])
        out, err = capsys.readouterr()
        assert code == 2 and "--by" in err and words in err and len(err.splitlines()) == 1


def test_drawn_keeps_the_measured_pitches_the_dataset_drew(tracked, capsys):
    export = str(ROOT / "data" / "statcast_2025-05-01_bat_tracking.csv")
    other = str(ROOT / "data" / "statcast_2020-09-03.csv")  # a day the study never drew
    counts = {}
    for flag in ((), ("--drawn",)):
        code = main(["compare", tracked, export, other, "--columns", "launch_speed",
                     "--permutations", "0", "--json", *flag])
        out, err = capsys.readouterr()
        assert code == 0, err
        result = json.loads(out)
        counts[flag] = result["columns"][0]["measured"]["rows"]
    real = read(export)
    drawn = len(real[balls_in_play(real)])
    assert counts[("--drawn",)] == drawn == result["settings"]["drawn"]
    assert counts[()] > drawn + 100
    code = main(["compare", tracked, other, "--drawn"])
    _, err = capsys.readouterr()
    assert code == 2 and "--drawn: the dataset drew none" in err


def test_a_dataset_drawn_too_thinly_says_how_many_samples_to_give():
    from mcbat.stats.compare.comparison import DRAWS_ADVISED, per_row_lines

    simulated, measured = _frames(rows=300, draws=4, spread=1.0)
    thin = per_row_calibration(simulated, measured, UNITS)
    assert thin["met"] == 0 and thin["drawn"] == 300
    (line,) = per_row_lines(thin)
    assert f"--samples {DRAWS_ADVISED * 300:,}" in line
    other = measured.assign(game_pk=measured["game_pk"] + 10_000)  # pitches never drawn
    (line,) = per_row_lines(per_row_calibration(simulated, other, UNITS))
    assert "not drawn from these pitches" in line
