"""Figures of ``mcbat reproduce statcast``: each function takes the long table of
:func:`~mcbat.papers.statcast.reproduce.compare_file`, draws one PNG into ``fig_dir`` and
returns its path. One panel per flight; the first spin model's balls."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from mcbat.papers.statcast.compare import COMPARED, launch_angle_bins  # noqa: E402

__all__ = ["predicted_vs_measured", "residual_vs_launch_angle"]

_STYLE = {"catch": ("tab:blue", "o", "outfield catch (at 6 ft)"),
          "home_run": ("tab:red", "^", "home run (projected to the ground)"),
          "hit": ("tab:gray", "s", "hit in play (first bounce or wall)")}


def _panels(long):
    """Per flight, the first spin model's compared balls with a prediction."""
    spin = long["spin_model"].cat.categories[0]
    flights = [f for f in long["flight"].cat.categories if (long["flight"] == f).any()]
    parts = []
    for flight in flights:
        part = long[(long["spin_model"] == spin) & (long["flight"] == flight)
                    & long["comparison"].isin(COMPARED)
                    & np.isfinite(long["predicted_distance"])]
        parts.append((flight, part))
    return spin, parts


def predicted_vs_measured(fig_dir, long):
    """Predicted against measured distance, by comparison class, one panel per flight."""
    spin, parts = _panels(long)
    fig, axes = plt.subplots(1, len(parts), figsize=(5.2 * len(parts), 5.0), squeeze=False,
                             sharex=True, sharey=True)
    lo = min(p["hit_distance_sc"].min() for _, p in parts) - 10
    hi = max(max(p["hit_distance_sc"].max(), p["predicted_distance"].max())
             for _, p in parts) + 10
    for ax, (flight, part) in zip(axes[0], parts):
        for kind, (colour, marker, label) in _STYLE.items():
            sel = part[part["comparison"] == kind]
            ax.scatter(sel["hit_distance_sc"], sel["predicted_distance"], s=14,
                       c=colour, marker=marker, alpha=0.7, lw=0, label=label)
        ax.plot([lo, hi], [lo, hi], color="k", lw=1)
        med = np.median(part["residual"])
        ax.set_title(f"flight {flight!r}: median predicted - measured {med:+.1f} ft "
                     f"(n = {len(part)})", fontsize=9)
        ax.set_xlabel("measured hit_distance_sc (ft)")
        ax.set_xlim(lo, hi)
        ax.set_ylim(lo, hi)
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel(f"predicted distance (ft; spin model {spin!r})")
    axes[0, 0].legend(fontsize=8, loc="upper left")
    path = fig_dir / "predicted_vs_measured.png"
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def residual_vs_launch_angle(fig_dir, long):
    """Predicted minus measured against launch angle, with the median of the catches and
    home runs per 10-degree bin, one panel per flight."""
    spin, parts = _panels(long)
    fig, axes = plt.subplots(1, len(parts), figsize=(5.2 * len(parts), 4.6), squeeze=False,
                             sharex=True, sharey=True)
    for ax, (flight, part) in zip(axes[0], parts):
        for kind, (colour, marker, label) in _STYLE.items():
            sel = part[part["comparison"] == kind]
            ax.scatter(sel["launch_angle"], sel["residual"], s=14, c=colour, marker=marker,
                       alpha=0.7, lw=0, label=label)
        core = part[part["comparison"].isin(("catch", "home_run"))]
        bins = launch_angle_bins(core["launch_angle"])
        centres, medians = [], []
        for b in np.unique(bins):
            r = core["residual"][bins == b]
            if len(r) >= 3:
                centres.append(b + 5.0)
                medians.append(np.median(r))
        ax.plot(centres, medians, "k-o", ms=5, lw=1.5,
                label="median of catches and home runs (10° bins, n >= 3)")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.axhspan(-5.0, 5.0, color="tab:green", alpha=0.1, lw=0)
        ax.set_title(f"flight {flight!r} (band: ±5 ft)", fontsize=9)
        ax.set_xlabel("launch angle (deg)")
        ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel(f"predicted - measured (ft; spin model {spin!r})")
    axes[0, 0].legend(fontsize=7, loc="lower left")
    path = fig_dir / "residual_vs_launch_angle.png"
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path
