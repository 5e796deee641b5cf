"""``mcbat check``: a dataset that is not ok is bad input (exit 2); the report stays on
stdout and stderr ends with one line naming the first problem's file and what is wrong."""

import json
import shutil
from pathlib import Path

import pytest

import mcbat.dataset.chunks as ds
from mcbat.cli import main
from mcbat.runner import run_study
from mcbat.study import load_study

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "studies" / "example.toml"
THROUGHPUT = ROOT / "studies" / "throughput.toml"
SAMPLES, CHUNK = 2_000, 500


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    out = tmp_path_factory.mktemp("clean") / "ds"
    run_study(load_study(EXAMPLE), out, samples=SAMPLES, seed=5, chunk_size=CHUNK,
              progress=False)
    return out


@pytest.fixture
def copy(clean, tmp_path):
    out = tmp_path / "ds"
    shutil.copytree(clean, out)
    return out


def _check(capsys, directory, *flags):
    code = main(["check", str(directory), *flags])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _flip(path):
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))


def test_a_complete_dataset_exits_0_with_nothing_on_stderr(clean, capsys):
    code, out, err = _check(capsys, clean)
    assert code == 0 and err == "" and "ok: complete" in out


def _remove(d):
    (d / ds.chunk_name(2)).unlink()


def _beyond(d):
    shutil.copy(d / ds.chunk_name(0), d / ds.chunk_name(6))


def _flip_one(d):
    _flip(d / ds.chunk_name(1))


def _copy_over(d):
    shutil.copy(d / ds.chunk_name(0), d / ds.chunk_name(3))


def _foreign(d):
    shutil.copy(d / ds.chunk_name(0), d / "chunk-000000 (copy).parquet")


def _no_records(d):
    manifest = ds.read_manifest(d)
    del manifest["files"]
    ds.write_manifest(d, manifest)


@pytest.mark.parametrize("damage, first", [
    (_remove, "chunk-000002.parquet: missing (1,500 of 2,000 rows present)"),
    (_beyond, "chunk-000006.parquet: not part of the dataset"),
    (_flip_one, "chunk-000001.parquet: checksum mismatch"),
    (_copy_over, "chunk-000003.parquet: "),
    (_foreign, "chunk-000000 (copy).parquet: not a chunk file of the dataset"),
    (_no_records, "_mcbat.json: records no checksums"),
], ids=["missing", "beyond the last chunk", "flipped byte", "copied over another",
        "foreign copy", "unverified"])
def test_a_dataset_that_is_not_ok_exits_2_naming_the_first_problem(copy, capsys, damage,
                                                                   first):
    damage(copy)
    code, out, err = _check(capsys, copy)
    assert code == 2
    assert "ok: complete" not in out and out.startswith(f"dataset: {copy}")
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"mcbat: error: {copy}: {first}"), lines[0]


def test_more_problems_than_one_are_counted_on_the_error_line(copy, capsys):
    _remove(copy)
    _flip_one(copy)
    _foreign(copy)
    code, out, err = _check(capsys, copy)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "(copy).parquet: not a chunk file" in err and "(and 2 more problem(s)" in err
    # the report names every one of them
    assert "1 of 4 chunk(s) missing (2)" in out
    assert "chunk-000001.parquet: checksum mismatch" in out and "(copy).parquet" in out


def test_quick_finds_what_it_reads_and_passes_what_it_does_not(copy, capsys):
    _flip_one(copy)  # same size, same footer: only the checksum sees it
    assert _check(capsys, copy, "--quick")[0] == 0
    _remove(copy)
    code, _, err = _check(capsys, copy, "--quick")
    assert code == 2 and "chunk-000002.parquet: missing" in err


def test_an_unfinished_summary_names_the_summary_table(tmp_path, capsys):
    study = tmp_path / "summary.toml"
    study.write_text(THROUGHPUT.read_text() + '\n[summary]\nby = { from_barrel_end = '
                     '{ bins = 4, low = 0, high = 40, unit = "cm" } }\n'
                     'columns = ["exit_speed"]\nquantiles = [0.5]\n')
    out = tmp_path / "ds"
    run_study(load_study(study), out, samples=SAMPLES, chunk_size=CHUNK, progress=False,
              summary_only=True)
    assert _check(capsys, out)[0] == 0
    manifest = json.loads((out / ds.MANIFEST).read_text())
    del manifest["summary"]["table"]
    ds.write_manifest(out, manifest)
    code, _, err = _check(capsys, out)
    assert code == 2
    assert err.startswith(f"mcbat: error: {out}: _summary.parquet: the [summary] table is "
                          "not finished")


def test_a_directory_that_is_not_a_dataset_is_exit_2_as_before(tmp_path, capsys):
    code, out, err = _check(capsys, tmp_path)
    assert code == 2 and out == "" and "not an mcbat dataset" in err
