"""Figures of fits: ``fig_fit_residuals`` (``mcbat fit --residuals``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from mcbat.stats.columns import BAT_FRAME_COLUMNS, GAME_TABLE_COLUMNS

__all__ = ["fig_fit_residuals"]


def fig_fit_residuals(path, table, result) -> Path:
    """Normalised residuals of a fit (``mcbat fit --residuals``) against the measured impact
    parameter (a drop test), the undercut (a game) or the row number."""
    fig = Figure(figsize=(7.2, 4.6), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    r = np.asarray(result.residuals)
    columns = {**BAT_FRAME_COLUMNS, **GAME_TABLE_COLUMNS}
    names = [c for c, (_, role) in columns.items() if role == "observable" and c in table]
    along = next((c for c in ("impact_parameter", "undercut") if c in table), None)
    if along is None:
        x, label = np.arange(1, len(table) + 1), "row"
    else:
        x, label = table[along].to_numpy(float) / 0.0254, f"{along.replace('_', ' ')} (inches)"
    markers = ("o", "s", "^")
    for j, name in enumerate(names):
        ax.scatter(x, r[:, j], s=18, marker=markers[j % 3], label=name.replace("_", " "))
    ax.axhline(0.0, color="0.3", lw=1)
    for level in (-2, 2):
        ax.axhline(level, color="0.6", lw=0.8, ls="--")
    params = ", ".join(f"{k} = {v:.4g} ± {result.stderr[k]:.2g}"
                       for k, v in result.params.items())
    ax.set_title(f"fit residuals: {params}\nchi2/dof = {result.chi2:.1f}/{result.dof}, "
                 f"p = {result.p_value:.3f}", fontsize=10)
    ax.set_xlabel(label)
    ax.set_ylabel("(measured − model) / sigma")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    path = Path(path)
    fig.savefig(path, dpi=150, bbox_inches="tight")
    return path
