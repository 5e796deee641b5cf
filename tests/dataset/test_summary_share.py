"""`[summary] share_above`: per bin, the share of a column's values strictly above a
threshold, from integer counts merged chunk by chunk, so the table does not depend on how
the rows were cut into chunks or on the order in which the chunks finish."""

import io

import numpy as np
import pyarrow as pa
import pytest

from mcbat.dataset.summary import SummaryState, shares, summarise, summary_table
from mcbat.errors import InputError
from mcbat.study.output import parse_summary

UNITS = {"launch_angle": "deg", "hit_distance": "ft", "launch_speed": "mph", "status": "1"}
SECTION = {"by": {"launch_angle": {"bins": 5, "low": 0, "high": 50}},
           "columns": ["launch_speed", "hit_distance"],
           "share_above": {"hit_distance": [300, 380.5], "launch_speed": 95}}


def _rows(n=20_000, seed=3):
    rng = np.random.default_rng(seed)
    distance = rng.normal(300, 80, n)
    distance[rng.random(n) < 0.05] = np.nan            # failed rows
    distance[:50] = 380.5                              # exactly at a threshold: not above
    return {"launch_angle": rng.uniform(-10, 60, n), "hit_distance": distance,
            "launch_speed": rng.normal(90, 10, n), "status": np.zeros(n, np.int8)}


def _merged(spec, cols, cuts, order):
    parts = np.split(np.arange(len(cols["status"])), cuts)
    state = SummaryState(spec)
    partials = {k: summarise(spec, {c: v[rows] for c, v in cols.items()})
                for k, rows in enumerate(parts)}
    for k in order(len(parts)):
        state.add(k, partials[k])
    assert state.merged == len(parts)
    return state


def test_the_share_is_the_count_above_over_the_values_bin_by_bin():
    spec = parse_summary(SECTION, UNITS)
    cols = _rows()
    state = _merged(spec, cols, [7_000], lambda n: range(n))
    table = summary_table(spec, state, {"units": {}}).to_pandas()
    b = np.floor(cols["launch_angle"] / 10)
    for (name, threshold), label in zip(spec.share_above, ("hit_distance_above_300",
                                                           "hit_distance_above_380.5",
                                                           "launch_speed_above_95")):
        x = cols[name]
        for i in range(5):
            values = x[(b == i) & ~np.isnan(x)]
            above = int((values > threshold).sum())
            assert table[f"{label}_count"][i] == above
            p = above / len(values)
            assert table[label][i] == pytest.approx(p, rel=1e-15)
            assert table[f"{label}_err"][i] == pytest.approx(
                np.sqrt(p * (1 - p) / len(values)), rel=1e-12)
    overall = {(s["column"], s["above"]): s for s in shares(spec, state)}
    inside = (cols["launch_angle"] >= 0) & (cols["launch_angle"] < 50)
    d = cols["hit_distance"][inside & ~np.isnan(cols["hit_distance"])]
    s = overall[("hit_distance", 380.5)]
    assert (s["n"], s["count"], s["unit"]) == (len(d), int((d > 380.5).sum()), "ft")
    assert s["share"] == pytest.approx((d > 380.5).mean(), rel=1e-15)


@pytest.mark.parametrize("cuts, order", [
    ([1], lambda n: range(n)),
    ([333, 5_000, 5_001, 19_000], lambda n: reversed(range(n))),
    (list(range(997, 20_000, 997)), lambda n: np.random.default_rng(1).permutation(n)),
])
def test_the_table_is_identical_whatever_the_chunking_and_order(cuts, order):
    spec = parse_summary(SECTION, UNITS)
    cols = _rows()
    reference = summary_table(spec, _merged(spec, cols, [10_000], lambda n: range(n)), {})
    got = summary_table(spec, _merged(spec, cols, cuts, order), {})
    assert got.equals(reference)
    assert isinstance(got, pa.Table) and "hit_distance_above_380.5_err" in got.column_names


def test_the_state_round_trips_its_counts():
    spec = parse_summary(SECTION, UNITS)
    state = _merged(spec, _rows(2_000), [500], lambda n: range(n))
    data = state.to_bytes()
    with np.load(io.BytesIO(data)) as saved:
        np.testing.assert_array_equal(saved["share_above"], state.above)


@pytest.mark.parametrize("share_above, words", [
    ({"spin": 1}, "summary.share_above.spin: must be one of summary.columns"),
    ({"hit_distance": True}, "summary.share_above.hit_distance: must be a number"),
    ({"hit_distance": [380, float("nan")]}, "summary.share_above.hit_distance[1]: must be finite"),
    ({"hit_distance": list(range(65))}, "summary.share_above: 65 thresholds; at most 64"),
    ([380], "summary.share_above: must be a table of columns and thresholds"),
])
def test_bad_thresholds_name_the_key(share_above, words):
    with pytest.raises(InputError) as err:
        parse_summary({**SECTION, "share_above": share_above}, UNITS)
    assert words in str(err.value)


def test_without_share_above_the_config_is_unchanged():
    section = {k: v for k, v in SECTION.items() if k != "share_above"}
    assert "share_above" not in parse_summary(section, UNITS).config()
    assert parse_summary(SECTION, UNITS).config()["share_above"] == [
        ["hit_distance", 300.0], ["hit_distance", 380.5], ["launch_speed", 95.0]]
