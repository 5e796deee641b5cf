"""mcbat.statcast.read on real Savant rows: two column layouts, the spray angle's sign
against the fielder who took the ball, the four-seamers' approach angle, a 2025 layout with
bat tracking, DataFrame input, Parquet round trip, and what happens to imperfect input."""

import io
import math
from importlib import resources

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest

from mcbat.errors import InputError
from mcbat.statcast import COLUMNS, OPTIONAL, UNITS, balls_in_play, read, write

DATA = resources.files("mcbat.data")
FILE_2019 = DATA.joinpath("statcast_2019_darvish.csv")
FILE_2020 = DATA.joinpath("statcast_2020-09-03.csv")
FILE_2014 = DATA.joinpath("statcast_2014_jeter.csv")
COLUMNS_2025 = [c for line in resources.files("tests").joinpath(
    "statcast/data/savant_2025_columns.txt").read_text().splitlines()
    if not line.startswith("#") for c in line.split(",")]


@pytest.fixture(scope="module")
def both():
    """The 2019 and 2020 exports, read."""
    return pd.concat([read(FILE_2019), read(FILE_2020)], ignore_index=True)


def test_two_layouts_read_to_the_same_columns_with_units():
    new, old = read(FILE_2014), read(FILE_2020)
    for df in (new, old):
        assert tuple(df.columns) == COLUMNS
        assert df.attrs["units"] == UNITS and set(UNITS) == set(COLUMNS)
        assert df.attrs["statcast"]["duplicate_columns"] == ["fielder_2", "pitcher"]
        assert df.attrs["statcast"]["non_numeric"] == {}  # "null" is missing, not bad
    # the 2022 export has spin_axis (empty for a 2014 game), the 2020 export has not
    assert "spin_axis" not in new.attrs["statcast"]["missing_columns"]
    assert "spin_axis" in old.attrs["statcast"]["missing_columns"]
    assert new.spin_axis.isna().all() and old.spin_axis.isna().all()
    # the byte-order mark does not eat the first column's name
    assert list(new.pitch_type) == ["SI", "FC", "FF", "FF", "FF", "FF"]
    assert set(new.game_year) == {2014.0} and set(old.game_year) == {2020.0}
    assert (new.batter == 116539).all()  # Derek Jeter


def test_values_pass_through_unchanged(both):
    raw = pd.read_csv(FILE_2020, na_values=["null"], low_memory=False)
    df = read(FILE_2020)
    for tidy, savant in (("release_speed", "release_speed"), ("spin_rate", "release_spin_rate"),
                         ("launch_speed", "launch_speed"), ("launch_angle", "launch_angle"),
                         ("hit_distance_sc", "hit_distance_sc"), ("plate_x", "plate_x")):
        assert np.array_equal(df[tidy].to_numpy(), raw[savant].to_numpy(dtype=float),
                              equal_nan=True), tidy
    assert list(df.handedness) == list(raw.stand)
    assert df.game_date.dt.strftime("%Y-%m-%d").eq("2020-09-03").all()
    assert df.at_bat_number.dtype == "Int64" and df.game_pk.notna().all()


def test_a_home_run_has_no_fielder_but_keeps_its_distance_and_spray(both):
    hr = both[both.events == "home_run"]
    assert len(hr) >= 20
    assert hr.hit_location.isna().all()
    assert hr.hit_distance_sc.notna().all() and hr.spray_angle.notna().all()


def test_spray_sign_follows_the_fielder_who_took_the_ball(both):
    """Positive spray is the first-base (right-field) side: every ball the left fielder (7)
    took has spray < 0, the right fielder's (9) > 0; a right-handed batter's grounders to
    third or short (5, 6) are pulled (< 0), a left-handed batter's to first or second
    (3, 4) are pulled the other way (> 0)."""
    bip = both[balls_in_play(both) & both.spray_angle.notna()]
    assert len(bip) > 450
    left, right = bip[bip.hit_location == 7], bip[bip.hit_location == 9]
    assert len(left) > 60 and len(right) > 60
    assert (left.spray_angle < 0).all() and (right.spray_angle > 0).all()
    grounders = bip[bip.bb_type == "ground_ball"]
    rhb = grounders[(grounders.handedness == "R") & grounders.hit_location.isin([5, 6])]
    lhb = grounders[(grounders.handedness == "L") & grounders.hit_location.isin([3, 4])]
    assert len(rhb) > 50 and len(lhb) > 40
    assert (rhb.spray_angle < 0).all() and (lhb.spray_angle > 0).all()
    # centre field sits in between
    assert abs(bip[bip.hit_location == 8].spray_angle.median()) < 5


@pytest.mark.parametrize("path", [FILE_2019, FILE_2020], ids=["2019", "2020"])
def test_four_seamers_descend_at_4_to_6_degrees_and_lose_speed(path):
    ff = read(path).query("pitch_type == 'FF'")
    assert len(ff) > 100
    assert -6.0 < ff.vertical_approach_angle.median() < -4.0
    # the plate speed is about 8 % below the release speed (BATTING.md)
    loss = 1 - ff.pitch_speed / ff.release_speed
    assert 0.06 < loss.median() < 0.11


def _layout_2025(rows):
    """Rows of the 2020 export rearranged into the 2025 column list, with bat-tracking
    values made up for the test (no real 2025 rows are shipped): the reader must find each
    column by name, whatever the order and the columns around it."""
    raw = pd.read_csv(FILE_2020, dtype=str, keep_default_na=False).iloc[rows]
    raw = raw.loc[:, ~raw.columns.duplicated()]
    n = len(raw)
    made_up = {"bat_speed": np.linspace(60.0, 80.0, n), "swing_length": np.linspace(6, 8, n),
               "attack_angle": np.linspace(-5, 25, n), "attack_direction": np.linspace(-20, 20, n),
               "swing_path_tilt": np.linspace(20, 40, n), "spin_axis": np.linspace(0, 350, n)}
    out = pd.DataFrame({c: raw[c].to_numpy() if c in raw.columns else "" for c in COLUMNS_2025})
    for c, v in made_up.items():
        out[c] = [f"{x:.4f}" for x in v]
    out.loc[out.index[::3], "bat_speed"] = ""  # no swing: empty, as Savant writes it
    return out, made_up


def test_a_2025_layout_with_bat_tracking(tmp_path):
    out, made_up = _layout_2025(slice(0, 60))
    path = tmp_path / "savant_2025.csv"
    out.to_csv(path, index=False)
    df = read(path)
    assert df.attrs["statcast"]["missing_columns"] == []
    for c in OPTIONAL:
        expect = np.array(made_up[c])
        if c == "bat_speed":
            expect[::3] = np.nan
        assert np.allclose(df[c], expect, atol=1e-4, equal_nan=True), c
    # the physics columns are the 2020 rows' own
    ref = read(FILE_2020).iloc[:60]
    assert np.array_equal(df.pitch_speed, ref.pitch_speed, equal_nan=True)
    assert np.array_equal(df.spray_angle, ref.spray_angle, equal_nan=True)


def test_a_pybaseball_dataframe_reads_like_the_file():
    """pybaseball hands over a typed DataFrame with the repeated columns renamed
    (``pitcher.1``) and missing values as NaN."""
    frame = pd.read_csv(FILE_2020, na_values=["null"], low_memory=False)
    assert "pitcher.1" in frame.columns
    a, b = read(frame), read(FILE_2020)
    pd.testing.assert_frame_equal(a, b, check_dtype=False)
    assert a.attrs["statcast"]["source"] == "<DataFrame>"


def test_parquet_round_trip_keeps_values_and_units(tmp_path):
    df = read(FILE_2019)
    path = tmp_path / "tidy.parquet"
    write(df, path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tidy.parquet"]  # no temp left
    meta = pq.read_schema(path).metadata[b"mcbat.statcast"]
    import json

    info = json.loads(meta)
    assert info["units"] == UNITS and info["statcast"]["rows"] == 438
    back = read(path)
    pd.testing.assert_frame_equal(back, df, check_dtype=False)
    assert back.attrs["units"] == UNITS


def _edited(tmp_path, edit, name="edited.csv"):
    text = FILE_2020.read_text(encoding="utf-8")
    path = tmp_path / name
    path.write_text(edit(text), encoding="utf-8")
    return path


def test_a_non_numeric_cell_is_nan_and_counted_with_its_line(tmp_path):
    lines = FILE_2020.read_text(encoding="utf-8").splitlines()
    header = next(iter(__import__("csv").reader([lines[0]])))
    row = next(iter(__import__("csv").reader([lines[1]])))
    row[header.index("launch_speed")] = "fast"
    buf = io.StringIO()
    __import__("csv").writer(buf, quoting=__import__("csv").QUOTE_MINIMAL,
                             lineterminator="\n").writerow(row)
    path = tmp_path / "bad_cell.csv"
    path.write_text("\n".join([lines[0], buf.getvalue().rstrip("\n"), *lines[2:]]) + "\n")
    df = read(path)
    assert len(df) == 2507 and math.isnan(df.launch_speed.iloc[0])
    assert df.attrs["statcast"]["non_numeric"] == {
        "launch_speed": {"cells": 1, "value": "fast", "line": 2}}
    assert df.launch_speed.iloc[1:].notna().sum() == read(FILE_2020).launch_speed.iloc[
        1:].notna().sum()


def test_a_truncated_download_is_refused_naming_the_line(tmp_path):
    text = FILE_2020.read_text(encoding="utf-8")
    cut = text[: len(text) // 2]  # mid-row
    cut = cut[: cut.rfind(",") + 1] + "1.5"
    path = tmp_path / "cut.csv"
    path.write_text(cut)
    with pytest.raises(InputError, match=r"line \d+: \d+ fields where the header has 89: "
                                         r"the file is truncated"):
        read(path)
    quoted = tmp_path / "cut_in_quotes.csv"
    quoted.write_text(text[: text.rfind('"Standard"') + 4])  # inside a quoted cell
    with pytest.raises(InputError, match="malformed CSV.*truncated or malformed"):
        read(quoted)


@pytest.mark.parametrize("drop", ["launch_angle", "vy0"])
def test_a_missing_required_column_is_named(tmp_path, drop):
    frame = pd.read_csv(FILE_2019, dtype=str, keep_default_na=False)
    path = tmp_path / "dropped.csv"
    frame.drop(columns=[drop]).to_csv(path, index=False)
    with pytest.raises(InputError) as err:
        read(path)
    assert str(err.value) == (f"{path}: not a Statcast (Baseball Savant) pitch-level export: "
                              f"missing column {drop}")


def test_an_unknown_home_team_has_no_elevation_and_is_counted(tmp_path):
    path = _edited(tmp_path, lambda t: t.replace('"NYM","NYY"', '"XYZ","NYY"'))
    df = read(path)
    report = df.attrs["statcast"]
    assert report["unknown_home_teams"] == {"XYZ": int((df.home_team == "XYZ").sum())}
    assert df.loc[df.home_team == "XYZ", "elevation"].isna().all()
    assert (df.loc[df.home_team == "BOS", "elevation"] == 20.0).all()
    assert report["elevation_missing"] == {"XYZ": int((df.home_team == "XYZ").sum())}


def test_an_empty_export_is_an_empty_table(tmp_path):
    path = tmp_path / "empty.csv"
    path.write_text(FILE_2020.read_text(encoding="utf-8").splitlines()[0] + "\n")
    df = read(path)
    assert len(df) == 0 and tuple(df.columns) == COLUMNS


def test_a_typed_pybaseball_frame_with_nullable_dtypes_reads_the_same():
    """pybaseball converts types (``convert_dtypes``: nullable integers, strings with
    ``pd.NA``, dates as datetimes)."""
    frame = pd.read_csv(FILE_2019, na_values=["null"], low_memory=False).convert_dtypes()
    frame["game_date"] = pd.to_datetime(frame["game_date"])
    assert str(frame["batter"].dtype) == "Int64"
    pd.testing.assert_frame_equal(read(frame), read(FILE_2019), check_dtype=False)


def test_the_attack_direction_check_sees_the_sign(tmp_path):
    """On a 2025-layout file whose attack direction follows the ball to the opposite field
    (made up from the real spray angles), the check is positive; with the sign flipped it
    is negative."""
    from mcbat.statcast import attack_direction_check

    df = read(FILE_2020)
    opposite = np.where(df.handedness == "L", -1.0, 1.0) * df.spray_angle.to_numpy()
    rng = np.random.default_rng(1)
    aimed = df.assign(attack_direction=0.3 * opposite + rng.normal(0, 5, len(df)))
    good = attack_direction_check(aimed)
    bad = attack_direction_check(aimed.assign(attack_direction=-aimed.attack_direction))
    assert good["rows"] == int((balls_in_play(df) & df.spray_angle.notna()).sum())
    assert good["correlation"] > 0.5 and bad["correlation"] < -0.5
    assert attack_direction_check(df) is None  # no bat tracking in 2020


def test_a_tidy_table_passes_through():
    df = read(FILE_2019)
    again = read(df)
    pd.testing.assert_frame_equal(again, df)
    assert again.attrs["statcast"] == df.attrs["statcast"]
