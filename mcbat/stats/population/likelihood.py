"""The binned likelihood of a population fit (``mcbat.stats.population.fit``): equal-count
bins of the data, and the cost of the reweighted, grid-interpolated templates in them."""

from __future__ import annotations

import numpy as np

__all__ = ["BinnedCost", "bin_index", "equal_count_edges", "grid_corners"]


def equal_count_edges(data, bins):
    """Interior edges of equal-count bins of ``data`` (the outer bins are open)."""
    q = np.quantile(data, np.arange(1, bins) / bins)
    return np.unique(q)


def bin_index(values, edges):
    """Flat bin index of every point (``values``: list of arrays, one per axis)."""
    idx = np.zeros(len(values[0]), np.int64)
    for v, e in zip(values, edges):
        idx = idx * (len(e) + 1) + np.searchsorted(e, v, side="right")
    return idx


class BinnedCost:
    """The binned cost at any parameter vector (reporting units)."""

    def __init__(self, n, keys, params, physics, nodes, draws_x, logq, idx, nbins):
        self.n, self.keys, self.params, self.physics = n, keys, params, physics
        self.nodes, self.x, self.logq, self.idx, self.nbins = nodes, draws_x, logq, idx, nbins
        self.total = float(n.sum())
        self.errordef = 1.0  # a chi2-like cost: intervals where it rises by 1

    def values(self, theta):
        """``{key: (mean, std)}`` and ``{physics: value}`` of a parameter vector."""
        dists = {key: [k.mean, k.std] for key, k in self.keys.items()}
        for (_, key, what), value in zip(self.params, theta):
            dists[key][0 if what == "mean" else 1] = value
        phys = dict(zip(self.physics, theta[len(self.params):]))
        return dists, phys

    def weights(self, theta):
        """The draws' weights at ``theta``."""
        dists, _ = self.values(theta)
        logw = -self.logq.copy()
        for key, (mean, std) in dists.items():
            logw += self.keys[key].logpdf(self.x[key], mean, std)
        return np.exp(logw - np.max(logw))

    def template(self, theta):
        """Sum and variance of the weights in each bin, interpolated between nodes."""
        w = self.weights(theta)
        _, phys = self.values(theta)
        t = np.zeros(self.nbins)
        v = np.zeros(self.nbins)
        for corner, c in grid_corners(self.nodes, phys):
            idx = self.idx[corner]
            good = idx >= 0
            t += c * np.bincount(idx[good], w[good], self.nbins)
            # correlated nodes (common random numbers): sum c_g V_g bounds the variance
            v += c * np.bincount(idx[good], w[good] ** 2, self.nbins)
        return t, v

    def __call__(self, theta):
        """The cost at ``theta`` (what MIGRAD minimises)."""
        from iminuit.cost import template_chi2_da

        theta = np.asarray(theta, float)
        # MINOS can try a width past its limit (seen at a mean held on its own limit): a
        # width that is not positive is no distribution, so the cost is a wall there
        if any(not theta[i] > 0.0 for i, (_, _, what) in enumerate(self.params)
               if what == "std"):
            return 1e30
        t, v = self.template(theta)
        s = t.sum()
        if not s > 0:
            return 1e30
        mu = np.maximum(self.total * t / s, 1e-12)
        var = np.maximum(self.total**2 * v / s**2, 1e-24)
        return float(template_chi2_da(self.n, mu, var))


def grid_corners(nodes, phys):
    """``(node index tuple, coefficient)`` of the multilinear interpolation at ``phys``."""
    if not nodes:
        return [((), 1.0)]
    parts = []
    for name, z in nodes.items():
        x = float(np.clip(phys[name], z[0], z[-1]))
        j = int(min(np.searchsorted(z, x, side="right") - 1, len(z) - 2))
        t = (x - z[j]) / (z[j + 1] - z[j])
        parts.append(((j, 1.0 - t), (j + 1, t)))
    out = [((), 1.0)]
    for pair in parts:
        out = [(c + (j,), a * b) for c, a in out for j, b in pair if b > 0.0]
    return out
