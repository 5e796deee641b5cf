"""`[output]` column selection and precision, and `[summary]` scans: a summary equals the
same statistics computed by pandas from the full rows of the same run, is identical whatever
the threads, chunking, engine or resumption, and bad sections are one-line errors."""

from pathlib import Path

import numba
import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest

import mcbat
from mcbat.dataset import binned_stats as core
from mcbat.dataset import chunks as ds
from mcbat.errors import InputError
from mcbat.runner import run_study
from mcbat.study import Study, load_study

ROOT = Path(__file__).resolve().parents[2]
THROUGHPUT = ROOT / "studies" / "throughput.toml"
SUMMARY = """
[summary]
by = { from_barrel_end = { bins = 14, low = 0, high = 70, unit = "cm" } }
columns = ["exit_speed", "scattering_angle", "friction_work"]
quantiles = [0.05, 0.5, 0.95]
share_above = { exit_speed = [2.5, 4.0], scattering_angle = -20 }
"""
SUMMARY_2D = """
[summary]
columns = ["exit_speed", "spin"]
[summary.by]
from_barrel_end = { bins = 7, low = 0, high = 0.56 }
mu = { bins = 4, low = 0, high = 0.8 }
"""


def _study(tmp_path, extra, name="s.toml"):
    path = tmp_path / name
    path.write_text(THROUGHPUT.read_text() + extra)
    return load_study(path)


@pytest.fixture(scope="module")
def full_run(tmp_path_factory):
    """A 60,000-row run with a [summary] that also stores every row."""
    tmp = tmp_path_factory.mktemp("summary")
    study = _study(tmp, SUMMARY)
    out = tmp / "rows"
    summary = run_study(study, out, samples=60_000, seed=5, chunk_size=16_000,
                        progress=False)
    return study, out, summary


def _pandas_summary(rows, spec):
    """The [summary] statistics by pandas, from the rows."""
    axis = spec.by[0]
    width = (axis.high - axis.low) / axis.bins
    values = rows[axis.name]
    index = np.floor((values - axis.low) / width)
    inside = (values >= axis.low) & (values < axis.high)
    index = index.where(inside).clip(upper=axis.bins - 1)
    groups = rows[inside].groupby(index[inside].astype(int))
    return groups, int((~inside).sum())


def test_summary_equals_pandas_on_the_full_rows(full_run):
    study, out, run = full_run
    rows = mcbat.load(out)
    table = mcbat.load_summary(out)
    spec = study.summary_spec({"from_barrel_end": "m", "exit_speed": "m/s",
                               "scattering_angle": "deg", "friction_work": "J"})
    groups, outside = _pandas_summary(rows, spec)
    assert len(table) == 14 and table.attrs["outside"] == outside
    assert table["count"].sum() + outside == len(rows) == 60_000
    assert run.summary["outside"] == outside
    np.testing.assert_allclose(table["from_barrel_end_low"], np.arange(14) * 5.0)
    np.testing.assert_allclose(table["from_barrel_end_high"], np.arange(1, 15) * 5.0)
    alpha = table.attrs["quantile_resolution"]["relative"]
    assert alpha == core.ALPHA
    for b in range(14):
        group = groups.get_group(b)
        assert table["count"][b] == len(group)
        for name in spec.columns:
            col = group[name].dropna()
            assert table[f"{name}_count"][b] == len(col)
            assert table[f"{name}_min"][b] == col.min()
            assert table[f"{name}_max"][b] == col.max()
            np.testing.assert_allclose(table[f"{name}_mean"][b], col.mean(), rtol=1e-12,
                                       atol=1e-300)
            np.testing.assert_allclose(table[f"{name}_std"][b], col.std(), rtol=1e-12,
                                       atol=1e-300)
            for q, label in ((0.05, "p5"), (0.5, "p50"), (0.95, "p95")):
                exact = col.quantile(q, interpolation="lower")
                got = table[f"{name}_{label}"][b]
                assert abs(got - exact) <= alpha * abs(exact) + core.MIN_MAGNITUDE, \
                    (name, b, q, got, exact)
    assert table.attrs["units"]["exit_speed_mean"] == "m/s"
    assert table.attrs["units"]["from_barrel_end_low"] == "cm"


def test_share_above_equals_pandas_and_is_in_the_closing_report(full_run):
    study, out, run = full_run
    rows = mcbat.load(out)
    table = mcbat.load_summary(out)
    spec = study.summary_spec({"from_barrel_end": "m", "exit_speed": "m/s",
                               "scattering_angle": "deg", "friction_work": "J"})
    assert spec.share_above == (("exit_speed", 2.5), ("exit_speed", 4.0),
                                ("scattering_angle", -20.0))
    groups, _ = _pandas_summary(rows, spec)
    for name, threshold, label in (("exit_speed", 2.5, "exit_speed_above_2.5"),
                                   ("exit_speed", 4.0, "exit_speed_above_4"),
                                   ("scattering_angle", -20.0,
                                    "scattering_angle_above_-20")):
        shares = []
        for b in range(14):
            col = groups.get_group(b)[name].dropna()
            above = int((col > threshold).sum())
            assert table[f"{label}_count"][b] == above
            p = above / len(col)
            shares.append(p)
            assert table[label][b] == pytest.approx(p, rel=1e-15)
            assert table[f"{label}_err"][b] == pytest.approx(
                np.sqrt(p * (1 - p) / len(col)), rel=1e-12)
        assert any(0 < p < 1 for p in shares)  # the threshold splits the bins
        assert table.attrs["units"][label] == "1"
        inside = pd.concat([groups.get_group(b)[name].dropna() for b in range(14)])
        overall, = [s for s in table.attrs["share_above"]
                    if (s["column"], s["above"]) == (name, threshold)]
        assert overall["n"] == len(inside) and overall["count"] == (inside > threshold).sum()
        assert overall["share"] == pytest.approx((inside > threshold).mean(), rel=1e-15)
        assert overall in run.summary["share_above"]
    lines = "\n".join(run.lines())
    share = run.summary["share_above"][0]
    assert (f"share above: exit_speed > 2.5 m/s: {100 * share['share']:.2f} +- "
            f"{100 * share['error']:.2f} %") in lines


def test_summary_is_identical_whatever_threads_chunks_engine_mode(full_run, tmp_path):
    study, out, _ = full_run
    reference = pq.read_table(out / "_summary.parquet")
    variants = [dict(threads=1, chunk_size=16_000), dict(threads=2, chunk_size=9_000),
                dict(threads=2, chunk_size=60_000, summary_only=True)]
    for i, options in enumerate(variants):
        got = tmp_path / f"v{i}"
        run_study(study, got, samples=60_000, seed=5, progress=False, **options)
        assert pq.read_table(got / "_summary.parquet").equals(reference), options


def test_summary_and_column_selection_with_the_dask_engine_are_the_local_ones(full_run,
                                                                              tmp_path):
    pytest.importorskip("distributed")
    study, out, _ = full_run
    study = study.with_overrides(columns=["exit_speed", "mu", "status"])
    got = tmp_path / "dask"
    run_study(study, got, samples=60_000, seed=5, chunk_size=16_000, progress=False,
              engine="dask", workers=2, threads=1)
    assert pq.read_table(got / "_summary.parquet").equals(
        pq.read_table(out / "_summary.parquet"))
    rows = mcbat.load(got)
    assert list(rows.columns) == ["mu", "status", "exit_speed", "sample_id"]
    pd.testing.assert_frame_equal(rows, mcbat.load(out)[list(rows.columns)],
                                  check_exact=True)


def test_summary_only_stores_no_rows_and_load_says_where_to_look(full_run, tmp_path):
    study, _, _ = full_run
    out = tmp_path / "only"
    run = run_study(study, out, samples=20_000, seed=5, chunk_size=5_000, progress=False,
                    summary_only=True)
    assert run.summary["summary_only"] and "summarised only" in "\n".join(run.lines())
    names = sorted(p.name for p in out.iterdir())
    assert names == ["_mcbat.json", "_summary.parquet", "_summary_state.npz"]
    assert mcbat.check(out).ok
    with pytest.raises(InputError, match="summary-only run stores no rows"):
        mcbat.load(out)
    assert mcbat.load_summary(out)["count"].sum() + mcbat.load_summary(out).attrs[
        "outside"] == 20_000


def test_an_interrupted_summary_resumes_to_the_same_table(full_run, tmp_path, monkeypatch):
    from mcbat.runner.engines import local

    study, _, _ = full_run
    reference = tmp_path / "ref"
    run_study(study, reference, samples=40_000, seed=5, chunk_size=5_000, progress=False,
              summary_only=True)
    out = tmp_path / "cut"
    original, calls = local.run_chunk, []

    def dies_at_the_fifth(*args, **kwargs):
        calls.append(1)
        if len(calls) == 5:
            raise KeyboardInterrupt
        return original(*args, **kwargs)

    monkeypatch.setattr(local, "run_chunk", dies_at_the_fifth)
    with pytest.raises(KeyboardInterrupt):
        run_study(study, out, samples=40_000, seed=5, chunk_size=5_000, progress=False,
                  summary_only=True)
    monkeypatch.setattr(local, "run_chunk", original)
    assert not (out / "_summary.parquet").exists()
    assert not mcbat.check(out).ok  # unfinished: said so
    resumed = run_study(study, out, samples=40_000, seed=5, chunk_size=5_000, progress=False,
                        summary_only=True)
    assert resumed.chunks_computed == 4  # from the saved state (chunks 0-3 merged)
    assert (out / "_summary.parquet").read_bytes() == \
        (reference / "_summary.parquet").read_bytes()


def test_two_by_columns_bin_row_major(tmp_path):
    study = _study(tmp_path, SUMMARY_2D)
    out = tmp_path / "ds"
    run_study(study, out, samples=20_000, seed=3, chunk_size=5_000, progress=False)
    table, rows = mcbat.load_summary(out), mcbat.load(out)
    assert len(table) == 28
    assert table["from_barrel_end_low"].tolist()[:5] == [0.0] * 4 + [0.08]
    np.testing.assert_allclose(table["mu_low"][:4], [0.0, 0.2, 0.4, 0.6])
    inside = (rows["from_barrel_end"] < 0.56) & (rows["mu"] < 0.8)
    assert table["count"].sum() == inside.sum() and table.attrs["outside"] == (~inside).sum()
    b = rows[inside]
    i = np.minimum((b["from_barrel_end"] / 0.08).astype(int), 6)
    j = np.minimum((b["mu"] / 0.2).astype(int), 3)
    counts = np.bincount(i * 4 + j, minlength=28)
    assert table["count"].tolist() == counts.tolist()


def test_output_columns_and_float32(tmp_path):
    study = _study(tmp_path, '\n[output]\ncolumns = ["exit_speed", "mu", "status"]\n'
                             'precision = "float32"\n')
    out = tmp_path / "ds"
    run_study(study, out, samples=10_000, seed=2, chunk_size=4_000, progress=False,
              threads=min(2, numba.config.NUMBA_NUM_THREADS))
    rows = mcbat.load(out)
    assert list(rows.columns) == ["mu", "status", "exit_speed", "sample_id"]
    assert rows["exit_speed"].dtype == np.float32 and rows["mu"].dtype == np.float64
    full = tmp_path / "full"
    run_study(load_study(THROUGHPUT), full, samples=10_000, seed=2, chunk_size=4_000,
              progress=False)
    ref = mcbat.load(full)
    assert (rows["mu"] == ref["mu"]).all() and (rows["status"] == ref["status"]).all()
    np.testing.assert_array_equal(rows["exit_speed"], ref["exit_speed"].astype(np.float32))
    assert rows.attrs["units"]["exit_speed"] == "m/s"
    with pytest.raises(InputError) as err:  # a column the study did not store
        mcbat.load(out, columns=["exit_speed", "spin"])
    assert err.value.field == "columns" and "'spin' is not stored" in err.value.message
    other = tmp_path / "other"  # another chunking and thread count: the same rows
    run_study(study, other, samples=10_000, seed=2, chunk_size=3_000, threads=1,
              progress=False)
    pd.testing.assert_frame_equal(mcbat.load(other), rows, check_exact=True)


def test_columns_override_and_from_barrel_end(tmp_path, cli):
    out = tmp_path / "cli"
    proc = cli("run", THROUGHPUT, "--out", out, "--samples", 3000, "--quiet", "--columns",
               "from_barrel_end,axial")
    assert proc.returncode == 0, proc.stderr
    rows = mcbat.load(out)
    assert list(rows.columns) == ["axial", "from_barrel_end", "sample_id"]
    barrel = load_study(THROUGHPUT).bat.cm_from_barrel_end
    np.testing.assert_allclose(rows["from_barrel_end"], barrel - rows["axial"], rtol=0,
                               atol=1e-15)
    assert rows["from_barrel_end"].between(0, 0.70 + 1e-12).all()


@pytest.mark.parametrize("extra, args, words", [
    ('\n[output]\ncolumns = ["exit_sped"]\n', (),
     "output.columns: 'exit_sped' is not a column of this study's dataset"),
    ("", ("--columns", "nope"), "--columns: 'nope' is not a column"),
    ('\n[output]\nprecision = "float16"\n', (), "output.precision: must be one of"),
    ("", ("--summary-only",), "--summary-only: needs a [summary] section"),
    (SUMMARY.replace("from_barrel_end =", "from_barel_end ="), (),
     "summary.by.from_barel_end: not a column of this study's dataset"),
    (SUMMARY.replace('unit = "cm"', 'unit = "deg"'), (),
     "summary.by.from_barrel_end.unit: 'deg' is not a unit of this column's quantity"),
    (SUMMARY.replace("0.95]", "1.5]"), (), "summary.quantiles[2]: must be in (0, 1)"),
    (SUMMARY.replace("low = 0, high = 70", "low = 70, high = 0"), (),
     "summary.by.from_barrel_end.high: must be > low"),
    (SUMMARY.replace("bins = 14", "bins = 100000"), (),
     "summary.by: 100,000 bins x 3 columns with quantiles need"),
    (SUMMARY.replace("scattering_angle = -20", "spin = 10"), (),
     "summary.share_above.spin: must be one of summary.columns"),
    (SUMMARY.replace("[2.5, 4.0]", "[2.5, \"fast\"]"), (),
     "summary.share_above.exit_speed[1]: must be a number"),
    (SUMMARY.replace("[2.5, 4.0]", "[]"), (),
     "summary.share_above.exit_speed: must be a threshold or a non-empty list"),
    (SUMMARY.replace("share_above = {", "share_above = 3 #"), (),
     "summary.share_above: must be a table of columns and thresholds"),
])
def test_bad_output_and_summary_sections_exit_2(tmp_path, cli, extra, args, words):
    path = tmp_path / "bad.toml"
    path.write_text(THROUGHPUT.read_text() + extra)
    proc = cli("run", path, "--out", tmp_path / "ds", "--samples", 1000, "--quiet", *args)
    assert proc.returncode == 2, proc.stderr
    assert proc.stdout == "" and "Traceback" not in proc.stderr
    line, = proc.stderr.strip().splitlines()
    assert words in line, line
    assert not (tmp_path / "ds").exists()


def test_the_summary_section_is_part_of_the_config(tmp_path):
    a = _study(tmp_path, SUMMARY, "a.toml")
    b = _study(tmp_path, SUMMARY.replace("bins = 14", "bins = 7"), "b.toml")
    assert a.config_hash() != b.config_hash() != load_study(THROUGHPUT).config_hash()
    c = _study(tmp_path, SUMMARY.replace("4.0]", "4.5]"), "c.toml")
    assert c.config_hash() != a.config_hash()
    no_share = SUMMARY.replace("share_above", "# share_above")
    assert "share_above" not in _study(tmp_path, no_share, "d.toml").config()["summary"]
    assert Study.from_dict(a.definition()).config() == a.config()
    assert ds.MANIFEST == "_mcbat.json"
