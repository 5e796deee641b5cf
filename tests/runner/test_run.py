"""`mcbat run`: Parquet datasets that are identical whatever the threads, chunking or
interruption, match the single-impact API row by row, and refuse bad input cleanly."""

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest

import mcbat
from mcbat.api import Ball, Bat, Contact, ImpactCase, SolverSettings, solve
from mcbat.dataset import chunks as ds
from mcbat.dataset import schema, storage
from mcbat.runner import run_study
from mcbat.study import load_study

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "studies" / "example.toml"


def mcbat_cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "mcbat.cli", *map(str, args)],
                          capture_output=True, text=True, check=False, cwd=cwd)


@pytest.fixture(scope="module")
def study():
    return load_study(EXAMPLE)


@pytest.fixture(scope="module")
def baseline(study, tmp_path_factory):
    out = tmp_path_factory.mktemp("baseline") / "ds"
    run_study(study, out, samples=30_000, seed=11, threads=2, chunk_size=7_000,
              progress=False)
    return mcbat.load(out)


def _same_rows(a: pd.DataFrame, b: pd.DataFrame, ignore=()):
    cols = [c for c in schema.COLUMNS if c not in ignore]
    pd.testing.assert_frame_equal(a[cols].reset_index(drop=True),
                                  b[cols].reset_index(drop=True), check_exact=True)


def test_dataset_columns_and_metadata(baseline, study):
    assert list(baseline.columns) == list(schema.COLUMNS)
    assert len(baseline) == 30_000
    assert baseline["sample_id"].tolist() == list(range(30_000))
    assert (baseline["status"] == 0).mean() > 0.99
    directory = Path(baseline.attrs["directory"])
    names = sorted(p.name for p in directory.iterdir())
    assert names == [ds.MANIFEST] + [ds.chunk_name(k) for k in range(5)]
    meta = json.loads(pq.read_schema(directory / ds.chunk_name(0)).metadata[ds.METADATA_KEY])
    assert meta["seed"] == 11 and meta["samples"] == 30_000
    assert meta["config_hash"] == baseline.attrs["mcbat"]["config_hash"]
    assert meta["units"]["exit_speed"] == "m/s" and meta["units"]["scattering_angle"] == "deg"
    assert {"mcbat", "numba", "numpy", "pyarrow"} <= set(meta["versions"])
    assert meta["study"] == study.config()
    assert "[study]" in meta["study_toml"]
    assert meta["schema"] == schema.SCHEMA_VERSION
    # Every column is REQUIRED in the Parquet file (schema 6): no nulls anywhere, and a
    # failed row's outputs are NaN values.
    arrow_schema = pq.read_schema(directory / ds.chunk_name(0))
    assert not [field.name for field in arrow_schema if field.nullable]
    parquet_schema = pq.ParquetFile(directory / ds.chunk_name(0)).schema
    assert {parquet_schema.column(i).max_definition_level
            for i in range(len(parquet_schema))} == {0}
    # Derived columns agree with the outputs they come from.
    ok = baseline[baseline["status"] == 0]
    speed = np.sqrt(ok["ball_vx"] ** 2 + ok["ball_vy"] ** 2 + ok["ball_vz"] ** 2)
    assert np.allclose(ok["exit_speed"], speed, rtol=1e-15, atol=0)
    assert np.allclose(ok["scattering_angle"],
                       np.degrees(np.arctan2(ok["ball_vy"], ok["ball_vx"])), rtol=1e-15)
    assert (ok["spin_axial"] == ok["ball_wz"]).all()


def test_threads_do_not_change_the_data(study, tmp_path, baseline):
    out = tmp_path / "one-thread"
    run_study(study, out, samples=30_000, seed=11, threads=1, chunk_size=7_000,
              progress=False)
    _same_rows(mcbat.load(out), baseline)


def test_chunk_size_does_not_change_the_data(study, tmp_path, baseline):
    out = tmp_path / "chunks"
    run_study(study, out, samples=30_000, seed=11, threads=2, chunk_size=4_096,
              progress=False)
    other = mcbat.load(out)
    assert other["chunk"].max() == math.ceil(30_000 / 4_096) - 1
    # Only the bookkeeping column `chunk` says how rows were grouped into files.
    _same_rows(other, baseline, ignore=("chunk",))


def test_seed_changes_the_data(study, tmp_path, baseline):
    out = tmp_path / "seed"
    run_study(study, out, samples=30_000, seed=12, threads=2, chunk_size=7_000,
              progress=False)
    assert not np.array_equal(mcbat.load(out)["mu"], baseline["mu"])


def test_rows_match_the_single_impact_api(study, baseline):
    rng = np.random.default_rng(0)
    settings = SolverSettings(**study.solver)
    ok = baseline[baseline["status"] == 0]
    outputs = ("ball_vx", "ball_vy", "ball_vz", "ball_wx", "ball_wy", "ball_wz",
               "bat_vx", "bat_vy", "bat_vz", "bat_wx", "bat_wy", "bat_wz",
               "normal_impulse", "compression_impulse", "friction_work", "energy_out")
    for i in rng.choice(ok.index, size=40, replace=False):
        row = ok.loc[i]
        assert row["bat_slope"] == 0.0  # the example study's bat is a cylinder
        case = ImpactCase(
            ball=Ball(row["ball_mass"], row["ball_radius"], row["ball_inertia_factor"]),
            bat=Bat(row["bat_mass"], row["bat_transverse_inertia"], row["bat_axial_inertia"],
                    radius=row["bat_radius"]),
            contact=Contact(row["axial"], row["angle"]),
            ball_velocity=[row[f"ball_v{c}_in"] for c in "xyz"],
            ball_spin=[row[f"ball_w{c}_in"] for c in "xyz"],
            bat_velocity=[row[f"bat_v{c}_in"] for c in "xyz"],
            bat_spin=[row[f"bat_w{c}_in"] for c in "xyz"],
            mu=row["mu"], e=row["e"])
        result = solve(case, settings)
        got = {**{f"ball_v{c}": v for c, v in zip("xyz", result.ball_velocity)},
               **{f"ball_w{c}": v for c, v in zip("xyz", result.ball_spin)},
               **{f"bat_v{c}": v for c, v in zip("xyz", result.bat_velocity)},
               **{f"bat_w{c}": v for c, v in zip("xyz", result.bat_spin)},
               "normal_impulse": result.normal_impulse,
               "compression_impulse": result.compression_impulse,
               "friction_work": result.friction_work, "energy_out": result.energy_out}
        for name in outputs:
            assert got[name] == row[name], (i, name)
        assert (result.end_state == "stuck") == (row["end_state"] == 1)


def test_rerun_changes_nothing_and_other_config_is_refused(study, tmp_path):
    out = tmp_path / "ds"
    run_study(study, out, samples=5_000, seed=3, chunk_size=2_000, progress=False)
    stamps = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    summary = run_study(study, out, samples=5_000, seed=3, chunk_size=2_000, progress=False)
    assert summary.chunks_computed == 0 and summary.chunks_kept == 3
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == stamps
    proc = mcbat_cli("run", EXAMPLE, "--out", out, "--samples", 5_000, "--seed", 4,
                     "--chunk-size", 2_000, "--quiet")
    assert proc.returncode == 2
    assert "different study config, seed or sample count" in proc.stderr
    assert "--overwrite" in proc.stderr and "Traceback" not in proc.stderr
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == stamps
    proc = mcbat_cli("run", EXAMPLE, "--out", out, "--samples", 5_000, "--seed", 4,
                     "--chunk-size", 2_000, "--quiet", "--overwrite")
    assert proc.returncode == 0, proc.stderr
    assert mcbat.load(out).attrs["mcbat"]["seed"] == 4


def test_a_dataset_of_an_older_schema_is_refused_by_name(study, tmp_path):
    """A dataset written by an older mcbat (schema 5: OPTIONAL Parquet columns, which
    pyarrow does not concatenate with this version's REQUIRED ones) is not resumed, and
    the error says why."""
    out = tmp_path / "ds"
    run_study(study, out, samples=3_000, seed=3, chunk_size=2_000, progress=False)
    manifest = json.loads((out / ds.MANIFEST).read_text())
    manifest["schema"] = schema.SCHEMA_VERSION - 1
    manifest["config_hash"] = "0" * len(manifest["config_hash"])  # as an old run's would
    (out / ds.MANIFEST).write_text(json.dumps(manifest))
    stamps = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    proc = mcbat_cli("run", EXAMPLE, "--out", out, "--samples", 3_000, "--seed", 3,
                     "--chunk-size", 2_000, "--quiet")
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert f"schema version {schema.SCHEMA_VERSION - 1}" in proc.stderr
    assert "--overwrite" in proc.stderr
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == stamps


def test_foreign_directory_is_never_overwritten(study, tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("precious")
    for extra in ((), ("--overwrite",)):
        proc = mcbat_cli("run", EXAMPLE, "--out", out, "--samples", 100, "--quiet", *extra)
        assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert (out / "notes.txt").read_text() == "precious"
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]


def test_truncated_chunk_is_redone(study, tmp_path):
    out = tmp_path / "ds"
    run_study(study, out, samples=6_000, seed=5, chunk_size=2_000, progress=False)
    before = mcbat.load(out)
    victim = out / ds.chunk_name(1)
    victim.write_bytes(victim.read_bytes()[:1000])
    summary = run_study(study, out, samples=6_000, seed=5, chunk_size=2_000, progress=False)
    assert summary.chunks_computed == 1 and summary.chunks_kept == 2
    _same_rows(mcbat.load(out), before)


def test_sigkill_mid_run_then_resume_gives_identical_data(tmp_path):
    args = ["run", EXAMPLE, "--samples", 400_000, "--seed", 21, "--chunk-size", 20_000,
            "--threads", 1, "--quiet"]
    killed = tmp_path / "killed"
    proc = subprocess.Popen([sys.executable, "-m", "mcbat.cli", *map(str, args),
                             "--out", str(killed)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if killed.is_dir() and len(ds.chunk_files(killed)) >= 3:
            break
        time.sleep(0.02)
    assert proc.poll() is None, "the run finished before it could be killed"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    done_before = len(ds.chunk_files(killed))
    assert 3 <= done_before < 20
    # Kept: the chunks the manifest recorded before the kill. A file written but not yet
    # recorded (the kill fell in between) is recomputed, and the run says so.
    recorded = set(ds.read_manifest(killed)["files"])
    unrecorded = {p.name for p in ds.chunk_files(killed).values()} - recorded
    assert 1 <= len(recorded) <= done_before  # records: the first chunk, then every second
    resumed = mcbat_cli(*args, "--out", killed)
    assert resumed.returncode == 0, resumed.stderr
    assert f"({20 - len(recorded)} computed, {len(recorded)} kept from before)" \
        in resumed.stdout
    for name in unrecorded:
        assert f"recomputed {name}: not recorded in the manifest" in resumed.stdout
    clean = tmp_path / "clean"
    assert mcbat_cli(*args, "--out", clean).returncode == 0
    assert not list(killed.glob(".*tmp"))
    _same_rows(mcbat.load(killed), mcbat.load(clean))


BAD_STUDIES = {
    "unknown key": ("[study]\nname='x'\nsamples=10\nseed=1\ncolour='red'\n", "study.colour"),
    "bad distribution": ("[friction]\nmu = { dist = 'gaussian', mean = 0.5, std = 0.1 }\n",
                         "friction.mu"),
    "mu out of range": ("[friction]\nmu = -0.5\n", "friction.mu"),
    "e out of range": ("[restitution]\ne = 1.5\n", "restitution.e"),
}


@pytest.mark.parametrize("name", list(BAD_STUDIES))
def test_bad_study_exits_2_names_the_key_and_writes_nothing(name, tmp_path):
    text, key = BAD_STUDIES[name]
    good = EXAMPLE.read_text()
    section = text.split("]")[0] + "]"
    # Replace the section of the good study with the bad one.
    lines, skip = [], False
    for line in good.splitlines():
        if line.strip().startswith("["):
            skip = line.strip() == section
            if skip:
                lines.append(text)
                continue
        if not skip:
            lines.append(line)
    bad = tmp_path / "bad.toml"
    bad.write_text("\n".join(lines) + "\n")
    out = tmp_path / "out"
    proc = mcbat_cli("run", bad, "--out", out, "--quiet")
    assert proc.returncode == 2, proc.stderr
    assert key in proc.stderr and "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert not out.exists()


def test_load_rejects_a_non_dataset(tmp_path):
    with pytest.raises(mcbat.errors.InputError, match="not an mcbat dataset"):
        mcbat.load(tmp_path)


def test_binned_quantiles_match_a_direct_computation(baseline):
    band = mcbat.stats.analysis.binned(baseline, "scattering_angle", "exit_speed", bins=8)
    ok = baseline[baseline["status"] == 0]
    assert band["count"].sum() == len(ok)
    edges = np.linspace(ok["scattering_angle"].min(), ok["scattering_angle"].max(), 9)
    row = band.iloc[3]
    assert row["x_low"] == pytest.approx(edges[3]) and row["x_high"] == pytest.approx(edges[4])
    inside = ok[(ok["scattering_angle"] > edges[3]) & (ok["scattering_angle"] <= edges[4])]
    assert row["count"] == len(inside)
    assert row["q50"] == pytest.approx(inside["exit_speed"].median())
    assert row["q16"] == pytest.approx(inside["exit_speed"].quantile(0.16))
    assert row["q16"] <= row["q50"] <= row["q84"]


def test_end_state_fractions(baseline):
    overall = mcbat.stats.analysis.end_state_fractions(baseline)
    assert overall["fraction"].sum() == pytest.approx(1.0)
    ok = baseline[baseline["status"] == 0]
    assert overall.loc["stuck", "fraction"] == pytest.approx((ok["end_state"] == 1).mean())
    by_spin = mcbat.stats.analysis.end_state_fractions(baseline, by="ball_wz_in")
    assert sorted(by_spin.index) == [-72.0, 0.0, 79.0]
    assert np.allclose(by_spin.sum(axis=1), 1.0)


def test_progress_bar_shows_impacts_per_second(tmp_path):
    proc = mcbat_cli("run", EXAMPLE, "--out", tmp_path / "p", "--samples", 2_000)
    assert proc.returncode == 0, proc.stderr
    assert "impacts/s" in proc.stderr
    assert "rows: 2,000" in proc.stdout and str(tmp_path / "p") in proc.stdout


def test_measurement_noise_goes_to_separate_columns(tmp_path):
    study = load_study(ROOT / "studies" / "cross_nathan_2006.toml")
    runs = []
    for chunk_size in (3_000, 4_096):
        out = tmp_path / f"noise{chunk_size}"
        run_study(study, out, samples=12_000, chunk_size=chunk_size, progress=False)
        runs.append(mcbat.load(out))
    a, b = runs
    measured = ["exit_speed_measured", "scattering_angle_measured", "spin_axial_measured"]
    assert list(a.columns) == list(schema.COLUMNS) + measured
    pd.testing.assert_frame_equal(a.drop(columns="chunk"), b.drop(columns="chunk"),
                                  check_exact=True)
    ok = a[a["status"] == 0]
    # The model values are untouched; the errors have the study's spreads.
    speed = np.sqrt(ok["ball_vx"] ** 2 + ok["ball_vy"] ** 2 + ok["ball_vz"] ** 2)
    assert np.array_equal(ok["exit_speed"], speed)
    for name, std in (("exit_speed", 0.03), ("scattering_angle", 1.5), ("spin_axial", 3.0)):
        error = ok[f"{name}_measured"] - ok[name]
        assert abs(error.mean()) < 4 * std / np.sqrt(len(ok))
        assert error.std() == pytest.approx(std, rel=0.03)


@pytest.mark.parametrize("flag, value, words", [
    ("--samples", "abc", "--samples must be an integer"),
    ("--samples", "0", "--samples: must be an integer >= 1"),
    ("--threads", "0", "--threads: must be an integer >= 1"),
    ("--threads", "64", "--threads: at most"),
    ("--seed", "-1", "--seed: must be an integer >= 0"),
    ("--chunk-size", "0", "--chunk-size: must be an integer >= 1"),
])
def test_bad_flags_exit_2_and_write_nothing(tmp_path, flag, value, words):
    out = tmp_path / "out"
    proc = mcbat_cli("run", EXAMPLE, "--out", out, flag, value, "--quiet")
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1 and words in proc.stderr
    assert "Traceback" not in proc.stderr and not out.exists()


@pytest.mark.parametrize("scheme", ["memory", "local"])
def test_url_output_with_the_local_engine(study, tmp_path, baseline, scheme):
    # memory:// is an fsspec-only file system (wrapped with pyarrow.fs.FSSpecHandler);
    # local:// is one of pyarrow's own (LocalFileSystem), like s3:// or gs://.
    if scheme == "memory":
        pytest.importorskip("fsspec")
    url = (f"memory://mcbat-test-{tmp_path.name}/ds" if scheme == "memory"
           else f"local://{tmp_path / 'ds'}")
    summary = run_study(study, url, samples=30_000, seed=11, threads=2, chunk_size=7_000,
                        progress=False)
    assert str(summary.directory) == url and summary.chunks_computed == 5
    _same_rows(mcbat.load(url), baseline)
    assert sorted(storage.list_names(url)) == [ds.MANIFEST] + [ds.chunk_name(k) for k in range(5)]
    # Resume works the same: a truncated chunk is redone, the others kept.
    victim = storage.join(url, ds.chunk_name(2))
    fs, path = storage.resolve(victim)
    with fs.open_input_stream(path) as handle:
        head = handle.read(1000)
    with fs.open_output_stream(path) as handle:
        handle.write(head)
    summary = run_study(study, url, samples=30_000, seed=11, chunk_size=7_000,
                        progress=False)
    assert (summary.chunks_computed, summary.chunks_kept) == (1, 4)
    _same_rows(mcbat.load(url), baseline)
    assert sorted(storage.list_names(url)) == [ds.MANIFEST] + [ds.chunk_name(k) for k in range(5)]


def test_unknown_url_scheme_is_a_clear_error(tmp_path):
    proc = mcbat_cli("run", EXAMPLE, "--out", "nosuchscheme://bucket/ds", "--samples", 100,
                     "--quiet")
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mcbat: error: nosuchscheme://bucket/ds: "
                                                   "--out: ")
