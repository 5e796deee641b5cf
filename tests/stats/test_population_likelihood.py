"""The binned cost of a population fit (mcbat.stats.population.likelihood) where MINOS
steps outside a parameter's domain."""

import numpy as np

from mcbat.stats.population.likelihood import BinnedCost
from mcbat.stats.population.parameters import FreeKey


def _cost():
    rng = np.random.default_rng(1)
    x = rng.normal(6.0, 3.0, 2000)
    key = FreeKey("contact.from_barrel_end", "from_barrel_end", "normal", "in", 0.0254, 6.0,
                  3.0)
    logq = key.logpdf(x, 6.0, 3.0)
    edges = np.quantile(x, [0.25, 0.5, 0.75])
    idx = np.searchsorted(edges, x, side="right")
    n = np.bincount(np.searchsorted(edges, rng.normal(6.5, 3.0, 500), side="right"),
                    minlength=4).astype(float)
    params = [("contact.from_barrel_end.mean", "contact.from_barrel_end", "mean"),
              ("contact.from_barrel_end.std", "contact.from_barrel_end", "std")]
    return BinnedCost(n, {"contact.from_barrel_end": key}, params, [], {},
                      {"contact.from_barrel_end": x}, logq, {(): idx}, 4)


def test_a_width_that_is_not_positive_is_a_wall_not_an_error():
    cost = _cost()
    inside = cost([6.5, 3.0])
    assert np.isfinite(inside) and inside < 1e3
    for width in (0.0, -5.6):
        assert cost([6.5, width]) == 1e30
