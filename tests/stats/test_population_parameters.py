"""The free parameters of a population fit (mcbat.stats.population.parameters): a
parameter the study does not have, or cannot fit, refused with one line naming it."""

import pytest

import mcbat
from mcbat.errors import InputError
from mcbat.statcast import read
from mcbat.stats.population.fit import fit_population, population_table
from tests.stats.population_shared import REAL, ROOT, STUDY, assert_one_line_exit_2, run_mcbat


@pytest.fixture(scope="module")
def pitches():
    table, _ = population_table(read(REAL))
    return table




@pytest.mark.parametrize("free, words", [
    ("swing.bat_speed.mean,swing.nothing.mean", ["--free", "swing.nothing"]),
    ("swing.bat_speed.width", ["--free", "unknown parameter"]),
    ("pitch.speed.mean", ["--free", "measured row by row"]),
    ("friction.mu.mean", ["--free", "friction.mu"]),
])
def test_parameters_the_study_does_not_have(free, words):
    proc = run_mcbat("fit", "--population", "--study", str(STUDY), "--data", str(REAL),
                  "--free", free)
    assert_one_line_exit_2(proc, *words)


def test_uniform_key_is_refused(pitches):
    # studies/real_pitches.toml draws the undercut uniformly: no mean and std to fit
    game = mcbat.load_study(ROOT / "studies" / "real_pitches.toml")
    with pytest.raises(InputError, match="uniform distribution"):
        fit_population(game, pitches, ["contact.undercut.mean"])
