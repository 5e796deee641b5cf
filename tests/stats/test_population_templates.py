"""The template draws of a population fit (mcbat.stats.population.templates): the same
balls whichever engine solves them."""

import pytest

import mcbat
from mcbat.statcast import read
from mcbat.stats.population.fit import fit_population, population_table, simulate_table
from tests.stats.population_shared import REAL, STUDY


@pytest.fixture(scope="module")
def study():
    return mcbat.load_study(STUDY)


@pytest.fixture(scope="module")
def pitches():
    table, _ = population_table(read(REAL))
    return table


def test_engines_give_the_same_templates(study, pitches, tmp_path):
    # the local engine (run_study into a dataset, read back) and the in-process solve draw
    # the same balls: the same fit to the last digit
    table = simulate_table(study, pitches, 60, seed=3, values={})
    kw = {"draws": 10, "seed": 4, "passes": 1}
    memory = fit_population(study, table, ["swing.bat_speed.mean"], **kw)
    local = fit_population(study, table, ["swing.bat_speed.mean"], engine="local",
                           workdir=tmp_path, **kw)
    assert memory.parameters[0]["value"] == local.parameters[0]["value"]
    assert memory.chi2 == local.chi2
