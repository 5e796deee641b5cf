"""Fits read Statcast exports: the measurement table taken from real Savant rows (the balls
in play with a measured launch; counted), from the tidy Parquet table, from a layout with bat
tracking, and ``mcbat fit --data`` on a real export."""

import json
import subprocess
import sys
from importlib import resources

import numpy as np
import pandas as pd
import pytest

from mcbat.statcast import balls_in_play, is_statcast, measurement_table, read, write
from mcbat.stats.measurements import read_measurements
from tests.conftest import ROOT

FILE_2020 = resources.files("mcbat.data").joinpath("statcast_2020-09-03.csv")


def test_a_savant_export_is_a_game_measurement_table():
    table = read_measurements(FILE_2020)
    assert list(table.columns) == ["launch_speed", "launch_angle", "spray_angle",
                                   "pitch_speed"]
    report = table.attrs["statcast"]
    assert report == {"rows": 2507, "used": 413, "not_in_play": 2080, "no_launch": 3,
                      "foul_territory": 11, "no_plate_speed": 0, "no_bat_tracking": 0,
                      "measured_inputs": ["pitch_speed"]}
    assert np.isfinite(table.to_numpy()).all()
    # the rows are the fair balls in play with a launch, in file order, values unchanged
    df = read(FILE_2020)
    fouls = df.des.str.contains("in foul territory", regex=False).fillna(False)
    bip = df[balls_in_play(df) & df.launch_speed.notna() & df.launch_angle.notna() & ~fouls]
    # the foul outs are the balls caught beyond the lines (one of the 12 has no launch
    # and counts as such)
    caught = df[balls_in_play(df) & fouls]
    assert len(caught) == 12 and caught.launch_speed.isna().sum() == 1
    assert (caught.spray_angle.abs() > 45).all()
    assert np.array_equal(table.launch_speed, bip.launch_speed)
    assert np.array_equal(table.pitch_speed, bip.pitch_speed)
    # pitch_speed is the plate speed, not the release speed
    assert (table.pitch_speed < bip.release_speed.to_numpy()).all()


def test_the_tidy_table_and_other_tables_are_told_apart(tmp_path):
    tidy = tmp_path / "tidy.parquet"
    write(read(FILE_2020), tidy)
    assert is_statcast(FILE_2020) and is_statcast(tidy)
    pd.testing.assert_frame_equal(read_measurements(tidy), read_measurements(FILE_2020))
    drops = resources.files("mcbat.data").joinpath("synthetic_cross_nathan_60.csv")
    assert not is_statcast(drops)
    assert "statcast" not in read_measurements(drops).attrs


def test_bat_tracking_columns_become_measured_inputs(tmp_path):
    """A 2025-layout file built from the 2020 rows with made-up bat tracking (no real 2025
    rows are shipped): bat_speed and attack_angle become measured inputs; balls in play
    without bat tracking are dropped and counted."""
    raw = pd.read_csv(FILE_2020, dtype=str, keep_default_na=False)
    raw = raw.loc[:, ~raw.columns.duplicated()]
    n = len(raw)
    raw["bat_speed"] = [f"{v:.1f}" for v in np.linspace(60, 80, n)]
    raw["attack_angle"] = [f"{v:.1f}" for v in np.linspace(-5, 25, n)]
    in_play = raw.description.str.startswith("hit_into_play")
    first = raw.index[in_play][:10]
    raw.loc[first, "bat_speed"] = ""  # ten balls in play without bat tracking
    path = tmp_path / "tracked.csv"
    raw.to_csv(path, index=False)
    table = measurement_table(path)
    assert list(table.columns) == ["launch_speed", "launch_angle", "spray_angle",
                                   "pitch_speed", "bat_speed", "attack_angle"]
    assert table.attrs["statcast"]["no_bat_tracking"] == 10
    assert table.attrs["statcast"]["used"] == 413 - 10


def test_an_export_without_balls_in_play_is_refused(tmp_path):
    from mcbat.errors import InputError

    raw = pd.read_csv(FILE_2020, dtype=str, keep_default_na=False)
    raw = raw.loc[:, ~raw.columns.duplicated()]
    path = tmp_path / "no_bip.csv"
    raw[~raw.description.str.startswith("hit_into_play")].to_csv(path, index=False)
    with pytest.raises(InputError, match="no ball in play with a measured launch"):
        read_measurements(path)


def test_mcbat_fit_reads_a_savant_export(tmp_path):
    """A real export (the first 300 pitches of the 2020 day: ~50 balls in play) fitted by
    the game preset; the command says on stderr which rows it used."""
    lines = FILE_2020.read_text(encoding="utf-8").splitlines()
    path = tmp_path / "savant.csv"
    path.write_text("\n".join(lines[:301]) + "\n")
    # The preset aims the swing at centre field (attack direction sd 8 deg); real balls
    # in play spread over the whole fair territory: a study that spans it.
    text = (ROOT / "studies" / "game_fastball.toml").read_text()
    old = 'attack_direction = { dist = "truncnormal", mean = 0, std = 8, low = -30, high = 30,'
    assert old in text
    study = tmp_path / "wide.toml"
    study.write_text(text.replace(old, 'attack_direction = { dist = "truncnormal", mean = 0, '
                                       'std = 25, low = -60, high = 60,'))
    proc = subprocess.run([sys.executable, "-m", "mcbat", "fit", "--study",
                           str(study), "--data", str(path),
                           "--free", "e", "--draws", "4", "--intervals", "curvature",
                           "--no-compare", "--json"],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    used = measurement_table(path).attrs["statcast"]["used"]
    assert used > 30
    assert proc.stderr.count("\n") == 1
    assert f"Statcast export: {used:,} of 300 pitches used" in proc.stderr
    result = json.loads(proc.stdout)
    assert 0 < result["params"]["e"]["value"] < 1
    assert result["dof"] == 3 * used - 1  # launch speed, launch angle, spray angle per ball
