"""Faults injected into datasets and runs: partial or corrupt data is never reported as
complete, nothing the run did not write is deleted, every spelling of a directory shares
one lock, and the closing report reads the chunks under it and one at a time."""

import os
import shutil
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import mcbat
from mcbat.dataset import chunks as ds
from mcbat.dataset.lock import dataset_lock
from mcbat.errors import InputError
from mcbat.runner import run_study, study_run
from mcbat.study import load_study

ROOT = Path(__file__).resolve().parents[2]
THROUGHPUT = ROOT / "studies" / "throughput.toml"
EXAMPLE = ROOT / "studies" / "example.toml"
GAME = ROOT / "studies" / "game_fastball.toml"
SUMMARY = """
[summary]
by = { from_barrel_end = { bins = 4, low = 0, high = 40, unit = "cm" } }
columns = ["exit_speed"]
quantiles = [0.5]
"""
SAMPLES, CHUNK = 10_000, 2_000


def _cli(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "mcbat", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, check=False)


def _summary_study(tmp_path):
    path = tmp_path / "summary.toml"
    path.write_text(THROUGHPUT.read_text() + SUMMARY)
    return load_study(path)


def _run(study, out, seed=3, **kw):
    return run_study(study, out, samples=SAMPLES, seed=seed, chunk_size=CHUNK,
                     progress=False, **kw)


def _flip_middle(path, n=64):
    data = bytearray(path.read_bytes())
    middle = len(data) // 2
    for i in range(n):
        data[middle + i] ^= 0xFF
    path.write_bytes(bytes(data))


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    """A complete 5-chunk impact dataset, and its rows."""
    out = tmp_path_factory.mktemp("clean") / "ds"
    _run(load_study(EXAMPLE), out)
    return out, mcbat.load(out)


@pytest.fixture
def copy(clean, tmp_path):
    out = tmp_path / "ds"
    shutil.copytree(clean[0], out)
    return out


def test_a_summary_only_rerun_never_hides_missing_chunks(tmp_path):
    study = _summary_study(tmp_path)
    out = tmp_path / "ds"
    _run(study, out)
    for k in (3, 4):
        (out / ds.chunk_name(k)).unlink()
    # Storing no rows is another dataset on disk: the rerun is refused, not folded in.
    with pytest.raises(InputError, match="summary-only"):
        _run(study, out, summary_only=True)
    result = mcbat.check(out)
    assert not result.ok and result.missing == [3, 4]
    with pytest.raises(InputError, match=r"2 of 5 chunk\(s\) missing"):
        mcbat.load(out)
    # A manifest that already says "summary-only" over the records of a run that stored
    # its rows (what the rerun used to write) still owes every row.
    manifest = ds.read_manifest(out)
    manifest["summary_only"] = True
    ds.write_manifest(out, manifest)
    result = mcbat.check(out)
    assert not result.ok and result.missing == [3, 4]
    proc = _cli("check", out)
    assert proc.returncode == 2 and "6,000 of 10,000 rows" in proc.stdout
    with pytest.raises(InputError, match="missing"):
        mcbat.load(out)


def test_a_manifest_without_checksums_is_unverified_and_a_rerun_records_them(copy, clean):
    manifest = ds.read_manifest(copy)
    del manifest["files"]  # the format of an older mcbat
    ds.write_manifest(copy, manifest)
    _flip_middle(copy / ds.chunk_name(1))
    result = mcbat.check(copy)
    report = "\n".join(result.lines())
    assert result.unverified and "CRC-32 of every byte" not in report
    assert "unverified" in report and "ok: complete" not in report
    assert _cli("check", copy).returncode == 2
    with pytest.warns(UserWarning, match="unverified"):
        mcbat.load(copy)
    summary = _run(load_study(EXAMPLE), copy)
    assert summary.chunks_computed == 5  # nothing without a record is trusted
    assert sorted(ds.read_manifest(copy)["files"]) == [ds.chunk_name(k) for k in range(5)]
    result = mcbat.check(copy)
    assert result.ok and not result.unverified
    assert mcbat.load(copy).equals(clean[1])


@pytest.mark.parametrize("files", [[], None, "x"], ids=["list", "null", "string"])
def test_an_unusable_files_record_is_a_clear_error_or_unverified(copy, files):
    manifest = ds.read_manifest(copy)
    manifest["files"] = files
    ds.write_manifest(copy, manifest)
    proc = _cli("check", copy)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    assert "ok: complete" not in proc.stdout
    # a rerun trusts no chunk without a record, recomputes and records them all
    proc = _cli("run", EXAMPLE, "--out", copy, "--samples", SAMPLES, "--seed", 3,
                "--chunk-size", CHUNK, "--quiet")
    assert proc.returncode == 0, proc.stderr
    assert mcbat.check(copy).ok


def test_a_deeply_nested_manifest_is_a_clear_error(copy):
    (copy / ds.MANIFEST).write_text("[" * 100_000 + "]" * 100_000)
    proc = _cli("check", copy)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr and len(proc.stderr.strip().splitlines()) == 1


def test_a_foreign_parquet_file_fails_check_and_is_left_alone(copy):
    foreign = copy / "chunk-000002 (copy).parquet"
    shutil.copy(copy / ds.chunk_name(2), foreign)
    result = mcbat.check(copy)
    assert not result.ok and result.foreign == [foreign.name]
    proc = _cli("check", copy)
    assert proc.returncode == 2 and foreign.name in proc.stdout
    with pytest.raises(InputError, match=r"\(copy\)"):
        mcbat.load(copy)
    with pytest.raises(InputError, match=r"\(copy\)"):
        _run(load_study(EXAMPLE), copy)
    assert foreign.read_bytes() == (copy / ds.chunk_name(2)).read_bytes()


def test_a_directory_named_like_a_chunk_is_never_deleted(copy):
    beyond = copy / "chunk-000009.parquet"
    beyond.mkdir()
    (beyond / "notes.txt").write_text("mine")
    assert not mcbat.check(copy).ok
    with pytest.raises(InputError, match="chunk-000009.parquet"):
        _run(load_study(EXAMPLE), copy)
    assert (beyond / "notes.txt").read_text() == "mine"
    shutil.rmtree(beyond)
    (copy / ds.chunk_name(2)).unlink()  # in range: where the run would write its chunk
    (copy / ds.chunk_name(2)).mkdir()
    (copy / ds.chunk_name(2) / "notes.txt").write_text("mine too")
    with pytest.raises(InputError, match=ds.chunk_name(2)):
        _run(load_study(EXAMPLE), copy)
    assert (copy / ds.chunk_name(2) / "notes.txt").read_text() == "mine too"


def test_a_stray_chunk_of_another_dataset_is_not_deleted(copy, tmp_path):
    other = tmp_path / "other"
    run_study(load_study(EXAMPLE), other, samples=2_000, seed=99, chunk_size=2_000,
              progress=False)
    stray = copy / ds.chunk_name(7)
    shutil.copy(other / ds.chunk_name(0), stray)
    with pytest.raises(InputError, match=ds.chunk_name(7)):
        _run(load_study(EXAMPLE), copy)
    assert stray.read_bytes() == (other / ds.chunk_name(0)).read_bytes()


@pytest.mark.parametrize("form", ["local://{abs}", "file://{abs}", "file:{abs}",
                                  "file://localhost{abs}", "{rel}", "{abs}/./"])
def test_every_spelling_of_a_directory_takes_its_one_lock(tmp_path, monkeypatch, form):
    out = tmp_path / "ds"
    monkeypatch.chdir(tmp_path)
    with dataset_lock(out):
        with pytest.raises(InputError, match="another mcbat run is writing"):
            run_study(load_study(EXAMPLE), form.format(abs=out, rel="ds"), samples=1_000,
                      seed=9, overwrite=True, progress=False)
    assert not (tmp_path / "file:").exists()


def test_a_second_writer_through_a_local_url_is_refused(tmp_path):
    """Real processes: the first run holds the lock of the plain path, the second comes
    through ``local://`` with another seed and ``--overwrite``."""
    out = tmp_path / "ds"
    first = subprocess.Popen([sys.executable, "-m", "mcbat", "run", str(THROUGHPUT), "--out",
                              str(out), "--samples", "1200000", "--chunk-size", "100000",
                              "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, cwd=ROOT)
    try:
        lock = out / "_mcbat.lock"
        # The first run takes the lock only once it has started (imports, a numba cache
        # load or compile): on a loaded machine that took over a minute, and a second run
        # started before it took the lock itself. Wait for the lock, however long.
        for _ in range(6000):
            if lock.exists() and f"pid {first.pid} " in lock.read_text():
                break
            assert first.poll() is None, first.communicate()
            time.sleep(0.05)
        else:
            pytest.fail("the first run did not take the lock within 5 minutes")
        second = _cli("run", THROUGHPUT, "--out", f"local://{out}", "--samples", "5000",
                      "--seed", "4", "--overwrite", "--quiet")
        assert second.returncode == 2 and "another mcbat run" in second.stderr
    finally:
        stdout, stderr = first.communicate(timeout=300)
    assert first.returncode == 0, stderr
    assert mcbat.check(out).ok and len(mcbat.load(out, columns=["sample_id"])) == 1_200_000


def test_the_closing_report_is_read_under_the_lock(tmp_path, monkeypatch):
    seen = []
    report = study_run.batted_ball_summary

    def probe(out, **kw):
        try:
            with dataset_lock(Path(out)):
                seen.append("free")
        except InputError:
            seen.append("held")
        return report(out, **kw)

    monkeypatch.setattr(study_run, "batted_ball_summary", probe)
    summary = run_study(load_study(GAME), tmp_path / "g", samples=2_000, chunk_size=1_000,
                        progress=False)
    assert seen == ["held"] and summary.batted_ball is not None


def _report_peak(out):
    """The report of a dataset, and the peak of the memory numpy allocated for it."""
    tracemalloc.start()
    try:
        got = study_run.batted_ball_summary(out, flight=True)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return got, peak


def test_the_closing_report_reads_one_chunk_at_a_time(tmp_path):
    small, out = tmp_path / "small", tmp_path / "g"
    run_study(load_study(GAME), small, samples=8_000, chunk_size=4_000, progress=False)
    run_study(load_study(GAME), out, samples=40_000, chunk_size=4_000, progress=False)
    _, peak_small = _report_peak(small)
    got, peak = _report_peak(out)
    # Five times the rows, the same memory (the columns of all rows: 5x).
    assert peak < 1.3 * peak_small, (peak, peak_small)
    df = mcbat.load(out)
    ok = df["status"] == 0
    for name in ("launch_speed", "launch_angle", "backspin", "hit_distance", "hang_time"):
        values = df.loc[ok, name].to_numpy()
        want = np.percentile(values[np.isfinite(values)], [50, 5, 95])
        np.testing.assert_allclose(got[name], want, rtol=1e-14, atol=0)
    sweet = ok & ((df["from_barrel_end"] - 0.1524).abs() <= 0.0127) \
        & (df["undercut"].abs() <= 0.00635)
    median, n = got["collision_efficiency_sweet_spot"]
    assert n == int(sweet.sum()) > 0
    assert median == pytest.approx(np.median(df.loc[sweet, "collision_efficiency"]),
                                   rel=1e-14)


def test_a_relative_directory_with_a_colon_is_a_plain_directory(tmp_path):
    proc = _cli("run", EXAMPLE, "--out", "run:1", "--samples", 2_000, "--chunk-size",
                1_000, "--quiet", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "run:1" / ds.MANIFEST).is_file()
    proc = _cli("check", "run:1", cwd=tmp_path)
    assert proc.returncode == 0 and "ok: complete" in proc.stdout, proc.stdout
    assert len(mcbat.load(tmp_path / "run:1")) == 2_000
    proc = _cli("run", GAME, "--out", "game:1", "--samples", 2_000, "--quiet", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "batted ball" in proc.stdout


def test_file_urls_with_one_slash_are_absolute_paths(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "abs"
    proc = _cli("run", EXAMPLE, "--out", f"file:{out}", "--samples", 1_000, "--quiet",
                cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (out / ds.MANIFEST).is_file() and not (tmp_path / "file:").exists()


def test_a_damaged_summary_of_the_same_size_is_rewritten(tmp_path):
    study = _summary_study(tmp_path)
    out = tmp_path / "ds"
    _run(study, out, summary_only=True)
    table = out / "_summary.parquet"
    good = table.read_bytes()
    _flip_middle(table, 16)
    assert len(table.read_bytes()) == len(good)
    assert _cli("check", out).returncode == 2
    _run(study, out, summary_only=True)
    assert table.read_bytes() == good
    assert mcbat.check(out).ok


def test_a_chunk_copied_in_with_its_record_from_another_dataset_is_recomputed(copy, clean,
                                                                              tmp_path):
    other = tmp_path / "other"
    _run(load_study(EXAMPLE), other, seed=4)
    shutil.copy(other / ds.chunk_name(1), copy / ds.chunk_name(1))
    manifest = ds.read_manifest(copy)
    manifest["files"][ds.chunk_name(1)] = ds.read_manifest(other)["files"][ds.chunk_name(1)]
    ds.write_manifest(copy, manifest)
    assert not mcbat.check(copy).ok
    summary = _run(load_study(EXAMPLE), copy)
    assert [k for k, _ in summary.redone] == [1]
    assert mcbat.load(copy).equals(clean[1])


def test_a_huge_description_is_refused_before_anything_is_written(tmp_path):
    study = tmp_path / "big.toml"
    text = EXAMPLE.read_text()
    head, _, rest = text.partition("[study]\n")
    study.write_text(head + "[study]\ndescription = \"" + "x" * 200_000 + "\"\n"
                     + "\n".join(line for line in rest.splitlines()
                                 if not line.startswith("description")) + "\n")
    proc = _cli("run", study, "--out", tmp_path / "ds", "--samples", 1_000, "--quiet")
    assert proc.returncode == 2, proc.stderr
    assert "study.description" in proc.stderr and not (tmp_path / "ds").exists()


def test_a_60_megabyte_description_is_refused_by_the_file_size(tmp_path, capsys):
    from mcbat.cli import main

    study = tmp_path / "big.toml"
    text = EXAMPLE.read_text()
    head, _, rest = text.partition("[study]\n")
    with open(study, "w") as handle:
        handle.write(head + "[study]\ndescription = \"")
        for _ in range(60):
            handle.write("x" * 1_000_000)
        handle.write("\"\n" + "\n".join(line for line in rest.splitlines()
                                         if not line.startswith("description")) + "\n")
    code = main(["run", str(study), "--out", str(tmp_path / "ds"), "--samples", "100",
                 "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "a study file is at most 1,048,576 bytes" in err and str(study) in err
    assert not (tmp_path / "ds").exists()


@pytest.mark.parametrize("char", ["\u0085", "\u2028", "\u202e", "\u200b"])
def test_study_names_with_unicode_controls_are_refused(tmp_path, char):
    study = tmp_path / "u.toml"
    study.write_text(EXAMPLE.read_text().replace('name = "example"',
                                                 f'name = "ex{char}ample"'))
    proc = _cli("run", study, "--samples", 100, "--quiet", cwd=tmp_path)
    assert proc.returncode == 2 and "study.name" in proc.stderr, proc.stderr
    assert not (tmp_path / "results").exists()


def test_an_empty_out_is_refused(tmp_path):
    proc = _cli("run", EXAMPLE, "--out", "", "--samples", 100, "--quiet", cwd=tmp_path)
    assert proc.returncode == 2 and "--out" in proc.stderr
    assert not (tmp_path / "results").exists()


@pytest.mark.parametrize("url", ["dir:///x", "data://x", "reference://x"])
def test_urls_that_are_not_storage_are_refused(tmp_path, url):
    proc = _cli("run", EXAMPLE, "--out", url, "--samples", 100, "--quiet", cwd=tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert "--out" in proc.stderr and "Traceback" not in proc.stderr


def test_a_url_scheme_missing_a_package_names_it(tmp_path):
    pytest.importorskip("fsspec")
    try:
        import aiohttp  # noqa: F401
        pytest.skip("aiohttp is installed: http:// works")
    except ImportError:
        pass
    proc = _cli("check", "http://127.0.0.1:9/ds", cwd=tmp_path)
    assert proc.returncode == 2 and "aiohttp" in proc.stderr, proc.stderr
    assert "needs fsspec" not in proc.stderr


def test_an_unreachable_object_store_is_an_error_in_bounded_time(tmp_path):
    """Without a network (or credentials), a gs:// URL fails once its retries have run
    for MCBAT_URL_TIMEOUT seconds (pyarrow's own default is 15 minutes)."""
    env = {**os.environ, "MCBAT_URL_TIMEOUT": "2"}
    t0 = time.monotonic()
    proc = subprocess.run([sys.executable, "-m", "mcbat", "check", "gs://mcbat-no-bucket/ds"],
                          capture_output=True, text=True, cwd=tmp_path, env=env, timeout=120,
                          check=False)
    assert time.monotonic() - t0 < 60
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr


def test_an_unreachable_object_store_as_out_is_an_error_in_bounded_time(monkeypatch):
    """``run --out gs://``: the writer's first request fails once its retries have run
    for MCBAT_URL_TIMEOUT seconds (in-process: the time of the requests, not of imports)."""
    from mcbat.dataset import storage

    monkeypatch.setenv("MCBAT_URL_TIMEOUT", "2")
    study = load_study(EXAMPLE)
    seconds = []
    try:
        for _ in range(2):  # the first also loads what a run loads: the second is timed
            storage._filesystem.cache_clear()  # no file system made with another limit
            t0 = time.monotonic()
            with pytest.raises(InputError, match="out: cannot write"):
                run_study(study, "gs://mcbat-no-bucket/ds", samples=100, progress=False)
            seconds.append(time.monotonic() - t0)
    finally:
        storage._filesystem.cache_clear()
    assert seconds[1] < 20, seconds
