"""Figs. 6-8 of the paper's Sec. V: the Monte Carlo rows against the noise-free model,
per incoming spin, in three layers (a faint cloud of rows, the model curve, the Monte Carlo
median and 16-84 % band in bins; ``mcbat.papers.cabo2012.figures``)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from mcbat.papers.cabo2012 import sec5
from mcbat.papers.cabo2012.figure_style import (
    COMPLIANT_LINE,
    LEGEND_FONT,
    MEDIAN_LINE,
    MODEL_LINE,
    PAPER,
    new_figure,
    save_png,
    spin_style,
)
from mcbat.papers.cabo2012.summary import (
    INCH,
    MEASURED,
    model_curves,
    model_speed_at_zero_angle,
    nominal_spin,
    solved,
)
from mcbat.stats.analysis import binned

__all__ = ["MAX_CLOUD", "MIN_BIN_COUNT", "fig_speed_vs_angle", "fig_spin_vs_impact_parameter"]

MAX_CLOUD = 4000  # Monte Carlo points drawn per incoming spin
MIN_BIN_COUNT = 20  # bins with fewer rows get no median / band


def _spin_rows(df: pd.DataFrame | None, spins) -> dict[float, pd.DataFrame]:
    """Solved rows per nominal spin (only the spins asked for)."""
    if df is None or not len(df):
        return {float(w): pd.DataFrame() for w in spins}
    data = solved(df)
    nominal = nominal_spin(data)
    return {float(w): data[nominal == float(w)] for w in spins}


def _cloud(rows: pd.DataFrame, x: str, y: str, w0: float, seed: int = 0):
    """A random subsample (at most MAX_CLOUD) of ``rows`` as a frame ``w0, x, y``."""
    if not len(rows):
        return pd.DataFrame({"w0": [], "x": [], "y": [], "sample_id": []})
    take = rows
    if len(rows) > MAX_CLOUD:
        rng = np.random.default_rng(seed)
        take = rows.iloc[np.sort(rng.choice(len(rows), MAX_CLOUD, replace=False))]
    sid = take["sample_id"].to_numpy() if "sample_id" in take else np.arange(len(take))
    return pd.DataFrame({"w0": w0, "x": take[x].to_numpy(float),
                         "y": take[y].to_numpy(float), "sample_id": sid})


def _bands(rows: pd.DataFrame, x: str, y: str, w0: float, bins: int,
           scale: float = 1.0) -> pd.DataFrame:
    """Median and 16-84 % band of ``y`` in ``bins`` equal bins of ``x`` (count >= MIN)."""
    if len(rows) < MIN_BIN_COUNT:
        return pd.DataFrame()
    table = binned(rows, x, y, bins=bins)
    table = table[table["count"] >= MIN_BIN_COUNT].reset_index(drop=True)
    table.insert(0, "w0", w0)
    for col in ("x_low", "x_high", "x_center"):
        table[col] = table[col] * scale
    return table


def _limits(values, pad=0.05):
    values = np.asarray(values, float)
    values = values[np.isfinite(values)]
    lo, hi = float(values.min()), float(values.max())
    d = (hi - lo) * pad or 1.0
    return lo - d, hi + d


def _layered_plot(ax, rows_by_spin, model, xcol, ycol, *, model_x, model_y, xscale=1.0,
                  bins=24, seed=0):
    """Cloud + model curve + median/band per spin.

    Returns ``(data dict, model legend handles, Monte Carlo legend handles)``; the model
    list starts with one entry per spin.
    """
    def has(column):
        return column is not None and any(column in r.columns for r in rows_by_spin.values())

    measured_x = has(MEASURED.get(xcol))
    measured_y = has(MEASURED.get(ycol))
    cx = MEASURED[xcol] if measured_x else xcol
    cy = MEASURED[ycol] if measured_y else ycol
    clouds, bands, curves = [], [], []
    handles = []
    for k, (w0, rows) in enumerate(rows_by_spin.items()):
        st = spin_style(w0)
        cloud = _cloud(rows, cx, cy, w0, seed + k)
        cloud["x"] *= xscale
        clouds.append(cloud)
        if len(cloud):
            ax.scatter(cloud["x"], cloud["y"], s=3, color=st["color"], alpha=0.12,
                       lw=0, rasterized=True, zorder=1)
        band = _bands(rows, xcol, ycol, w0, bins, xscale)
        bands.append(band)
        if len(band):
            ax.fill_between(band["x_center"], band["q16"], band["q84"], color=st["color"],
                            alpha=0.25, lw=0, zorder=2)
            ax.plot(band["x_center"], band["q50"], color=st["color"], zorder=3,
                    **MEDIAN_LINE)
        curve = model[model["w0"] == w0].sort_values("impact_parameter")
        curves.append(curve)
        if len(curve):
            ax.plot(curve[model_x], curve[model_y], color=st["color"], zorder=4,
                    **MODEL_LINE)
            every = max(len(curve) // 30, 1)
            ax.plot(curve[model_x].iloc[::every], curve[model_y].iloc[::every], ls="none",
                    marker=st["marker"], mfc=st["mfc"], mec=st["color"], ms=5, mew=1.2,
                    zorder=4)
        handles.append(Line2D([], [], color=st["color"], marker=st["marker"],
                              mfc=st["mfc"], mec=st["color"], **MODEL_LINE,
                              label=f"$w_0$ = {st['name']}  ({st['fill']})"))
    n_rows = sum(len(r) for r in rows_by_spin.values())
    e_star = model.attrs.get("e_star")
    noise = " with measurement noise" if measured_x or measured_y else ""
    model_handles = [
        Line2D([], [], color="k", marker="o", mfc="white", ms=5, **MODEL_LINE,
               label="model, noise-free single impacts"
                     + (f" ($e^*$ = {e_star:.4f}, $\\mu$ = 0.5)" if e_star else "")),
    ]
    mc_handles = [
        Line2D([], [], color="0.3", ls="none", marker="o", ms=3, alpha=0.5,
               label=f"Monte Carlo rows{noise}\n({n_rows:,}; ≤ {MAX_CLOUD:,} drawn per spin)"),
        Line2D([], [], color="0.3", **MEDIAN_LINE,
               label="Monte Carlo median (model values)"),
        Patch(color="0.3", alpha=0.25, label="Monte Carlo 16–84 % band"),
    ]
    data = {"model": pd.concat(curves, ignore_index=True) if curves else pd.DataFrame(),
            "cloud": pd.concat(clouds, ignore_index=True) if clouds else pd.DataFrame(),
            "binned": pd.concat([b for b in bands if len(b)], ignore_index=True)
            if any(len(b) for b in bands) else pd.DataFrame(),
            "cloud_columns": (cx, cy), "measured": bool(measured_x or measured_y)}
    return data, handles + model_handles, mc_handles


def _legend_below(fig, model_handles, mc_handles):
    """The legend under the axes, model entries left and Monte Carlo entries right."""
    rows = max(len(model_handles), len(mc_handles))
    blank = Line2D([], [], ls="none", label=" ")
    handles = (model_handles + [blank] * (rows - len(model_handles))
               + mc_handles + [blank] * (rows - len(mc_handles)))
    fig.legend(handles=handles, loc="outside lower center", ncol=2,
               fontsize=LEGEND_FONT, framealpha=0.95, columnspacing=1.5, handlelength=3.0)


def _spin_figure(size, df, model, spins, xcol, ycol, *, model_x, model_y, xscale=1.0,
                 bins=24):
    """A new figure of ``size`` with the layers of ``_layered_plot`` for ``spins`` (the
    rows of ``df`` at each), framed by ``_window``.

    Returns ``(figure, axes, data dict, model legend handles, Monte Carlo legend
    handles)``.
    """
    fig = new_figure(size)
    ax = fig.add_subplot()
    data, handles, mc_handles = _layered_plot(ax, _spin_rows(df, spins), model, xcol, ycol,
                                              model_x=model_x, model_y=model_y,
                                              xscale=xscale, bins=bins)
    _window(ax, data, model_x, model_y)
    return fig, ax, data, handles, mc_handles


def _window(ax, data, model_x, model_y, pad=0.06):
    """Axis limits: the Monte Carlo range in x (the whole model without rows), then y
    over everything visible."""
    cloud, curve, band = data["cloud"], data["model"], data["binned"]
    if len(cloud):
        xs = np.concatenate([cloud["x"].to_numpy(),
                             band["x_center"].to_numpy() if len(band) else []])
    else:
        xs = curve[model_x].to_numpy()
    xlim = _limits(xs, pad)
    ys = [cloud["y"].to_numpy()] if len(cloud) else []
    if len(curve):
        inside = (curve[model_x] >= xlim[0]) & (curve[model_x] <= xlim[1])
        ys.append(curve.loc[inside, model_y].to_numpy())
    if len(band):
        ys += [band["q16"].to_numpy(), band["q84"].to_numpy()]
    ylim = _limits(np.concatenate(ys), pad)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    data["xlim"], data["ylim"] = xlim, ylim


# ---------------------------------------------------------------- Figs. 6, 7

def fig_speed_vs_angle(outdir, df: pd.DataFrame | None, model: pd.DataFrame,
                       w0_values=(0.0,), name: str = "fig6_speed_vs_angle_w0", *,
                       title: str | None = None, bins: int = 24) -> tuple[Path, dict]:
    """Figs. 6 and 7: exit speed against scattering angle ``alpha = atan2(v_y, v_x)``.

    Fig. 6 is ``w0_values=(0.0,)``; Fig. 7 is ``w0_values=(79.0, -72.0)``,
    ``name="fig7_speed_vs_angle_spin"`` (open circles +79, filled -72, as in the paper).

    Parameters
    ----------
    df : DataFrame or None
        Monte Carlo rows (``mcbat.load``); rows are assigned to the nominal spin
        nearest to ``ball_wz_in``. If it has ``exit_speed_measured`` and
        ``scattering_angle_measured``, the cloud is drawn from those (the median and band
        always from the noise-free ``exit_speed`` / ``scattering_angle``).
    model : DataFrame
        ``mcbat.papers.cabo2012.summary.model_curves``.
    title : str, optional
        Default: "Fig. N of the paper ..." with N from ``name`` (``fig6...``, ``fig7...``).

    Returns
    -------
    (Path, dict)
        ``data``: ``model`` (the model-curve rows drawn), ``cloud`` (``w0, x, y,
        sample_id`` of the drawn subsample; x deg, y m/s), ``binned`` (one row per drawn
        bin: ``w0``, the ``mcbat.stats.analysis.binned`` columns ``x_low, x_high, x_center,
        count, mean, q16, q50, q84``), ``cloud_columns``, ``measured``, ``xlim``, ``ylim``
        and ``alpha0`` (per spin: the model's exit speed at ``alpha = 0``).
    """
    w0_values = tuple(float(w) for w in w0_values)
    fig, ax, data, handles, mc_handles = _spin_figure(
        (7.6, 6.3), df, model, w0_values, "scattering_angle", "exit_speed",
        model_x="scattering_angle", model_y="exit_speed", bins=bins)
    alpha0 = {}
    for w0 in w0_values:
        curve = model[model["w0"] == w0]
        v0 = model_speed_at_zero_angle(curve) if len(curve) else math.nan
        alpha0[w0] = v0
        if w0 == 0.0 and math.isfinite(v0):
            ax.plot([0.0], [v0], marker="*", ms=14, mfc="gold", mec="k", ls="none",
                    zorder=6)
            handles.append(Line2D([], [], marker="*", ms=12, mfc="gold", mec="k",
                                  ls="none", label=f"calibration point: {v0:.4f} m/s "
                                  rf"at $\alpha$ = 0 (paper {sec5.TARGET_SPEED:g})"))
    data["alpha0"] = alpha0
    ax.axvline(0.0, color="0.6", lw=0.8)
    ax.set_xlabel(r"scattering angle $\alpha = \mathrm{atan2}(v_y, v_x)$ (deg; "
                  r"0 = straight back up)")
    ax.set_ylabel("exit speed of the ball (m/s)")
    if title is None:
        number = name[3] if name.startswith("fig") and name[3:4].isdigit() else "?"
        spins = ", ".join(spin_style(w)["name"].split(" (")[0] for w in w0_values)
        title = (f"Fig. {number} of {PAPER}: exit speed vs scattering angle, "
                 f"$w_0$ = {spins}\nball dropped at 4 m/s on a resting bat, "
                 "14–16 cm from the barrel end")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    _legend_below(fig, handles, mc_handles)
    path = save_png(fig, outdir, name)
    return path, data


# ---------------------------------------------------------------- Fig. 8

def fig_spin_vs_impact_parameter(outdir, df: pd.DataFrame | None, model: pd.DataFrame, *,
                                 spins=sec5.SPINS, bins: int = 24,
                                 name: str = "fig8_spin_vs_impact_parameter"
                                 ) -> tuple[Path, dict]:
    """Fig. 8: outgoing spin about the bat axis against the impact parameter (inches).

    All three incoming spins (open circles +79, squares 0, filled circles -72), layered
    as in ``fig_speed_vs_angle``; the cloud uses ``spin_axial_measured`` (and
    ``impact_parameter_measured``) when the dataset has them.

    Returns
    -------
    (Path, dict)
        As ``fig_speed_vs_angle``, with x the impact parameter in inches (the
        ``binned`` edges and centres in inches too) and y the spin ``w_z`` in rad/s.
    """
    spins = tuple(float(w) for w in spins)
    fig, ax, data, handles, mc_handles = _spin_figure(
        (7.6, 6.7), df, model, spins, "impact_parameter", "spin_axial",
        model_x="impact_parameter_in", model_y="spin_axial", xscale=1.0 / INCH, bins=bins)
    # The same model with Cross & Nathan's tangential restitution, for comparison.
    e_x = sec5.CROSS_NATHAN_E_X
    compliant = model_curves(model.attrs.get("e_star", sec5.e_star_paper()), spins,
                             mu=model.attrs.get("mu", sec5.MU), e_x=e_x)
    slopes = {}
    for w0, curve in compliant.groupby("w0", sort=False):
        style = spin_style(w0)
        ax.plot(curve["impact_parameter_in"], curve["spin_axial"], color=style["color"],
                zorder=4, **COMPLIANT_LINE)
    for label, frame in (("rigid", model), ("compliant", compliant)):
        near = frame[(frame["w0"] == spins[0]) & (frame["impact_parameter_in"].abs() < 0.6)]
        slopes[label] = float(np.polyfit(near["impact_parameter_in"], near["spin_axial"], 1)[0])
    handles.append(Line2D([], [], color="0.3", **COMPLIANT_LINE,
                          label=f"model with tangential compliance, $e_x$ = {e_x:g}"))
    data["compliant_slope_per_inch"] = slopes["compliant"]
    data["rigid_slope_per_inch"] = slopes["rigid"]
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.axvline(0.0, color="0.6", lw=0.8)
    ax.text(0.99, 0.02, "Solid lines: the paper's rigid Coulomb model ($e_x$ = 0).\n"
            f"Dash-dot: Cross & Nathan's tangential restitution $e_x$ = {e_x:g}:\n"
            f"slope {slopes['compliant']:.1f} vs {slopes['rigid']:.1f} rad/s per inch "
            f"({100 * (slopes['compliant'] / slopes['rigid'] - 1):+.0f} %); the rigid\n"
            "model under-predicts measured spins by ~10–15 %.",
            transform=ax.transAxes, ha="right", va="bottom", fontsize=7.5,
            bbox=dict(boxstyle="round", fc="lightyellow", ec="0.6", alpha=0.9))
    ax.set_xlabel(r"impact parameter $b = (R + r_b)\sin\theta$ (inches)")
    ax.set_ylabel(r"outgoing ball spin about the bat axis $\omega_z$ (rad/s)")
    ax.set_title(f"Fig. 8 of {PAPER}: outgoing spin vs impact parameter\n"
                 "ball dropped at 4 m/s on a resting bat, 14–16 cm from the barrel end",
                 fontsize=10)
    ax.grid(alpha=0.3)
    _legend_below(fig, handles, mc_handles)
    path = save_png(fig, outdir, name)
    return path, data
