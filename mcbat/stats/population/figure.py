"""The figure of a population fit: data against the fitted model (``mcbat fit --population
--figure``)."""

from __future__ import annotations

import numpy as np

from mcbat.stats.population.fit import OBSERVABLES, grid_corners

__all__ = ["fig_population", "model_histogram"]


def model_histogram(result, observables, edges):
    """The fitted model's expected counts (the table's row count) in ``edges`` of
    ``observables`` (one array of edges per observable), from the reweighted draws."""
    fd = result.figure_data
    cost, theta = fd["cost"], fd["theta"]
    w = cost.weights(theta)
    _, phys = cost.values(theta)
    axes = [result.observables.index(o) for o in observables]
    total = np.zeros([len(e) - 1 for e in edges])
    norm = 0.0
    for corner, c in grid_corners(cost.nodes, phys):
        values = cost.observed[corner]
        good = np.all(np.isfinite(values), axis=0)
        norm += c * w[good].sum()
        h, _ = np.histogramdd(values[axes][:, good].T, bins=edges, weights=w[good])
        total += c * h
    return total * result.rows / norm


def fig_population(path, result):
    """Write the figure: each observable's distribution (data with Poisson errors, the
    fitted model), the launch speed / angle plane (model density, data points) and the fit's
    bin pulls."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = result.figure_data["data"]
    obs = result.observables
    fig, axes = plt.subplots(1, len(obs) + 2, figsize=(4.2 * (len(obs) + 2), 4.0))
    for ax, o in zip(axes, obs):
        x = data[o].to_numpy(float)
        lo, hi = np.quantile(x, [0.005, 0.995])
        edges = np.linspace(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo), 31)
        n, _ = np.histogram(x, edges)
        model = model_histogram(result, (o,), [edges])
        centres = 0.5 * (edges[1:] + edges[:-1])
        ax.stairs(model, edges, color="C1", label="model (fitted)")
        ax.errorbar(centres, n, yerr=np.sqrt(n), fmt="o", ms=3, color="k", label="data")
        ax.set_xlabel(f"{o} ({OBSERVABLES[o]})")
        ax.set_ylabel("balls per bin")
    axes[0].legend(frameon=False, fontsize=8)
    ax = axes[len(obs)]
    if "launch_speed" in obs and "launch_angle" in obs:
        es = np.linspace(0, 125, 51)
        ea = np.linspace(-90, 90, 46)
        model = model_histogram(result, ("launch_speed", "launch_angle"), [es, ea])
        mesh = ax.pcolormesh(es, ea, model.T, cmap="Blues", shading="flat")
        fig.colorbar(mesh, ax=ax, label="model: balls per cell")
        ax.plot(data["launch_speed"], data["launch_angle"], ".", ms=2, color="C3",
                label="data")
        ax.set_xlabel("launch_speed (mph)")
        ax.set_ylabel("launch_angle (deg)")
        ax.legend(frameon=False, fontsize=8, loc="lower left")
    ax = axes[-1]
    cost = result.figure_data["cost"]
    t, v = cost.template(result.figure_data["theta"])
    n = result.figure_data["n"]
    mu = n.sum() * t / t.sum()
    var = n.sum() ** 2 * v / t.sum() ** 2
    pull = (n - mu) / np.sqrt(np.maximum(mu + var, 1e-12))
    shape = [len(e) + 1 for e in result.figure_data["edges"]]
    if len(shape) == 2:
        image = ax.imshow(pull.reshape(shape).T, origin="lower", cmap="RdBu_r", vmin=-3,
                          vmax=3, aspect="auto")
        fig.colorbar(image, ax=ax, label="(data - model) / sigma")
        ax.set_xlabel(f"{obs[0]} bin (equal-count)")
        ax.set_ylabel(f"{obs[1]} bin (equal-count)")
    else:
        ax.hist(pull, bins=20)
        ax.set_xlabel("(data - model) / sigma per fit bin")
    ax.set_title(f"fit bins: chi2/dof = {result.chi2:.1f}/{result.dof}, "
                 f"p = {result.p_value:.2f}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
