"""Figures of ``mcbat reproduce statcast``: each function takes the long table of
``mcbat.papers.statcast.reproduce.compare_file``, draws one PNG into ``fig_dir`` and
returns its path. One row of panels per spin model, one column per flight."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from mcbat.papers.statcast.compare import (  # noqa: E402
    COMPARED,
    eligible_window,
    launch_angle_bins,
)

__all__ = ["predicted_vs_measured", "residual_breakdowns", "residual_vs_launch_angle"]

_STYLE = {"catch": ("tab:blue", "o", "outfield catch (at 6 ft)"),
          "home_run": ("tab:red", "^", "home run (projected to the ground)"),
          "hit": ("tab:gray", "s", "hit in play (first bounce or wall)")}


def _panels(long):
    """Per spin model and flight, the compared balls with a prediction."""
    spins = [s for s in long["spin_model"].cat.categories if (long["spin_model"] == s).any()]
    flights = [f for f in long["flight"].cat.categories if (long["flight"] == f).any()]
    return [[(spin, flight, long[(long["spin_model"] == spin) & (long["flight"] == flight)
                                 & long["comparison"].isin(COMPARED)
                                 & np.isfinite(long["predicted_distance"])])
             for flight in flights] for spin in spins]


def _figure(grid, height):
    rows, cols = len(grid), len(grid[0])
    return plt.subplots(rows, cols, figsize=(5.2 * cols, height * rows), squeeze=False,
                        sharex=True, sharey=True)


#: The widest distance axis drawn (ft): a value beyond (a launch speed of 1e20 flown to
#: 1e30 ft) is off the axes rather than stretching them past what matplotlib can draw.
DISTANCE_AXIS = (-100.0, 2000.0)


def _distance_limits(parts):
    """The axis limits (ft) of the distance panels: the finite values' range with a 10 ft
    margin, within ``DISTANCE_AXIS`` (0..500 ft when nothing is finite)."""
    values = np.concatenate([np.asarray(p[c], float) for p in parts
                             for c in ("hit_distance_sc", "predicted_distance")] or [[]])
    values = values[np.isfinite(values)]
    if values.size == 0:
        return 0.0, 500.0
    low, high = DISTANCE_AXIS
    lo = float(np.clip(values.min() - 10.0, low, high - 20.0))
    hi = float(np.clip(values.max() + 10.0, lo + 20.0, high))
    return lo, hi


def predicted_vs_measured(fig_dir, long):
    """Predicted against measured distance, by comparison class."""
    grid = _panels(long)
    fig, axes = _figure(grid, 5.0)
    parts = [p for row in grid for _, _, p in row]
    lo, hi = _distance_limits(parts)
    for ax, (spin, flight, part) in zip(axes.ravel(), (c for row in grid for c in row)):
        for kind, (colour, marker, label) in _STYLE.items():
            sel = part[part["comparison"] == kind]
            ax.scatter(sel["hit_distance_sc"], sel["predicted_distance"], s=14,
                       c=colour, marker=marker, alpha=0.7, lw=0, label=label)
        ax.plot([lo, hi], [lo, hi], color="k", lw=1)
        finite = part["residual"].to_numpy(float)
        finite = finite[np.isfinite(finite)]
        med = f"{np.median(finite):+.1f} ft" if finite.size else "none"
        ax.set_title(f"spin {spin!r}, flight {flight!r}: median predicted - measured "
                     f"{med} (n = {finite.size})", fontsize=8)
        ax.set_xlim(lo, hi)
        ax.set_ylim(lo, hi)
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("measured hit_distance_sc (ft)")
    for ax in axes[:, 0]:
        ax.set_ylabel("predicted distance (ft)")
    axes[0, 0].legend(fontsize=7, loc="upper left")
    path = fig_dir / "predicted_vs_measured.png"
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def residual_vs_launch_angle(fig_dir, long):
    """Predicted minus measured against launch angle, with the median of the catches and
    home runs per 10-degree bin."""
    grid = _panels(long)
    fig, axes = _figure(grid, 4.2)
    for ax, (spin, flight, part) in zip(axes.ravel(), (c for row in grid for c in row)):
        for kind, (colour, marker, label) in _STYLE.items():
            sel = part[part["comparison"] == kind]
            ax.scatter(sel["launch_angle"], sel["residual"], s=14, c=colour, marker=marker,
                       alpha=0.7, lw=0, label=label)
        core = part[part["comparison"].isin(("catch", "home_run"))]
        bins = launch_angle_bins(core["launch_angle"])
        centres, medians = [], []
        for b in np.unique(bins):
            r = core["residual"][bins == b]
            r = r[np.isfinite(r)]
            if len(r) >= 3:
                centres.append(b + 5.0)
                medians.append(np.median(r))
        ax.plot(centres, medians, "k-o", ms=5, lw=1.5,
                label="median of catches and home runs (10° bins, n >= 3)")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.axhspan(-5.0, 5.0, color="tab:green", alpha=0.1, lw=0)
        ax.set_title(f"spin {spin!r}, flight {flight!r} (band: ±5 ft)", fontsize=8)
        ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("launch angle (deg)")
    for ax in axes[:, 0]:
        ax.set_ylabel("predicted - measured (ft)")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=7, frameon=False)
    path = fig_dir / "residual_vs_launch_angle.png"
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def _median_with_error(residual):
    """Median and its standard error (1.2533 sigma / sqrt(n), sigma from the MAD)."""
    r = residual[np.isfinite(residual)]
    if r.size < 2:
        return np.nan, np.nan, r.size
    sigma = 1.4826 * np.median(np.abs(r - np.median(r)))
    return float(np.median(r)), 1.2533 * sigma / np.sqrt(r.size), r.size


def residual_breakdowns(fig_dir, rows, min_balls=20,
                        name="residual_by_season_month_temperature.png", title=""):
    """The median residual of the fly balls and home runs of 20-50 deg, with its error,
    by season, by calendar month and by game temperature (groups of at least
    ``min_balls``): ``rows`` are the long table's rows of one flight and spin model."""
    window = rows[eligible_window(rows)]
    residual = window["residual"].to_numpy(float)
    dates = pd.to_datetime(window["game_date"], errors="coerce")
    groups = {
        "season": window["game_year"].to_numpy(float),
        "month": dates.dt.month.to_numpy(float),
        "game temperature (degF, 5-degree bins)":
            np.floor(window["temperature"].to_numpy(float) / 5.0) * 5.0 + 2.5,
    }
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), sharey=True)
    for ax, (label, key) in zip(axes, groups.items()):
        xs, meds, errs, ns = [], [], [], []
        for value in np.unique(key[np.isfinite(key)]):
            med, err, n = _median_with_error(residual[key == value])
            if n >= min_balls:
                xs.append(value)
                meds.append(med)
                errs.append(err)
                ns.append(n)
        ax.errorbar(xs, meds, yerr=errs, fmt="o-", color="tab:blue", capsize=3)
        for x, m, n in zip(xs, meds, ns):
            ax.annotate(str(n), (x, m), textcoords="offset points", xytext=(0, 8),
                        ha="center", fontsize=7, color="0.35")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.axhspan(-4.0, 4.0, color="tab:green", alpha=0.1, lw=0)
        ax.set_xlabel(label)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("median predicted - measured (ft)")
    fig.suptitle(f"{title}fly balls and home runs of 20-50 deg ({len(window)} balls; "
                 f"numbers: balls per point, groups of {min_balls} or more; band: +-4 ft)",
                 fontsize=9)
    path = fig_dir / name
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path
