"""The manifest knows the chunks: records, checks, resume, load."""

import shutil
from pathlib import Path

import pytest

import mcbat
import mcbat.dataset.chunks as ds
from mcbat.errors import InputError
from mcbat.runner import run_study
from mcbat.runner.plan import prepare_directory
from mcbat.study import load_study

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "studies" / "example.toml"
SAMPLES, CHUNK, SEED = 12_000, 3_000, 17


def _run(out, **kw):
    return run_study(load_study(EXAMPLE), out, samples=SAMPLES, seed=SEED, chunk_size=CHUNK,
                     progress=False, **kw)


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    out = tmp_path_factory.mktemp("clean") / "ds"
    _run(out)
    return out


@pytest.fixture
def copy(clean, tmp_path):
    out = tmp_path / "ds"
    shutil.copytree(clean, out)
    return out


def _same_bytes(a, b):
    names = sorted(p.name for p in Path(b).glob("chunk-*.parquet"))
    assert sorted(p.name for p in Path(a).glob("chunk-*.parquet")) == names
    for name in names:
        assert (Path(a) / name).read_bytes() == (Path(b) / name).read_bytes(), name


def _flip_middle(path, n=64):
    data = bytearray(path.read_bytes())
    middle = len(data) // 2
    for i in range(n):
        data[middle + i] ^= 0xFF
    path.write_bytes(bytes(data))


def test_every_chunk_is_recorded_with_its_checksum(clean, cli):
    manifest = ds.read_manifest(clean)
    assert sorted(manifest["files"]) == [ds.chunk_name(k) for k in range(4)]
    for name, record in manifest["files"].items():
        data = (clean / name).read_bytes()
        assert record == {"rows": CHUNK, "bytes": len(data), "crc32": ds.checksum(data)}
    result = mcbat.check(clean)
    assert result.ok and result.rows_good == SAMPLES and result.checksums
    proc = cli("check", clean)
    assert proc.returncode == 0 and "ok: complete" in proc.stdout


def test_a_corrupted_chunk_is_refused_by_load_and_recomputed_at_resume(copy, clean, cli):
    _flip_middle(copy / ds.chunk_name(1))
    with pytest.raises(InputError, match="chunk-000001.parquet: checksum mismatch"):
        mcbat.load(copy)
    proc = cli("check", copy)
    assert proc.returncode == 2 and "chunk-000001.parquet: checksum mismatch" in proc.stdout
    summary = _run(copy)
    assert (summary.chunks_computed, summary.chunks_kept) == (1, 3)
    assert summary.redone == [(1, "checksum mismatch (the file was changed or corrupted)")]
    assert any(line.startswith("recomputed chunk-000001.parquet: checksum mismatch")
               for line in summary.lines())
    _same_bytes(copy, clean)
    assert len(mcbat.load(copy)) == SAMPLES


def test_an_interrupted_dataset_is_refused_unless_partial_is_allowed(copy, cli):
    (copy / ds.chunk_name(2)).unlink()
    with pytest.raises(InputError, match=r"1 of 4 chunk\(s\) missing \(2\): 9,000 of 12,000"):
        mcbat.load(copy)
    with pytest.warns(UserWarning, match="partial dataset"):
        df = mcbat.load(copy, allow_partial=True)
    assert len(df) == 9_000 and 6_000 not in set(df["sample_id"])
    assert cli("check", copy).returncode == 2


def test_a_chunk_copied_over_another_is_noticed_and_redone(copy, clean):
    shutil.copy(copy / ds.chunk_name(0), copy / ds.chunk_name(2))
    with pytest.raises(InputError, match="chunk-000002.parquet"):
        mcbat.load(copy)
    quick = mcbat.check(copy, checksums=False)  # what load checks, without reading data
    assert [name for name, _ in quick.mismatched] == [ds.chunk_name(2)]
    # with the recorded size made to match, the footer's sample_id range still tells
    manifest = ds.read_manifest(copy)
    manifest["files"][ds.chunk_name(2)]["bytes"] = (copy / ds.chunk_name(2)).stat().st_size
    ds.write_manifest(copy, manifest)
    reason = mcbat.check(copy, checksums=False).mismatched[0][1]
    assert "holds sample_id 0..2999, chunk 2 is 6000..8999" in reason
    summary = _run(copy)
    assert summary.chunks_computed == 1 and summary.redone[0][0] == 2
    _same_bytes(copy, clean)


def test_a_stray_chunk_is_refused_by_load_and_removed_at_resume(copy, clean):
    shutil.copy(copy / ds.chunk_name(0), copy / ds.chunk_name(7))
    with pytest.raises(InputError, match="not part of the dataset.*chunk-000007"):
        mcbat.load(copy)
    summary = _run(copy)
    assert summary.chunks_computed == 0 and summary.removed == [ds.chunk_name(7)]
    _same_bytes(copy, clean)
    assert mcbat.load(copy)["sample_id"].is_unique


def test_an_unrecorded_chunk_is_recomputed(copy, clean):
    manifest = ds.read_manifest(copy)
    del manifest["files"][ds.chunk_name(3)]  # as if the run was killed before recording it
    ds.write_manifest(copy, manifest)
    with pytest.raises(InputError, match="not part of the dataset"):
        mcbat.load(copy)
    summary = _run(copy)
    assert summary.redone == [(3, "not recorded in the manifest")]
    _same_bytes(copy, clean)


def test_chunk_names_have_no_digit_limit(tmp_path):
    assert ds.chunk_name(1_000_000) == "chunk-1000000.parquet"
    assert ds.chunk_index("chunk-1000000.parquet") == 1_000_000
    assert ds.chunk_index("chunk-000042.parquet") == 42
    assert ds.chunk_index("chunk-0000042.parquet") is None  # not the canonical name
    assert ds.chunk_index("chunk-42.parquet") is None
    # --overwrite treats a 7-digit chunk file as one of mcbat's, not a foreign file
    out = tmp_path / "ds"
    out.mkdir()
    ds.write_manifest(out, {"config_hash": "another", "chunk_size": 1, "samples": 1,
                            "chunks": 1})
    (out / "chunk-1000000.parquet").write_bytes(b"old")
    manifest = {"config_hash": "new", "files": {}, "study_toml": ""}
    prepare_directory(out, manifest, 5, overwrite=True)
    assert sorted(p.name for p in out.iterdir()) == [ds.MANIFEST]


def test_a_comment_only_edit_before_resume_keeps_one_study_text(tmp_path, cli):
    study_file = tmp_path / "s.toml"
    study_file.write_text(EXAMPLE.read_text())
    out = tmp_path / "ds"
    args = ["run", study_file, "--out", out, "--samples", SAMPLES, "--chunk-size", CHUNK,
            "--quiet"]
    assert cli(*args).returncode == 0
    (out / ds.chunk_name(3)).unlink()
    study_file.write_text("# a comment added later\n" + EXAMPLE.read_text())
    proc = cli(*args)
    assert proc.returncode == 0 and "(1 computed, 3 kept" in proc.stdout
    texts = {ds.json.loads(ds.read_metadata(out / ds.chunk_name(k)).metadata[
        ds.METADATA_KEY])["study_toml"] for k in range(4)}
    assert texts == {EXAMPLE.read_text()}


def test_old_datasets_without_records_still_load(copy):
    manifest = ds.read_manifest(copy)
    del manifest["files"]  # written before chunk records existed
    ds.write_manifest(copy, manifest)
    # They load, said to be unverified: the manifest has no checksum to compare with.
    with pytest.warns(UserWarning, match="unverified"):
        assert len(mcbat.load(copy)) == SAMPLES
    (copy / ds.chunk_name(1)).write_bytes((copy / ds.chunk_name(1)).read_bytes()[:400])
    with pytest.raises(InputError, match="chunk-000001.parquet: unreadable Parquet footer"):
        mcbat.load(copy)


def test_a_chunk_too_big_for_the_encoding_buffer_is_written_all_the_same(tmp_path,
                                                                          monkeypatch):
    """The reusable encoding buffer is sized from the table; a chunk that does not fit
    (compressed pages can grow) falls back to a growing buffer, with the same bytes."""
    import numpy as np
    import pyarrow as pa

    table = pa.table({"x": np.random.default_rng(0).random(50_000),
                      "k": np.full(50_000, 3.0)})
    fits = ds.write_chunk(table, tmp_path / "a.parquet", compression="zstd")
    monkeypatch.setattr(ds, "_capacity", lambda t: 1000)
    monkeypatch.setattr(ds._buffers, "buffer", None, raising=False)
    spills = ds.write_chunk(table, tmp_path / "b.parquet", compression="zstd")
    assert fits == spills
    assert (tmp_path / "a.parquet").read_bytes() == (tmp_path / "b.parquet").read_bytes()
    assert pa.parquet.read_table(tmp_path / "b.parquet").equals(table)
