"""The random distributions of study inputs (mcbat.study.distributions): the statistics of
what the sampler draws against the distributions' own."""

import math

import numpy as np
import pytest
from scipy import stats

from tests.study.cases import close, study


def test_uniform_statistics(all_kinds_sample):
    x = all_kinds_sample["axial"]
    n = x.size
    assert x.min() >= 0.05 and x.max() < 0.20
    width = 0.15
    close(x.mean(), 0.125, width / math.sqrt(12), n)
    assert abs(x.std() - width / math.sqrt(12)) < 0.01 * width / math.sqrt(12)
    counts, _ = np.histogram(x, bins=10, range=(0.05, 0.20))
    assert np.all(np.abs(counts - n / 10) < 5 * math.sqrt(n / 10))


def test_normal_statistics(all_kinds_sample):
    x = all_kinds_sample["ball_vx_in"]
    close(x.mean(), -20.0, 2.0, x.size)
    assert abs(x.std() - 2.0) < 0.02
    assert stats.kstest(x, "norm", args=(-20.0, 2.0)).pvalue > 1e-4


@pytest.mark.parametrize("column, low, high", [("ball_vy_in", -0.5, 2.0),
                                               ("ball_vz_in", 3.0, 5.0)])  # an upper tail
def test_truncnormal_statistics(all_kinds_sample, column, low, high):
    x = all_kinds_sample[column]
    assert x.min() >= low and x.max() <= high
    ref = stats.truncnorm(low, high)  # mean 0, std 1
    close(x.mean(), ref.mean(), ref.std(), x.size)
    assert abs(x.std() - ref.std()) < 0.02 * ref.std()
    assert stats.kstest(x, ref.cdf).pvalue > 1e-4


def test_choice_frequencies(all_kinds_sample):
    x = all_kinds_sample["ball_wx_in"]
    n = x.size
    assert set(np.unique(x)) == {-1.0, 0.0, 2.0}
    for value, p in ((-1.0, 1 / 8), (0.0, 2 / 8), (2.0, 5 / 8)):
        close(np.mean(x == value), p, math.sqrt(p * (1 - p)), n)


def test_choice_zero_weight_never_drawn():
    s = study(friction__mu={"dist": "choice", "values": [0.1, 0.2, 0.3], "weights": [0, 1, 0]})
    assert np.all(s.sample(0, 70_000)["mu"] == 0.2)


def test_mixture_statistics(all_kinds_sample):
    x = all_kinds_sample["bat_vx_in"]
    n = x.size
    fixed = x == 5.0
    close(fixed.mean(), 0.25, math.sqrt(0.25 * 0.75), n)
    rest = x[~fixed]
    assert rest.min() >= 0.0 and rest.max() < 1.0
    close(rest.mean(), 0.5, 1 / math.sqrt(12), rest.size)
