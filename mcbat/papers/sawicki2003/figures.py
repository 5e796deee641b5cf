"""Figures of the optimal-swing reproduction (``mcbat reproduce sawicki2003``).

Each function takes the scans (``(pitch, model) -> (Scan, cell means)``), draws one PNG
into ``fig_dir`` and returns its path.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

__all__ = ["distance_vs_launch_angle", "distance_vs_undercut", "spray_chart"]

_COLOUR = {"fastball": "tab:red", "curveball": "tab:blue"}
_STYLE = {"rigid": "--", "compliant": "-"}
_MARKER = {"rigid": "x", "compliant": "o"}


def distance_vs_undercut(fig_dir, scans, results):
    """Mean carry against undercut at each pitch and model's best attack angle."""
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for (pitch, model), (_, means) in scans.items():
        best = results[pitch][model]
        cut = means["attack_angle"] == best["attack_angle"]
        u, d, se = means["undercut"][cut], means["distance"][cut], means["distance_se"][cut]
        ax.plot(u, d, _STYLE[model], color=_COLOUR[pitch],
                label=f"{pitch}, {model} (attack {best['attack_angle']:.0f}°)")
        ax.fill_between(u, d - se, d + se, color=_COLOUR[pitch], alpha=0.15, lw=0)
        ax.plot(best["undercut"], best["distance"], "o", color=_COLOUR[pitch], ms=6,
                mfc="white" if model == "rigid" else _COLOUR[pitch])
    ax.set_xlabel("undercut (in; > 0: bat axis below the ball's centre)")
    ax.set_ylabel("mean carry (ft)")
    ax.set_title("Carry against undercut, at the best attack angle "
                 "(band: ±1 standard error; dot: optimum)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower center")
    path = fig_dir / "distance_vs_undercut.png"
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def _field(ax):
    """Foul lines to 330 ft and an illustrative fence (330 ft at the lines, 400 ft in
    centre field)."""
    line = 330.0
    for sign in (-1.0, 1.0):
        ax.plot([0.0, sign * line / np.sqrt(2.0)], [0.0, line / np.sqrt(2.0)], color="0.5",
                lw=1)
    spray = np.radians(np.linspace(-45.0, 45.0, 91))
    fence = 400.0 - 70.0 * (np.abs(spray) / np.radians(45.0)) ** 1.5
    ax.plot(fence * np.sin(spray), fence * np.cos(spray), color="0.5", lw=1, ls=":")


def spray_chart(fig_dir, scans, results):
    """Landing points of the balls hit in each pitch and model's optimal cell."""
    fig, ax = plt.subplots(figsize=(6.4, 6.0))
    _field(ax)
    for (pitch, model), (scan, _) in scans.items():
        best = results[pitch][model]
        cell = ((scan.attack_angle == best["attack_angle"])
                & (scan.undercut == best["undercut"]) & scan.ok)
        ax.scatter(scan.flight["landing_x"][cell], scan.flight["landing_y"][cell], s=10,
                   marker=_MARKER[model], color=_COLOUR[pitch], alpha=0.6, lw=0.8,
                   label=f"{pitch}, {model}: {best['distance']:.0f} ft")
    ax.set_aspect("equal")
    ax.set_xlabel("x (ft, towards first base)")
    ax.set_ylabel("y (ft, towards centre field)")
    ax.set_title("Landing points at the optimum (fence illustrative)", fontsize=10)
    ax.legend(fontsize=8, loc="lower left")
    ax.set_xlim(-320, 320)
    ax.set_ylim(-20, 540)
    ax.grid(alpha=0.2)
    path = fig_dir / "spray_chart.png"
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def distance_vs_launch_angle(fig_dir, scans, model="compliant"):
    """Carry against launch angle, coloured by launch speed (Statcast's view), for every
    ball of both pitches' scans with ``model``."""
    pitches = [p for (p, m) in scans if m == model]
    fig, axes = plt.subplots(1, len(pitches), figsize=(11, 4.6), sharey=True)
    speeds = np.concatenate([scans[p, model][0].batted["launch_speed"] for p in pitches])
    lo, hi = np.nanpercentile(speeds, [1, 99])
    for ax, pitch in zip(np.atleast_1d(axes), pitches):
        scan = scans[pitch, model][0]
        keep = scan.ok & np.isfinite(scan.flight["hit_distance"])
        sc = ax.scatter(scan.batted["launch_angle"][keep], scan.flight["hit_distance"][keep],
                        c=scan.batted["launch_speed"][keep], s=2, cmap="viridis", vmin=lo,
                        vmax=hi, rasterized=True)
        ax.set_title(f"{pitch} ({model} model, {keep.sum():,} balls)", fontsize=10)
        ax.set_xlabel("launch angle (deg)")
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("carry (ft)")
    fig.colorbar(sc, ax=axes, label="launch speed (mph)")
    path = fig_dir / "distance_vs_launch_angle.png"
    fig.savefig(path, dpi=130, bbox_inches="tight")
    plt.close(fig)
    return path
