"""The textbook fit of drop tables (every input known, plain maximum likelihood): an
independent check on the fit's intervals."""

import pytest

from harness.drop_tables import drop_table, kernel_solver
from harness.textbook_fit import (
    marginal_fit,
    marginal_neg_log_likelihood,
    mu_information_share,
    textbook_fit,
)


def exact_table(k):
    """Table ``k`` of the drop test with exact impact parameters (seed as the validation's)."""
    return drop_table(60, 1000 + k, solver=kernel_solver, impact_parameter_err=0.0)


@pytest.mark.parametrize("k", [0, 3])
def test_textbook_interval_agrees_with_the_cramer_rao_error(k):
    table = exact_table(k)
    r = textbook_fit(table)
    share, fisher_error = mu_information_share(table)
    width = 0.5 * (r["lower_error"] + r["upper_error"])
    # Two independent routes to mu's error: the profile's rise of 1/2 at the best fit and
    # the Fisher matrix from the Jacobian at the truth. They agree where the likelihood is
    # near quadratic; they cannot differ by much on 60 rows with 3 observables each.
    assert 0.7 < width / fisher_error < 1.3
    assert abs(r["mu"] - 0.18) < 4 * width
    assert abs(r["e"] - 0.6) < 0.01
    # Each row's share is non-negative, so three of sixty rows carry at least 3/60.
    assert 3 / 60 <= share <= 1.0


@pytest.mark.slow
def test_fit_with_exact_inputs_matches_the_textbook_fit():
    """mcbat's fit (axial contact marginalised over the study's range) and the textbook fit
    (the true contact points) of the same exact-b table agree within half an error."""
    from pathlib import Path

    from mcbat.stats.fit.estimate import fit
    from mcbat.study import load_study

    study = load_study(Path(__file__).resolve().parents[2] / "studies" / "cross_nathan_2006.toml")
    table = exact_table(2)
    ours = fit(study, table, ("e", "mu"), seed=2).params["mu"]
    r = textbook_fit(table)
    assert abs(ours - r["mu"]) < 0.5 * 0.5 * (r["lower_error"] + r["upper_error"])


def test_marginal_fit_converges_in_its_nodes_and_is_the_textbook_fit_for_exact_inputs():
    table = drop_table(60, 1000, solver=kernel_solver)
    textbook = textbook_fit(table)
    scale = min(textbook["lower_error"], textbook["upper_error"])  # mu's error, ~0.002
    coarse, fine = marginal_fit(table, nodes=128), marginal_fit(table, nodes=256)
    # Doubling the nodes moves the best fit by under a hundredth of mu's error (e*'s error
    # is of the same size), far below the shifts the marginal fit is used to measure.
    assert abs(coarse["e"] - fine["e"]) < 0.01 * scale
    assert abs(coarse["mu"] - fine["mu"]) < 0.01 * scale
    # Impact parameters measured to 10 um: the marginal fit is the textbook fit.
    exact = drop_table(60, 1000, solver=kernel_solver, impact_parameter_err=1e-5)
    marginal = marginal_fit(exact)
    assert abs(marginal["e"] - textbook["e"]) < 0.005 * scale
    assert abs(marginal["mu"] - textbook["mu"]) < 0.005 * scale


def test_marginal_likelihood_over_contact_points_converges_in_its_nodes():
    table = drop_table(60, 1000, solver=kernel_solver)

    def rise(nodes, contact_nodes):
        """-ln L one and a half errors of e* from the truth, above its value there."""
        nll = marginal_neg_log_likelihood(table, nodes=nodes, contact_nodes=contact_nodes)
        return float(nll(0.603, 0.18).sum() - nll(0.6, 0.18).sum())

    coarse, fine = rise(64, 8), rise(128, 16)
    # The rise is of order 1; the fit comparisons need it to a few hundredths at 3000 rows.
    assert abs(coarse) > 0.1
    assert abs(coarse - fine) < 0.01
    # Not knowing the contact points loses information: the rise differs from the one
    # with the true contact points.
    assert abs(coarse - rise(128, 0)) > 0.01
