"""The look shared by the figures of the paper's Sec. V (``mcbat.papers.cabo2012.figures``):
the paper's marker per incoming spin, the line styles, and the Agg figure written as PNG."""

from __future__ import annotations

from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

__all__ = ["COMPLIANT_LINE", "DPI", "LEGEND_FONT", "MEDIAN_LINE", "MODEL_LINE", "PAPER",
           "SPIN_STYLE", "new_figure", "save_png", "spin_style"]

DPI = 150
PAPER = "Cabo, Soler & González (2012)"

# The paper's marker language (Figs. 7, 8): open circles +79, squares 0, filled circles -72.
SPIN_STYLE = {
    79.0: dict(color="tab:blue", marker="o", mfc="white", name="+79 rad/s (topspin)",
               fill="open circles"),
    0.0: dict(color="tab:green", marker="s", mfc="tab:green", name="0 rad/s",
              fill="squares"),
    -72.0: dict(color="tab:red", marker="o", mfc="tab:red", name="−72 rad/s (backspin)",
                fill="filled circles"),
}


# Line styles shared by Figs. 6-8 (curves in the spin's colour; legend proxies in grey).
MODEL_LINE = dict(lw=1.4, ls="-")  # noise-free model curve (+ spin markers)
MEDIAN_LINE = dict(lw=5.0, ls="-", alpha=0.45, solid_capstyle="round")  # MC median
COMPLIANT_LINE = dict(lw=1.3, ls=(0, (7, 2, 1.5, 2)), alpha=0.9)  # e_x model (dash-dot)
LEGEND_FONT = 7.5


def spin_style(w0: float) -> dict:
    """The colour, marker and name of incoming spin ``w0`` (rad/s)."""
    if float(w0) in SPIN_STYLE:
        return SPIN_STYLE[float(w0)]
    return dict(color="tab:purple", marker="D", mfc="tab:purple", name=f"{w0:+g} rad/s",
                fill="diamonds")


def new_figure(size=(7.2, 5.0)) -> Figure:
    """An empty figure on the Agg canvas (no pyplot, no global state)."""
    fig = Figure(figsize=size, dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def save_png(fig: Figure, outdir, name: str) -> Path:
    """Write ``fig`` as ``outdir/name.png`` (the folder created if needed) and clear it."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    path = outdir / (name if name.endswith(".png") else f"{name}.png")
    fig.savefig(path, dpi=DPI)
    fig.clf()
    return path
