"""The figure of a comparison (``mcbat compare --figure``): both sides' histograms per
column, the launch speed / launch angle plane, and the per-row rank histograms."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from mcbat.stats.compare.two_sample import format_p
from mcbat.stats.compare.units import column_values, convert

__all__ = ["fig_compare"]


def fig_compare(path, simulated, measured, comparison):
    """Histograms of both sides per compared column (densities, with the KS distance and
    Wasserstein distance), the launch speed / launch angle plane side by side
    (simulated as a 2-D histogram, measured as points on the same axes), and when the
    dataset was drawn from the measured pitches, each judged column's histogram of the
    measured values' ranks among their own rows' draws (flat for a calibrated model) and,
    binned by a measured column, its measured and model means per bin."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    columns = comparison.columns
    plane = comparison.plane
    per_row = 3
    rows_1d = math.ceil(len(columns) / per_row)
    ranks = [c for c in (comparison.per_row or {}).get("columns", []) if c["rows"]]
    by = (comparison.per_row or {}).get("by")
    binned = [c for c in ranks if by and c.get("bins")]
    rows = (rows_1d + (1 if plane else 0) + math.ceil(len(ranks) / per_row)
            + math.ceil(len(binned) / per_row))
    fig = Figure(figsize=(4.0 * per_row, 3.1 * rows), layout="constrained")
    FigureCanvasAgg(fig)
    grid = fig.add_gridspec(rows, per_row * 2)
    for k, c in enumerate(columns):
        ax = fig.add_subplot(grid[k // per_row, 2 * (k % per_row):2 * (k % per_row) + 2])
        sim, meas, unit, *_ = column_values(c["column"], simulated[c["column"]],
                                             measured[c["column"]], c["units"]["simulated"],
                                             c["units"]["measured"])
        low, high = _shown_range(sim, meas)
        bins = np.linspace(low, high, 31)
        # values beyond the range (each side's outer 0.5 %) are not drawn, not piled into
        # the end bins
        ax.hist(sim, bins=bins, density=True, histtype="stepfilled",
                alpha=0.35, color="C0", label=f"simulated ({sim.size:,})")
        ax.hist(meas, bins=bins, density=True, histtype="step", lw=1.6,
                color="C3", label=f"measured ({meas.size:,})")
        ax.set_xlabel(f"{c['column']} ({unit})")
        ax.set_title(f"KS D = {c['ks']['statistic']:.3f}, W = {c['wasserstein']:.3g} {unit}",
                     fontsize=9)
        ax.tick_params(labelsize=8)
        ax.set_yticks([])
        if k == 0:
            ax.legend(fontsize=7)
    if plane:
        (cx, cy), (ux, uy) = plane["columns"], plane["units"]
        given = {c["column"]: c["units"] for c in columns}
        points = []
        for df, side in ((simulated, "simulated"), (measured, "measured")):
            xy = np.column_stack([convert(df[c].to_numpy(dtype=float),
                                          given[c][side] or u, u)
                                  for c, u in ((cx, ux), (cy, uy))])
            points.append(xy[np.isfinite(xy).all(axis=1)])
        extent = [*_shown_range(points[0][:, 0], points[1][:, 0]),
                  *_shown_range(points[0][:, 1], points[1][:, 1])]
        p_text = format_p(plane["p_value"], comparison.settings["p_value_resolution"])
        titles = (f"simulated ({len(points[0]):,} rows)",
                  f"measured ({len(points[1]):,} rows); energy distance "
                  f"{plane['distance']:.3f} (standardized), p {p_text}")
        axes = [fig.add_subplot(grid[rows_1d, 0:per_row]),
                fig.add_subplot(grid[rows_1d, per_row:2 * per_row])]
        axes[0].hist2d(points[0][:, 0], points[0][:, 1], bins=50,
                       range=[extent[:2], extent[2:]], cmap="Blues", cmin=1)
        axes[1].scatter(points[1][:, 0], points[1][:, 1], s=6, color="C3", alpha=0.6)
        for ax, title in zip(axes, titles):
            ax.set_title(title, fontsize=9)
            ax.set_xlabel(f"{cx} ({ux})")
            ax.set_ylabel(f"{cy} ({uy})")
            ax.set_xlim(extent[:2])
            ax.set_ylim(extent[2:])
            ax.grid(alpha=0.3)
    first = rows_1d + (1 if plane else 0)
    for k, c in enumerate(ranks):
        ax = fig.add_subplot(grid[first + k // per_row,
                                  2 * (k % per_row):2 * (k % per_row) + 2])
        _rank_histogram(ax, c)
    first += math.ceil(len(ranks) / per_row)
    for k, c in enumerate(binned):
        ax = fig.add_subplot(grid[first + k // per_row,
                                  2 * (k % per_row):2 * (k % per_row) + 2])
        _bin_means(ax, c, by)
    path = Path(path)
    fig.savefig(path, dpi=130)
    return path


def _rank_histogram(ax, column):
    """The measured values' ranks (PIT, ten bins) as densities, with an exact model's
    level and the 95 % range of one bin's."""
    counts = np.asarray(column["histogram"], float)
    level = counts.sum() / counts.size
    half = 1.96 * np.sqrt(level * (1 - 1 / counts.size)) / level
    ax.axhspan(1 - half, 1 + half, color="0.85", label="exact model, 95 %")
    ax.bar(np.arange(counts.size) / counts.size, counts / level, width=1 / counts.size,
           align="edge", color="C2", alpha=0.7, edgecolor="white", label="measured")
    ax.axhline(1, color="0.3", lw=1)
    ax.set_xlim(0, 1)
    ax.set_xlabel(f"{column['column']}: rank in its own row's draws (PIT)")
    ax.set_ylabel("density")
    ax.set_title(f"{column['rows']:,} rows: {100 * column['above_p90']:.1f} % above p90, "
                 f"{100 * column['below_p10']:.1f} % below p10", fontsize=9)
    ax.tick_params(labelsize=8)
    ax.legend(fontsize=7, loc="upper center")


def _bin_means(ax, column, by):
    """Per bin of ``by``'s column: the measured mean with its 95 % interval, and the
    model's mean of the rows' own draws."""
    bins = column["bins"]
    x = np.arange(len(bins))
    measured = np.array([b["measured"] for b in bins])
    half = np.array([1.96 * b["se"] if b["se"] is not None else np.nan for b in bins])
    ax.errorbar(x, measured, yerr=half, fmt="o", color="C3", capsize=3,
                label="measured (95 %)")
    ax.plot(x, [b["model"] for b in bins], "s", color="C0", label="model")
    ax.set_xticks(x, [f"{b['bin']}\n({b['rows']})" for b in bins], fontsize=7)
    unit = f" ({by['unit']})" if by.get("unit") else ""
    ax.set_xlabel(f"{by['column']}{unit} (rows)")
    ax.set_ylabel(f"{column['column']} ({column['unit']})")
    ax.set_title(f"mean {column['column']} by {by['column']}", fontsize=9)
    ax.grid(alpha=0.3)
    ax.tick_params(axis="y", labelsize=8)
    ax.legend(fontsize=7)


def _shown_range(a, b):
    """From the lower to the upper 0.5 % quantile of whichever side reaches further."""
    low = min(np.quantile(a, 0.005), np.quantile(b, 0.005))
    high = max(np.quantile(a, 0.995), np.quantile(b, 0.995))
    return (low, high) if high > low else (low - 0.5, high + 0.5)
