"""Real pitches in game studies ([pitches]): the section's validation, the filters and the
counted exclusions, and the row draw's determinism (the study layer, on tables built here;
the runs on real Statcast rows are in tests/runner/test_real_pitches.py)."""

import math

import numpy as np
import pandas as pd
import pytest

from mcbat.errors import InputError
from mcbat.runner.pitches import load_pitches
from mcbat.study import Study
from mcbat.study.game import COLUMNS
from mcbat.study.pitches import ROW_STREAM
from mcbat.study.random_program import stream_id

MPH, DEG, RPM = 0.44704, math.pi / 180, 2 * math.pi / 60
AXIS = {"spin_axis": {"value": 200, "unit": "deg"}}  # a fallback spin axis


def tidy_table(n=60, seed=1):
    """A small tidy table (synthetic values, the reader's column names and units) with
    bat tracking on the 2024 rows and no spin axis on the first four."""
    rng = np.random.default_rng(seed)
    df = pd.DataFrame({
        "game_pk": 745000 + rng.integers(0, 3, n), "at_bat_number": rng.integers(1, 70, n),
        "pitch_number": rng.integers(1, 7, n), "pitcher": rng.choice([543037, 605400], n),
        "batter": rng.choice([592450, 660271, 545361], n),
        "pitch_type": rng.choice(["FF", "SL", "CH"], n), "p_throws": rng.choice(["R", "L"], n),
        "handedness": rng.choice(["R", "L"], n), "game_year": rng.choice([2019, 2024], n),
        "pitch_speed": rng.normal(87, 3, n), "vertical_approach_angle": rng.normal(-6, 1, n),
        "horizontal_approach_angle": rng.normal(0, 1.5, n),
        "spin_rate": rng.normal(2300, 200, n), "spin_axis": rng.normal(200, 30, n),
        "bat_speed": rng.normal(70, 4, n), "attack_angle": rng.normal(10, 5, n),
        "attack_direction": rng.normal(0, 8, n)})
    df.loc[df.game_year == 2019, ["bat_speed", "attack_angle", "attack_direction"]] = np.nan
    df.loc[:3, "spin_axis"] = np.nan
    # distinct pitches (a repeated game_pk, at_bat_number, pitch_number is a copy, left out)
    df["at_bat_number"] = np.arange(1, n + 1)
    return df


def study_dict(pitches, **sections):
    data = {
        "study": {"name": "real", "samples": 500, "seed": 3},
        "ball": {"preset": "baseball"}, "bat": {"preset": "r161"},
        "pitches": pitches,
        "pitch": {"spin_efficiency": 0.9},
        "swing": {"bat_speed": {"value": 70, "unit": "mph"},
                  "vertical_bat_angle": {"dist": "uniform", "low": -40, "high": -20,
                                         "unit": "deg"}},
        "contact": {"undercut": {"dist": "uniform", "low": -1, "high": 1, "unit": "in"}},
        "friction": {"mu": 0.5},
    }
    data.update(sections)
    return data


@pytest.fixture(scope="module")
def table_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("pitches") / "tidy.parquet"
    tidy_table().to_parquet(path)
    return path


def loaded(table_file, **pitches):
    spec = {"file": str(table_file), **pitches}
    return load_pitches(Study.from_dict(study_dict(spec)))


def test_the_row_stream_is_no_study_keys_stream():
    from mcbat.study.game import KEYS

    names = [f"{s}.{k}" for s, keys in KEYS.items() for k in keys]
    assert stream_id(ROW_STREAM) not in {stream_id(name) for name in names}


def test_drawn_values_are_the_rows_values_in_si(table_file):
    study = loaded(table_file, fallback={"spin_axis": {"value": 210, "unit": "deg"}})
    df = tidy_table()
    n = 400
    inputs = study.sample_inputs(0, n)
    cols = {name: inputs[i] for i, name in enumerate(COLUMNS)}
    rows = study.pitch_identifiers(0, n)["source_row"]
    real = df.iloc[rows]
    assert np.array_equal(cols["pitch_speed"], real["pitch_speed"].to_numpy() * MPH)
    assert np.array_equal(cols["pitch_spin_rate"], real["spin_rate"].to_numpy() * RPM)
    assert np.array_equal(cols["pitch_vertical_approach_angle"],
                          real["vertical_approach_angle"].to_numpy() * DEG)
    assert np.array_equal(cols["handedness"],
                          np.where(real["handedness"] == "R", 1.0, -1.0))
    # The four rows without a spin axis take the fallback; the others their own.
    axis = real["spin_axis"].to_numpy()
    missing = np.isnan(axis)
    assert missing.any() and (~missing).any()
    assert np.allclose(cols["pitch_spin_axis"][missing], math.radians(210), rtol=1e-15, atol=0)
    assert np.array_equal(cols["pitch_spin_axis"][~missing], axis[~missing] * DEG)
    # Not drawn from the rows: the study's keys as always.
    assert np.all(cols["bat_speed"] == 70 * MPH)
    assert np.all(cols["pitch_spin_efficiency"] == 0.9)
    # Every selected row is drawn, about equally often (60 rows, 20,000 draws).
    counts = np.bincount(study.pitch_identifiers(0, 20_000)["source_row"], minlength=60)
    assert (counts > 0).all()
    assert counts.std() / counts.mean() < 0.2


def test_the_draw_does_not_depend_on_chunks_or_threads(table_file):
    import numba

    study = loaded(table_file, fallback={"spin_axis": {"dist": "uniform", "low": 180,
                                                       "high": 240, "unit": "deg"}})
    pieces = [(0, 1), (1, 1000), (1000, 1024), (1024, 3000)]
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))  # the whole on two
        whole = study.sample_inputs(0, 3000)
        ids = study.pitch_identifiers(0, 3000)
        numba.set_num_threads(1)  # the pieces on one
        joined = np.concatenate([study.sample_inputs(a, b) for a, b in pieces], axis=1)
        joined_ids = {k: np.concatenate([study.pitch_identifiers(a, b)[k] for a, b in pieces])
                      for k in ids}
    finally:
        numba.set_num_threads(threads)
    assert np.array_equal(whole, joined, equal_nan=True)
    for k in ids:
        assert np.array_equal(ids[k], joined_ids[k])
    assert not np.array_equal(study.pitch_identifiers(0, 3000, seed=4)["source_row"],
                              ids["source_row"])


def test_filters_and_lists(table_file):
    df = tidy_table()
    study = loaded(table_file, pitch_type=["FF", "SL"], p_throws="R", game_year=2024,
                   fallback=AXIS)
    want = df[df.pitch_type.isin(["FF", "SL"]) & (df.p_throws == "R") & (df.game_year == 2024)]
    rows = study.pitch_identifiers(0, 5000)["source_row"]
    assert set(rows) == set(want.index)
    summary = study.pitch_rows.summary
    assert summary["rows_in_file"] == 60 and summary["selected"] == len(want)
    pitcher = int(df.pitcher.iloc[0])
    rows = loaded(table_file, pitcher=pitcher, batter=[int(df.batter.iloc[0])],
                  fallback=AXIS).pitch_identifiers(0, 2000)
    assert set(rows["pitcher"]) == {pitcher}
    assert set(rows["batter"]) == {int(df.batter.iloc[0])}


def test_rows_without_a_value_are_left_out_and_counted(table_file):
    study = loaded(table_file)  # no fallback for spin_axis
    assert study.pitch_rows.summary["excluded"] == {"without spin_axis": 4}
    assert study.pitch_rows.summary["drawn_from"] == 56
    assert not set(study.pitch_identifiers(0, 5000)["source_row"]) & {0, 1, 2, 3}
    assert study.config()["pitches"]["excluded"] == {"without spin_axis": 4}


def test_swing_from_bat_tracking(table_file):
    df = tidy_table()
    data = study_dict({"file": str(table_file), "swing": True,
                       "fallback": AXIS},
                      swing={"vertical_bat_angle": -30.0 * DEG})
    study = load_pitches(Study.from_dict(data))
    # The 2019 rows have no bat tracking: left out (no fallback for the swing).
    assert study.pitch_rows.summary["excluded"]["without bat_speed"] == \
        int((df.game_year == 2019).sum())
    inputs = study.sample_inputs(0, 300)
    cols = {name: inputs[i] for i, name in enumerate(COLUMNS)}
    real = df.iloc[study.pitch_identifiers(0, 300)["source_row"]]
    assert (real.game_year == 2024).all()
    assert np.array_equal(cols["bat_speed"], real["bat_speed"].to_numpy() * MPH)
    assert np.array_equal(cols["attack_angle"], real["attack_angle"].to_numpy() * DEG)
    assert np.array_equal(cols["attack_direction"],
                          real["attack_direction"].to_numpy() * DEG)


def test_a_fixed_handedness_overrides_the_rows(table_file):
    data = study_dict({"file": str(table_file), "fallback": AXIS},
                      handedness="L")
    study = load_pitches(Study.from_dict(data))
    inputs = study.sample_inputs(0, 200)
    assert np.all(inputs[COLUMNS.index("handedness")] == -1.0)
    assert study.config()["handedness"] == "L"
    assert study.config()["pitches"]["handedness"] == "study"


def test_the_config_holds_the_files_hash_and_the_filters(table_file, tmp_path):
    a = loaded(table_file, pitch_type="FF", fallback=AXIS)
    b = loaded(table_file, pitch_type=["FF", "SL"], fallback=AXIS)
    assert a.config_hash() != b.config_hash()
    import hashlib

    assert a.config()["pitches"]["sha256"] == hashlib.sha256(table_file.read_bytes()).hexdigest()
    changed = tmp_path / "tidy.parquet"
    tidy_table().iloc[:-1].to_parquet(changed)  # one row fewer: another file
    c = load_pitches(Study.from_dict(study_dict({"file": str(changed), "pitch_type": "FF",
                                                 "fallback": AXIS})))
    assert c.config()["pitches"]["file"] == a.config()["pitches"]["file"]
    assert c.config_hash() != a.config_hash()


def test_an_unloaded_study_says_how_to_load_it(table_file):
    study = Study.from_dict(study_dict({"file": str(table_file)}))
    with pytest.raises(RuntimeError, match="load_pitches"):
        study.sample_inputs(0, 10)


BAD = [
    ({"file": 3}, "pitches.file", "must be a file name"),
    ({"file": "x.parquet", "pitch_type": []}, "pitches.pitch_type", "empty list"),
    ({"file": "x.parquet", "p_throws": "S"}, "pitches.p_throws", '"R" or "L"'),
    ({"file": "x.parquet", "game_year": "2024"}, "pitches.game_year", "integer"),
    ({"file": "x.parquet", "pitcher": [1, 2.5]}, "pitches.pitcher[1]", "integer"),
    ({"file": "x.parquet", "stand": "R"}, "pitches.stand", "unknown key"),
    ({"file": "x.parquet", "swing": "yes"}, "pitches.swing", "true or false"),
    ({"file": "x.parquet", "fallback": {"bat_speed": 70}}, "pitches.fallback.bat_speed",
     "only with pitches.swing = true"),
    ({"file": "x.parquet", "fallback": {"speed": {"value": -1, "unit": "mph"}}},
     "pitches.fallback.speed.value", "pitch speed must be > 0"),
]


@pytest.mark.parametrize(("pitches", "field", "words"), BAD)
def test_bad_sections_name_the_key(pitches, field, words):
    with pytest.raises(InputError) as err:
        Study.from_dict(study_dict(pitches), source="s.toml")
    assert err.value.field == field and words in err.value.message


def test_a_drawn_key_in_pitch_or_swing_is_refused():
    data = study_dict({"file": "x.parquet"})
    data["pitch"]["spin_axis"] = 3.0
    with pytest.raises(InputError, match=r"pitch\.spin_axis: drawn from the rows of "
                                         r"\[pitches\].*\[pitches.fallback\]"):
        Study.from_dict(data)
    data = study_dict({"file": "x.parquet", "swing": True})
    with pytest.raises(InputError, match=r"swing\.bat_speed: drawn from the rows"):
        Study.from_dict(data)


def test_a_filter_selecting_no_row_is_named(table_file):
    with pytest.raises(InputError) as err:
        loaded(table_file, pitch_type="KN")
    assert err.value.field == "pitches.pitch_type"
    assert "selects no row of" in err.value.message and "'KN'" in err.value.message
    assert "FF" in err.value.message  # what the file has instead
    # Each filter selects rows, but not together: the one that empties it is named.
    df = tidy_table()
    pitcher = int(df.pitcher.iloc[0])
    others = sorted(set(df.batter) - set(df.batter[df.pitcher == pitcher]))
    if not others:  # (every batter faced him in this table: a batter he never faced)
        others = [1]
    with pytest.raises(InputError) as err:
        loaded(table_file, pitcher=pitcher, batter=others[0])
    assert err.value.field == "pitches.batter"
    assert "among the" in err.value.message


def test_no_row_left_says_which_fallback_would_help(tmp_path):
    df = tidy_table()
    df["spin_axis"] = np.nan  # a season without spin axes
    path = tmp_path / "t.parquet"
    df.to_parquet(path)
    with pytest.raises(InputError) as err:
        loaded(path)
    assert err.value.field == "pitches"
    assert "60 without spin_axis" in err.value.message
    assert "pitches.fallback.spin_axis" in err.value.message


def test_a_file_without_bat_tracking_drawn_with_its_swing_says_so(tmp_path):
    # A season before bat tracking, drawn with swing = true: the hint names the missing
    # bat tracking and the two ways out, not the fallback of a value a few rows lack.
    df = tidy_table()
    df[["bat_speed", "attack_angle", "attack_direction"]] = np.nan
    path = tmp_path / "t.parquet"
    df.to_parquet(path)
    data = study_dict({"file": str(path), "swing": True},
                      swing={"vertical_bat_angle": -30.0 * DEG})
    with pytest.raises(InputError) as err:
        load_pitches(Study.from_dict(data))
    assert err.value.field == "pitches"
    assert "56 without bat_speed" in err.value.message
    assert "no bat tracking" in err.value.message
    assert "pitches.swing = false" in err.value.message
    assert "pitches.fallback.spin_axis" not in err.value.message


def test_out_of_range_rows_are_left_out_and_counted(tmp_path):
    df = tidy_table()
    df.loc[10, "pitch_speed"] = -3.0
    df.loc[11, "vertical_approach_angle"] = 95.0
    path = tmp_path / "t.parquet"
    df.to_parquet(path)
    study = loaded(path, fallback=AXIS)
    assert study.pitch_rows.summary["excluded"] == {
        "pitch_speed out of range": 1, "vertical_approach_angle out of range": 1}
    assert not {10, 11} & set(study.pitch_identifiers(0, 5000)["source_row"])


def test_a_table_row_is_the_same_pitch_in_a_tidy_csv(table_file, tmp_path):
    csv = tmp_path / "tidy.csv"
    tidy_table().to_csv(csv, index=False)
    a = loaded(table_file, fallback=AXIS)
    b = loaded(csv, fallback=AXIS)
    assert np.array_equal(a.sample_inputs(0, 500), b.sample_inputs(0, 500))
    assert a.config()["pitches"]["sha256"] != b.config()["pitches"]["sha256"]

