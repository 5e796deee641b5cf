"""The figures of the paper's Sec. V (Cabo, Soler & Gonzalez), as PNG files.

Every function writes PNG file(s) into ``outdir`` (created if needed) and returns
``(path, data)``: ``data`` is a dict of the numpy arrays / pandas frames actually plotted,
so that tests and reports can check them against the single-impact solver.

``fig_slip_velocity``
    Figs. 2-4: ``v1``, ``v2``, ``|v_t|`` during the first slip; ``fig2_v1.png``,
    ``fig3_v2.png``, ``fig4_slip_speed.png``.
``fig_energy_after_stick``
    Fig. 5: kinetic energy after stick; ``fig5_energy_after_stick.png``.
``fig_speed_vs_angle``
    Fig. 6 (``w0 = 0``), Fig. 7 (``w0 = +79, -72``): exit speed vs scattering angle;
    ``fig6_speed_vs_angle_w0.png``, ``fig7_speed_vs_angle_spin.png``.
``fig_spin_vs_impact_parameter``
    Fig. 8: outgoing spin vs ``b`` (in); ``fig8_spin_vs_impact_parameter.png``.

``all_figures`` draws them all. Figures 6-8 layer three things per incoming spin: the
Monte Carlo rows as a faint cloud (a random subsample; from the measured-noise columns
``*_measured`` if the dataset has them), the noise-free model curve
(``mcbat.papers.cabo2012.summary.model_curves``, thin solid line with markers) and the
Monte Carlo median (thick translucent line) with its 16-84 % band in bins
(``mcbat.stats.analysis.binned``, from the noise-free columns). The legends of Figs. 6-8
sit below the axes, so they hide no data.

Plotting uses ``matplotlib.figure.Figure`` with the Agg canvas only: no pyplot, no
global state, nothing left open.

Figs. 2-5 are drawn by ``mcbat.papers.cabo2012.figures_slip``, Figs. 6-8 by
``mcbat.papers.cabo2012.figures_monte_carlo``, in the look of
``mcbat.papers.cabo2012.figure_style``; the functions are importable from here.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from mcbat.papers.cabo2012.figure_style import DPI
from mcbat.papers.cabo2012.figures_monte_carlo import (
    fig_speed_vs_angle,
    fig_spin_vs_impact_parameter,
)
from mcbat.papers.cabo2012.figures_slip import fig_energy_after_stick, fig_slip_velocity
from mcbat.papers.cabo2012.summary import model_curves

__all__ = ["fig_slip_velocity", "fig_energy_after_stick", "fig_speed_vs_angle",
           "fig_spin_vs_impact_parameter", "model_curves", "all_figures", "DPI"]


def all_figures(outdir, df: pd.DataFrame | None, e_star: float,
                model: pd.DataFrame | None = None) -> dict[str, tuple[Path, dict]]:
    """Every figure into ``outdir``; returns ``{file stem: (path, data)}``."""
    model = model_curves(e_star) if model is None else model
    out = {}
    for path, data in fig_slip_velocity(outdir):
        out[path.stem] = (path, data)
    out["fig5_energy_after_stick"] = fig_energy_after_stick(outdir, e_star)
    out["fig6_speed_vs_angle_w0"] = fig_speed_vs_angle(outdir, df, model, (0.0,),
                                                       "fig6_speed_vs_angle_w0")
    out["fig7_speed_vs_angle_spin"] = fig_speed_vs_angle(outdir, df, model, (79.0, -72.0),
                                                         "fig7_speed_vs_angle_spin")
    out["fig8_spin_vs_impact_parameter"] = fig_spin_vs_impact_parameter(outdir, df, model)
    return out
