"""`mcbat run` of a study with real pitches ([pitches], studies/real_pitches.toml, on the
real Statcast rows of data/statcast_2020-09-03.csv): the same data whatever the threads,
chunking or resumption (the Dask engine: tests/runner/test_dask.py); every row traces to
its pitch in the file; a changed file is never resumed into the old dataset; bad files and
empty filters are one-line errors, exit 2, with nothing written."""

import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mcbat
from mcbat.dataset import chunks as ds
from mcbat.dataset.schema import GAME_COLUMNS, PITCH_SOURCE_COLUMNS
from mcbat.runner import run_study
from mcbat.statcast import read

ROOT = Path(__file__).resolve().parents[2]
STUDY = ROOT / "studies" / "real_pitches.toml"
DATA = ROOT / "data" / "statcast_2020-09-03.csv"


@pytest.fixture
def mcbat_cli(cli):
    """``mcbat ARGS`` in this process (tests/cli_runner.py): the exit code, output and files
    these tests check are the command's, which an interpreter of its own would not change."""
    return cli


def same_rows(a, b, ignore=()):
    cols = [c for c in a.columns if c not in ignore]
    pd.testing.assert_frame_equal(a[cols].reset_index(drop=True),
                                  b[cols].reset_index(drop=True), check_exact=True)


@pytest.fixture(scope="module")
def baseline(tmp_path_factory):
    out = tmp_path_factory.mktemp("real") / "ds"
    run_study(mcbat.load_study(STUDY), out, samples=6_000, seed=7, threads=2,
              chunk_size=1_500, progress=False)
    return mcbat.load(out)


def copy_study(tmp_path, data_name="pitches.csv", text=None):
    """The example study and a copy of its file in ``tmp_path``."""
    study = tmp_path / "real.toml"
    study.write_text(STUDY.read_text().replace("../data/statcast_2020-09-03.csv",
                                               data_name))
    shutil.copy(DATA, tmp_path / data_name)
    return study


def test_columns_and_identifiers(baseline):
    assert list(baseline.columns) == [*GAME_COLUMNS, *PITCH_SOURCE_COLUMNS]
    for name in PITCH_SOURCE_COLUMNS:
        assert baseline[name].dtype == np.int64
    assert (baseline["status"] == 0).all()
    config = baseline.attrs["mcbat"]["study"]["pitches"]
    assert config["file"] == DATA.name and config["rows_in_file"] == 2507
    assert config["filters"] == {"pitch_type": ["FF", "SI"], "p_throws": ["R"]}


def test_every_row_traces_to_its_real_pitch(baseline):
    # The raw export, read with plain pandas (not mcbat's readers): row source_row of the
    # file is the pitch the identifiers name.
    raw = pd.read_csv(DATA, na_values=["null"], low_memory=False)
    real = raw.iloc[baseline["source_row"].to_numpy()]
    for name in ("game_pk", "at_bat_number", "pitch_number", "pitcher", "batter"):
        assert np.array_equal(real[name].to_numpy(np.int64), baseline[name].to_numpy()), name
    assert set(real["pitch_type"]) <= {"FF", "SI"} and set(real["p_throws"]) == {"R"}
    # ... and that pitch's values are the simulated inputs, in Statcast's units: the plate
    # speed (the reader's mph, from Savant's release state), the approach angle (deg), the
    # release spin rate (rpm); the batter's side. The kernel took each in SI, one
    # multiplication of the file's value, and the dataset divides it back.
    tidy = read(DATA).iloc[baseline["source_row"].to_numpy()]
    assert baseline.attrs["units"]["pitch_speed"] == "mph"
    assert np.allclose(baseline["pitch_speed"], tidy["pitch_speed"], rtol=3e-16, atol=0)
    assert np.allclose(baseline["pitch_vertical_approach_angle"],
                       tidy["vertical_approach_angle"], rtol=1e-15, atol=1e-13)
    assert np.allclose(baseline["pitch_spin_rate"], real["release_spin_rate"], rtol=1e-14,
                       atol=0)
    assert np.array_equal(baseline["handedness"].to_numpy(),
                          np.where(real["stand"] == "R", 1.0, -1.0))
    # The file has no spin axis: the fallback's range, 195-240 deg.
    axis = baseline["pitch_spin_axis"]
    assert axis.min() >= 195 - 1e-9 and axis.max() <= 240 + 1e-9
    # Resampled with replacement from every selected pitch.
    selected = ((raw["pitch_type"].isin(["FF", "SI"])) & (raw["p_throws"] == "R")).sum()
    assert baseline.attrs["mcbat"]["study"]["pitches"]["drawn_from"] == selected
    assert 0.9 * selected < baseline["source_row"].nunique() <= selected


def test_threads_do_not_change_the_data(baseline, tmp_path):
    run_study(mcbat.load_study(STUDY), tmp_path / "ds", samples=6_000, seed=7, threads=1,
              chunk_size=1_500, progress=False)
    same_rows(mcbat.load(tmp_path / "ds"), baseline)


def test_chunk_size_does_not_change_the_data(baseline, tmp_path):
    run_study(mcbat.load_study(STUDY), tmp_path / "ds", samples=6_000, seed=7, threads=2,
              chunk_size=1_024, progress=False)
    other = mcbat.load(tmp_path / "ds")
    assert other["chunk"].max() == 5
    same_rows(other, baseline, ignore=("chunk",))


def test_seed_changes_the_pitches(baseline, tmp_path):
    run_study(mcbat.load_study(STUDY), tmp_path / "ds", samples=6_000, seed=8,
              chunk_size=1_500, progress=False)
    assert not np.array_equal(mcbat.load(tmp_path / "ds")["source_row"],
                              baseline["source_row"])


def test_resumption_recomputes_the_missing_chunks_identically(baseline, tmp_path, mcbat_cli):
    study = copy_study(tmp_path, DATA.name)
    out = tmp_path / "ds"
    args = ("run", study, "--out", out, "--samples", 6_000, "--seed", 7, "--chunk-size",
            1_500, "--quiet")
    assert mcbat_cli(*args).returncode == 0
    (out / ds.chunk_name(2)).unlink()
    kept = {k: p.stat().st_mtime_ns for k, p in ds.chunk_files(out).items()}
    proc = mcbat_cli(*args)
    assert proc.returncode == 0, proc.stderr
    assert "(1 computed, 3 kept from before)" in proc.stdout
    assert all(ds.chunk_files(out)[k].stat().st_mtime_ns == t for k, t in kept.items())
    same_rows(mcbat.load(out), baseline)


def test_a_changed_file_is_not_resumed_into_the_old_dataset(tmp_path, mcbat_cli):
    study = copy_study(tmp_path)
    out = tmp_path / "ds"
    args = ("run", study, "--out", out, "--samples", 2_000, "--seed", 7, "--quiet")
    assert mcbat_cli(*args).returncode == 0
    stamps = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    data = tmp_path / "pitches.csv"
    lines = data.read_text(encoding="utf-8").splitlines(keepends=True)
    data.write_text("".join(lines[:-1]), encoding="utf-8")  # one pitch fewer
    proc = mcbat_cli(*args)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "different study config" in proc.stderr and "--overwrite" in proc.stderr
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == stamps
    # A file gone: one line, and the dataset on disk is left as it was (even with
    # --overwrite: the file is read before the directory is touched).
    moved = data.rename(tmp_path / "elsewhere.csv")
    line = one_line_exit_2(mcbat_cli(*args, "--overwrite"))
    assert "pitches.file: cannot read pitches.csv" in line
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == stamps
    moved.rename(data)
    proc = mcbat_cli(*args, "--overwrite")
    assert proc.returncode == 0, proc.stderr
    manifest = json.loads((out / ds.MANIFEST).read_text())
    assert manifest["study"]["pitches"]["rows_in_file"] == 2506


def one_line_exit_2(proc):
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    return lines[0]


def test_a_filter_selecting_no_row_exits_2_naming_it(tmp_path, mcbat_cli):
    study = copy_study(tmp_path)
    study.write_text(study.read_text().replace('p_throws = "R"', 'p_throws = "R"\n'
                                               "pitcher = 1"))
    line = one_line_exit_2(mcbat_cli("run", study, "--out", tmp_path / "ds", "--quiet"))
    assert "pitches.pitcher: selects no row of pitches.csv: no pitcher = 1" in line
    assert str(study) in line
    assert not (tmp_path / "ds").exists()


@pytest.mark.parametrize("case", ["missing", "columns", "truncated", "not a table",
                                  "empty"])
def test_bad_files_exit_2_with_one_line_and_write_nothing(tmp_path, mcbat_cli, case):
    study = copy_study(tmp_path)
    data = tmp_path / "pitches.csv"
    text = data.read_text(encoding="utf-8")
    if case == "missing":
        data.unlink()
        words = "pitches.file: cannot read pitches.csv: No such file or directory"
    elif case == "columns":  # a Savant export without its identifiers
        frame = pd.read_csv(DATA, dtype=str, keep_default_na=False)
        frame.drop(columns=["game_pk"]).to_csv(data, index=False)
        words = "missing column game_pk"
    elif case == "truncated":  # a download cut in the middle of a row
        data.write_text(text[: len(text) // 2], encoding="utf-8")
        words = "truncated or malformed"
    elif case == "not a table":
        data.write_bytes(b"PAR1 this is not parquet")
        words = "not a readable Parquet file"
    else:
        data.write_bytes(b"")
        words = "pitches.file"
    out = tmp_path / "ds"
    line = one_line_exit_2(mcbat_cli("run", study, "--out", out, "--quiet"))
    assert line.startswith(f"mcbat: error: {study}: pitches.file: "), line
    assert words in line
    assert not out.exists()


def test_a_tidy_parquet_file_gives_the_same_rows_as_the_savant_csv(baseline, tmp_path):
    # The tidy table the Savant reader writes (mcbat.statcast.write), in place of the CSV.
    from mcbat.statcast import write

    write(read(DATA), tmp_path / "pitches.parquet")
    study = copy_study(tmp_path, "pitches.csv")
    study.write_text(study.read_text().replace("pitches.csv", "pitches.parquet"))
    run_study(mcbat.load_study(study), tmp_path / "ds", samples=6_000, seed=7,
              chunk_size=1_500, progress=False)
    other = mcbat.load(tmp_path / "ds")
    inputs = [c for c in GAME_COLUMNS if c not in ("sample_id", "chunk")]
    same_rows(other[inputs + list(PITCH_SOURCE_COLUMNS)],
              baseline[inputs + list(PITCH_SOURCE_COLUMNS)])
    assert other.attrs["mcbat"]["config_hash"] != baseline.attrs["mcbat"]["config_hash"]


def test_calibrate_and_synth_read_the_pitches_file(tmp_path, mcbat_cli):
    # The commands that sample a study outside `mcbat run` load its [pitches] rows too.
    proc = mcbat_cli("calibrate", "--study", STUDY, "--target", 100, "--parameter", "e",
                     "--samples", 1000)
    assert proc.returncode == 0, proc.stderr
    result = json.loads(proc.stdout)
    assert abs(result["achieved"] - 100) < 1e-6 and 0 < result["value"] < 1
    out = tmp_path / "synth.csv"
    proc = mcbat_cli("synth", "--study", STUDY, "--rows", 40, "--seed", 1, "--out", out)
    assert proc.returncode == 0, proc.stderr
    table = pd.read_csv(out)
    # Its pitch speeds are the real plate speeds of the selected rows (mph).
    tidy = read(DATA)
    speeds = tidy.loc[tidy.pitch_type.isin(["FF", "SI"]) & (tidy.p_throws == "R"),
                      "pitch_speed"].to_numpy()
    assert np.isin(np.round(table["pitch_speed"].to_numpy(), 6), np.round(speeds, 6)).all()
