"""The collision measured per ball (mcbat.statcast.collision) on real exports."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mcbat.statcast as sc

EXCERPT = Path(__file__).parent / "data" / "statcast_2025-05-01_excerpt.csv"
SHARED = Path(__file__).parents[2] / ".." / "shared" / "data" / "statcast"


def test_columns_on_the_excerpt():
    df = sc.read(EXCERPT)
    bip = sc.balls_in_play(df)
    tracked = bip & df["bat_speed"].notna().to_numpy()
    q = df["collision_efficiency"].to_numpy()
    assert np.isfinite(q[tracked]).all() and np.isnan(q[~tracked]).all()
    # launch speed rebuilt from q: the definition, row by row
    rebuilt = q * df["pitch_speed"] + (1 + q) * df["bat_speed"]
    assert np.allclose(rebuilt[tracked], df.loc[tracked, "launch_speed"], rtol=1e-12)
    frac = df["squared_up_fraction"].to_numpy()
    top = 1.23 * df["bat_speed"] + 0.23 * df["pitch_speed"]
    assert np.allclose(frac[tracked], (df["launch_speed"] / top)[tracked])
    assert str(df["squared_up"].dtype) == "boolean"
    assert df["squared_up"][~tracked].isna().all()
    assert (df["squared_up"][tracked].astype(bool) == (frac[tracked] >= 0.8)).all()
    assert df.attrs["units"]["collision_efficiency"] == "1"


def test_parquet_round_trip(tmp_path):
    df = sc.read(EXCERPT)
    sc.write(df, tmp_path / "t.parquet")
    back = sc.read(tmp_path / "t.parquet")
    pd.testing.assert_series_equal(back["squared_up"], df["squared_up"])
    # a tidy table without the collision columns (written before they existed) gets them
    old = df.drop(columns=["collision_efficiency", "squared_up_fraction", "squared_up"])
    again = sc.read(old)
    assert np.allclose(again["collision_efficiency"], df["collision_efficiency"],
                       equal_nan=True)


def test_summary_on_the_excerpt():
    df = sc.read(EXCERPT)
    s = sc.collision_summary(df)
    q = df["collision_efficiency"].dropna()
    assert s["balls"] == len(q) == 70  # the sacrifice bunt has no bat tracking
    assert s["collision_efficiency"]["max"] == pytest.approx(q.max())
    assert s["upper_edge"]["max_squared_up"] <= s["upper_edge"]["max"]
    assert sum(b["balls"] for b in s["by_bat_speed"]) == s["balls"]
    slope = np.polyfit(df.loc[q.index, "bat_speed"], df.loc[q.index, "launch_speed"], 1)[0]
    assert s["launch_speed_vs_bat_speed"]["slope"] == pytest.approx(slope)


def test_summary_leaves_tracked_bunts_out():
    path = SHARED / "statcast_2024_skubal.csv"
    if not path.is_file():
        pytest.skip("the shared exports are not here")
    s = sc.collision_summary(sc.read(path))
    assert s["left_out"]["bunts"] == 3
    # the measured upper edge lies near Statcast's own ceiling q = 0.23
    assert 0.2 < s["upper_edge"]["p99"] < 0.26
