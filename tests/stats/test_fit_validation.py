"""The drop-test fit against tables simulated independently (harness.fit_validation).

The default run fits two tables per setting (a fit takes ~10 s) and checks what must hold
table by table (no refusal, no zero-width interval, pulls within reason); the slow-marked
tests run the full check with its statistical criteria: on 400 tables inside and at the
edges of the study's range, two-sided coverage 68 +- 3 %, mean pulls within +-0.1, and the
few one-sided limits missing the truth no more often than 95 % limits may; on 400 tables
at the onset of sticking, where limits are common, at least 93 % of them holding it, and
with the truth at each table's own onset of sticking at least 95 %; just below the
onsets (mu = 0.19), on 2400 tables, 95 +- 2 % of the limits holding the truth.
"""

import math

import numpy as np
import pytest
from scipy.stats import binom

from harness.fit_validation import fit_table, interval_statistics, summarize
from mcbat.study import load_study
from tests.conftest import ROOT


@pytest.fixture(scope="module")
def study():
    return load_study(ROOT / "studies" / "cross_nathan_2006.toml")


def _records(study, settings, tables):
    return [fit_table(s, k, study) for k in range(tables) for s in settings]


def test_interval_statistics_count_pulls_on_the_truths_side_and_limits_apart():
    def interval(value, lower, upper):
        return {"status": "measured", "value": value, "lower_error": lower,
                "upper_error": upper}

    entries = [
        (interval(1.0, 0.5, 2.0), 2.0),   # truth above: pull (1 - 2) / 2 = -0.5, covered
        (interval(1.0, 0.5, 2.0), 0.0),   # truth below: pull 1 / 0.5 = +2, not covered
        (interval(1.0, 0.0, 1.0), 1.5),   # zero width below: pull -0.5, counted as such
        ({"status": "lower_limit", "limit": 0.3}, 0.4),   # holds
        ({"status": "lower_limit", "limit": 0.5}, 0.4),   # excludes the truth
        ({"status": "upper_limit", "limit": 0.5}, 0.4),   # holds
    ]
    stats = interval_statistics(entries, tables=len(entries))
    np.testing.assert_allclose(stats["mean_pull"], (-0.5 + 2.0 - 0.5) / 3)
    np.testing.assert_allclose(stats["pull_sd"], np.std([-0.5, 2.0, -0.5], ddof=1))
    assert stats["coverage"] == pytest.approx(2 / 6)
    assert stats["interval_coverage"] == pytest.approx(2 / 3)
    assert stats["limits"] == 3 and stats["limit_coverage"] == pytest.approx(2 / 3)
    assert stats["zero_width"] == 1


@pytest.mark.slow
@pytest.mark.parametrize("setting", ["inside", "edges"])
def test_a_few_independent_tables_fit_without_refusal_or_zero_width(study, setting):
    records = _records(study, [setting], 2)
    assert not [r["refused"] for r in records if "refused" in r]
    for row in summarize(records):
        assert row["zero_width"] == 0
        assert row["coverage"] > 0  # at least one of two intervals holds the truth
        # Two pulls of unit spread: their mean has a spread of 1 / sqrt(2); the bound
        # 3 / sqrt(3) (three standard errors of a mean of three) is 2.4 of those.
        assert row["mean_pull"] is not None and abs(row["mean_pull"]) < 3 / math.sqrt(3)
    # True values inside the study's range: the measured ones do not reject it (p < 0.001
    # by design), and with true values spread over the range the fitted prior puts next
    # to nothing beyond it. Piled within 5 mm of its ends, the true values leave the
    # prior's step at the ends less well fixed: over 400 `edges` tables the share beyond
    # has a median of 0.0015 but reaches 0.05-0.065 in 3 of them (docs/fit-checks.md), and
    # table 1 is one of those three (0.052).
    assert not any(r["rejected"] for r in records)
    if setting == "inside":
        assert max(r["share_beyond"]["impact_parameter"] for r in records) < 0.02


@pytest.mark.slow
def test_coverage_and_pulls_over_400_tables_inside_and_at_the_edges(study):
    records = _records(study, ["inside", "edges"], 400)
    for row in summarize(records):
        where = f"{row['setting']} {row['param']}"
        assert row["refused"] == 0 and row["zero_width"] == 0, where
        assert abs(row["coverage"] - 0.68) <= 0.03, where
        assert abs(row["mean_pull"]) <= 0.1, where
        if row["limits"]:
            _assert_limits_hold_95_percent(row, where)
    assert np.isfinite([r["chi2"] for r in records]).all()


def _assert_limits_hold_95_percent(row, where):
    """95 +- 2 % of the limits hold the truth where there are enough of them to tell; with
    fewer (about 1.5 % of the `inside` tables report one) the number that miss it must be
    a plausible draw of Binomial(limits, 0.05): neither tail below 0.5 %."""
    n = row["limits"]
    misses = round(n * (1 - row["limit_coverage"]))
    assert binom.cdf(misses, n, 0.05) > 0.005 and binom.sf(misses - 1, n, 0.05) > 0.005, where
    if n >= 150:  # the share's standard error is then below 1.8 %
        assert abs(row["limit_coverage"] - 0.95) <= 0.02, where


@pytest.mark.slow
def test_one_sided_limits_hold_the_truth_where_tables_report_them_often(study):
    # At mu = 0.2 the plateau where every drop sticks begins: about half of the tables
    # bound mu from below only. A 95 % limit promises to hold the truth in at least 95 %
    # of the tables, just 95 % only where flat tables are rare. Here the truth lies at or
    # above the onset of sticking of about half the tables, where their data are those of
    # the plateau, so the limits are conservative (docs/fit-checks.md): only too many
    # misses fail.
    records = _records(study, ["onset"], 400)
    row = next(r for r in summarize(records) if r["param"] == "mu")
    assert row["limits"] >= 150 and row["refused"] == 0 and row["zero_width"] == 0
    misses = round(row["limits"] * (1 - row["limit_coverage"]))
    assert binom.sf(misses - 1, row["limits"], 0.05) > 0.005
    assert row["limit_coverage"] >= 0.93


@pytest.mark.slow
def test_one_sided_limits_just_below_the_onset_of_sticking_hold_the_truth_as_promised(study):
    # At mu = 0.19 some drop still slides in nearly every table, yet about one table in
    # seven looks flat and bounds mu from below only: the limits are tested where they can
    # fail. 2400 tables (about 4 hours) give over 300 of them, whose share holding the
    # truth then has a binomial error of 1.2 %, enough to hold it to 95 +- 2 % (with 150
    # limits an exact 95 % limit would land outside that band one time in four). The
    # two-sided intervals of e* are held to the inside criteria. Those of mu are the
    # tables not flat above: the ones whose best value lies far above the truth report a
    # limit instead, so the intervals that remain hold the truth more often than 68 %
    # (70 % in docs/fit-checks.md), and only too few fail.
    records = _records(study, ["onset_low"], 2400)
    for row in summarize(records):
        where = row["param"]
        assert row["refused"] == 0 and row["zero_width"] == 0, where
        assert abs(row["mean_pull"]) <= 0.1, where
        assert row["interval_coverage"] >= 0.65, where
        if row["param"] == "e":
            assert abs(row["interval_coverage"] - 0.68) <= 0.03, where
        if row["param"] == "mu":
            assert row["limits"] >= 300, where
            _assert_limits_hold_95_percent(row, where)


@pytest.mark.slow
def test_one_sided_limits_at_the_edges_of_the_range_hold_the_truth_as_promised(study):
    # Impact parameters within 5 mm of the ends of the study's range, mu = 0.203 just below
    # every table's onset of sticking (0.206-0.2125): the onsets lie within one to three
    # errors of the truth, where tables simulated around the best fit's prediction reject
    # the truth too often. About one table in five reports a limit (429
    # tables, about 40 minutes), too few to hold their share to +-2 %, so it is held to the
    # binomial count of a 95 % limit. The e* intervals are held to the inside criteria;
    # mu's intervals are those of the tables not flat above (their best values lie below
    # the truth), and only too few holding the truth fail.
    records = _records(study, ["edges_low"], 429)
    for row in summarize(records):
        where = row["param"]
        assert row["refused"] == 0 and row["zero_width"] == 0, where
        if row["param"] == "e":
            assert abs(row["mean_pull"]) <= 0.1, where
            assert abs(row["interval_coverage"] - 0.68) <= 0.03, where
        if row["param"] == "mu":
            assert row["interval_coverage"] >= 0.65, where
            assert row["limits"] >= 60, where
            _assert_limits_hold_95_percent(row, where)


@pytest.mark.slow
def test_one_sided_limits_with_the_truth_at_each_tables_onset_of_sticking_hold_it(study):
    # At a table's own onset of sticking every drop sticks: its data are distributed as at
    # mu = 2, and a limit excludes the truth no more often than it excludes mu = 2. Most
    # tables report a limit, and at least 95 % of those limits must hold the truth.
    records = _records(study, ["plateau"], 200)
    row = next(r for r in summarize(records) if r["param"] == "mu")
    assert row["limits"] >= 150 and row["refused"] == 0 and row["zero_width"] == 0
    assert row["limit_coverage"] >= 0.95


@pytest.mark.slow
def test_tables_reaching_beyond_the_studys_range_fit_without_bias(study):
    # True impact parameters in +-4 cm against the study's +-1 in: fitted (never refused)
    # with mean pulls within +-0.3 over 50 tables.
    records = _records(study, ["wide"], 50)
    for row in summarize(records):
        assert row["refused"] == 0 and row["zero_width"] == 0, row["param"]
        assert abs(row["mean_pull"]) <= 0.3, row["param"]


@pytest.mark.slow
def test_an_interval_below_a_plateau_the_95_percent_level_reaches_says_so(study):
    # Table 5 of "stick" (truth mu = 0.5, every drop sticks): one row looks as if it slid,
    # and the best fit sits at mu = 0.203 +- 0.004 just below the plateau of mu where all
    # rows stick, which lies less than the 95 % level above it.
    record = fit_table("stick", 5, study)
    mu = record["params"]["mu"]
    assert mu["status"] == "measured" and mu["open_at_95"] == 2.0
    assert any("at 95 % the data do not bound mu from above" in w for w in record["warnings"])
    # A table whose rows slide bounds mu at 95 % as well: no such warning.
    inside = fit_table("inside", 0, study)
    assert "open_at_95" not in inside["params"]["mu"] and not inside["warnings"]


@pytest.mark.parametrize("k", [0, 1, 2, 3])
def test_the_fits_likelihood_has_the_exact_marginal_likelihoods_score_at_the_truth(study, k):
    """mcbat's likelihood (draws of the impact parameters and contact points, its prior
    fitted with the parameters) and the exact marginal likelihood (both integrated by
    quadrature over their true distributions) have nearly the same gradient at the truth:
    the best fits they lead to differ by far less than half an error."""
    from harness.fit_validation import make_table
    from harness.textbook_fit import marginal_neg_log_likelihood
    from mcbat.stats.fit.likelihood import Likelihood

    table = make_table("inside", k)
    truth = np.array([0.6, 0.18])
    exact_rows = marginal_neg_log_likelihood(table, nodes=64, contact_nodes=8)
    like = Likelihood(study, table, ["e", "mu"], seed=k)
    like.refine(truth)

    def exact(p):
        return float(exact_rows(*p).sum())

    def gradient(f, p, h=2e-5):
        return np.array([(f(p + h * d) - f(p - h * d)) / (2 * h) for d in np.eye(2)])

    step = 5e-4  # a quarter of the errors
    hessian = np.array([(gradient(exact, truth + step * d) - gradient(exact, truth - step * d))
                        / (2 * step) for d in np.eye(2)])
    inverse = np.linalg.inv(0.5 * (hessian + hessian.T))
    shift = inverse @ (gradient(like, truth) - gradient(exact, truth))
    assert np.all(np.abs(shift) < 0.5 * np.sqrt(np.diag(inverse)))


@pytest.mark.slow
def test_the_test_behind_a_limit_rejects_the_truth_where_the_limit_excludes_it(study):
    # Table 1002 of "onset_low" (truth mu = 0.19) looks flat above and reports the lower
    # limit 0.1949: it excludes the truth. The conditional test at the truth, with a
    # profile and a grid of its own, rejects it at 95 % too; table 7's limit (0.179) holds
    # the truth, which the test does not reject.
    from harness.fit_validation import limit_p_value

    missed = limit_p_value("onset_low", 1002, study)
    assert missed["status"] == "lower_limit" and missed["limit"] > missed["truth"]
    assert missed["flat"] and missed["p_value"] < 0.05 and missed["rise"] > 1.0
    held = limit_p_value("onset_low", 7, study)
    assert held["status"] == "lower_limit" and held["limit"] < held["truth"]
    assert held["flat"] and held["p_value"] > 0.05
    # A table bounded on both sides reports no limit and is not tested.
    bounded = limit_p_value("onset_low", 0, study)
    assert bounded["status"] == "measured" and "p_value" not in bounded


def test_p_value_shares_count_at_or_below_each_level():
    from harness.fit_validation import p_value_shares

    shares = p_value_shares([0.01, 0.05, 0.3, 1.0], levels=(0.05, 0.5))
    assert [(a, s) for a, s, _ in shares] == [(0.05, 0.5), (0.5, 0.75)]
    assert math.isclose(shares[0][2], math.sqrt(0.05 * 0.95 / 4))


def test_refitted_limits_replace_the_earlier_records_of_their_tables(tmp_path):
    import json

    from validation.drop_fit_checks import BASE, limit_jobs, read_records

    def record(k, limit, tag):
        return {"setting": "edges_low", "table": k, "tag": tag,
                "params": {"e": {"limit": None}, "mu": {"limit": limit}}}

    earlier = [record(0, None, "earlier"), record(1, 0.2, "earlier"), record(2, 0.19, "earlier")]
    assert limit_jobs(earlier) == [("edges_low", 1), ("edges_low", 2)]
    (tmp_path / BASE).write_text("".join(json.dumps(r) + "\n" for r in earlier))
    # A refit's file sorts before the base by name, yet the refit wins.
    (tmp_path / "a.0.jsonl").write_text(json.dumps(record(1, 0.195, "refit")) + "\n")
    merged = {r["table"]: r for r in read_records(tmp_path)}
    assert [merged[k]["tag"] for k in (0, 1, 2)] == ["earlier", "refit", "earlier"]
    assert merged[1]["params"]["mu"]["limit"] == 0.195
    assert [r["table"] for r in read_records(tmp_path, base=False)] == [1]
