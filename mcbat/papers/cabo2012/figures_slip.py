"""Figs. 2-5 of the paper's Sec. V: the first slip of its nearly central impact
(``fig_slip_velocity``) and the kinetic energy after stick (``fig_energy_after_stick``),
from the single-impact solver (``mcbat.papers.cabo2012.figures`` has them all)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.lines import Line2D

from mcbat.api import history, solve
from mcbat.papers.cabo2012 import sec5
from mcbat.papers.cabo2012.figure_style import LEGEND_FONT, PAPER, new_figure, save_png

__all__ = ["fig_energy_after_stick", "fig_slip_velocity", "slip_history"]


def slip_history(n: int = 601, overshoot: float = 1.25) -> dict:
    """The first slip of the paper's case (``theta = pi/400``, ``w0 = 0``, ``mu = 0.5``).

    ``I`` runs over ``n`` points from 0 to ``overshoot * I_s`` plus ``I_s`` itself (the
    solver's stick impulse, kg m/s); arrays as ``mcbat.api.history`` (SI).
    """
    case = sec5.case(e=1.0)
    i_s = solve(case).stick_impulse
    impulses = np.union1d(np.linspace(0.0, overshoot * i_s, n), [i_s])
    h = history(case, impulses)
    h["stick_impulse_solver"] = float(i_s)
    return h


def fig_slip_velocity(outdir, n: int = 601) -> list[tuple[Path, dict]]:
    """Figs. 2-4: ``v1(I)``, ``v2(I)`` and ``|v_t|(I)`` during the first slip.

    The paper's nearly central impact: ``theta = pi/400``, ``w0 = 0``, ``mu = 0.5``
    (``mcbat.papers.cabo2012.sec5.case`` with ``e* = 1``; the slip does not depend on
    ``e*``), on a fine grid from ``I = 0`` to 1.25 ``I_s``, with the stick impulse ``I_s`` marked.

    Returns
    -------
    list of (Path, dict)
        Three entries, in order ``fig2_v1.png``, ``fig3_v2.png``, ``fig4_slip_speed.png``.
        Each ``data`` holds ``I`` (kg m/s), the plotted velocity (``v1``, ``v2`` or
        ``slip_speed``, m/s, SI even though the axes show mm/s and 1e-3 kg m/s),
        ``phase`` (0 slip, 1 stick) and ``stick_impulse`` (the solver's ``I_s``).
    """
    h = slip_history(n)
    i_s = h["stick_impulse_solver"]
    specs = [
        ("fig2_v1", "v1", "Fig. 2", r"$v_1(I)$: tangential slip along $\mathbf{t}_1$ "
         "(azimuthal)", r"$v_1$ (mm/s)"),
        ("fig3_v2", "v2", "Fig. 3", r"$v_2(I)$: tangential slip along $\mathbf{t}_2$ "
         "(bat axis)", r"$v_2$ (mm/s)"),
        ("fig4_slip_speed", "slip_speed", "Fig. 4",
         r"$|v_t|(I) = \sqrt{v_1^2 + v_2^2}$: slip speed", r"$|v_t|$ (mm/s)"),
    ]
    results = []
    for name, key, fig_no, what, ylabel in specs:
        fig = new_figure((7.0, 4.8))
        ax = fig.add_subplot()
        x = h["I"] * 1e3
        y = h[key] * 1e3
        slip = h["phase"] == 0
        ax.plot(x[slip], y[slip], color="tab:blue", lw=2.0, label=f"{key} while sliding")
        ax.plot(x[~slip], y[~slip], color="tab:orange", lw=2.0, ls="--",
                label="after stick (held at 0)")
        ax.axvline(i_s * 1e3, color="k", lw=1.0, ls=":")
        ax.plot([i_s * 1e3], [0.0], "kv", ms=9,
                label=rf"stick impulse $I_s$ = {i_s * 1e3:.5f}$\times10^{{-3}}$ kg m/s")
        ax.axvspan(i_s * 1e3, x[-1], color="tab:orange", alpha=0.08,
                   label="stick (paper: pure rotation)")
        ax.axhline(0.0, color="0.6", lw=0.8)
        ax.set_xlim(0.0, x[-1])
        ax.set_xlabel(r"normal impulse $I$ ($10^{-3}$ kg m/s)")
        ax.set_ylabel(ylabel)
        ax.set_title(f"{fig_no} of {PAPER}: {what}\n"
                     r"first slip, $\theta = \pi/400$, $w_0 = 0$, $\mu = 0.5$, "
                     "ball at 4 m/s", fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(loc="best", fontsize=8)
        path = save_png(fig, outdir, name)
        data = {"I": h["I"], key: h[key], "phase": h["phase"], "stick_impulse": i_s,
                "stick_impulse_history": h["stick_impulse"]}
        results.append((path, data))
    return results


# ---------------------------------------------------------------- Fig. 5

# Separation markers of Fig. 5: (marker, size, face, edge, edge width).
SEP_FRICTION = dict(marker="o", ms=11, mfc="white", mec="k", mew=1.6)
SEP_E_STAR = dict(marker="D", ms=8.5, mfc="tab:orange", mec="k", mew=1.1)


def _separation(ax, x, y, style: dict, label: str) -> Line2D:
    """Mark a separation point at ``(x, y)``; returns the matching legend proxy."""
    ax.plot([x], [y], ls="none", zorder=5, **style)
    return Line2D([], [], ls="none", label=label, **style)


def fig_energy_after_stick(outdir, e_star: float, n: int = 600) -> tuple[Path, dict]:
    """Fig. 5: the kinetic energy after stick, ``E_f`` against ``I' = I - I_s``.

    The paper's case (``theta = pi/400``, ``w0 = 0``, ``mu = 0.5``) integrated with friction
    as the only loss (``e* = 1``) and continued past separation. Drawn: ``E_f(I')``, the
    horizontal line ``E_in + W_fr(I_s)`` (the mechanical energy conserved while stuck; the
    gap down to ``E_f`` is the stored elastic energy), the friction-only separation
    (``I'_f^(out,1)``, back on the line) and the separation for ``e_star``
    (``solve(sec5.case(e=e_star))``), as an open circle and a filled diamond, and the end
    of compression.

    Returns
    -------
    (Path, dict)
        ``data``: ``I`` (absolute normal impulse, kg m/s), ``I_prime`` (``I - I_s``),
        ``energy`` (J), ``energy_line`` (J, scalar), ``stick_impulse``,
        ``friction_only`` and ``e_star_separation`` (dicts with ``I``, ``I_prime``,
        ``energy``), ``compression`` (``I``, ``I_prime``, ``energy`` at ``v_n = 0``),
        ``e_star``.
    """
    case1 = sec5.case(e=1.0)
    r1 = solve(case1)
    re = solve(sec5.case(e=float(e_star)))
    i_s = r1.stick_impulse
    span = r1.normal_impulse - i_s
    impulses = np.union1d(i_s + np.linspace(0.0, 1.08 * span, n),
                          [r1.compression_impulse, r1.normal_impulse, re.normal_impulse])
    h = history(case1, impulses)
    energy_line = float(h["energy_in"] + h["friction_work"][0])  # W_fr frozen while stuck
    i_prime = impulses - i_s
    sep1 = {"I": r1.normal_impulse, "I_prime": r1.normal_impulse - i_s,
            "energy": r1.energy_out}
    sep2 = {"I": re.normal_impulse, "I_prime": re.normal_impulse - i_s,
            "energy": re.energy_out}
    e_min = r1.energy_in + r1.friction_work + r1.compression_work
    comp = {"I": r1.compression_impulse, "I_prime": r1.compression_impulse - i_s,
            "energy": e_min}

    fig = new_figure((7.2, 6.1))
    ax = fig.add_subplot()
    ax.plot(i_prime, h["energy"], color="tab:blue", lw=2.0,
            label=r"kinetic energy $E_f(I')$ while stuck (friction-only dynamics)")
    ax.axhline(energy_line, color="k", lw=1.2, ls="--",
               label=rf"$E_{{in}} + W_{{fr}}(I_s)$ = {energy_line:.5f} J")
    # stored elastic energy at its maximum (end of compression)
    ax.annotate("", xy=(comp["I_prime"], e_min), xytext=(comp["I_prime"], energy_line),
                arrowprops=dict(arrowstyle="<->", color="0.35", lw=1.0))
    ax.text(comp["I_prime"] + 0.01, 0.5 * (e_min + energy_line),
            f"peak stored elastic\nenergy {-r1.compression_work:.4f} J\n"
            rf"(end of compression, $I'$ = {comp['I_prime']:.4f})",
            fontsize=8, color="0.25", va="center")
    ax.plot([comp["I_prime"]], [e_min], "s", color="0.35", ms=5)
    h0 = Line2D([], [], ls="none", marker="s", color="0.35", ms=5,
                label=rf"end of compression ($v_n$ = 0): $I'$ = {comp['I_prime']:.5f}, "
                      rf"$E$ = {e_min:.4f} J")
    h1 = _separation(ax, sep1["I_prime"], sep1["energy"], SEP_FRICTION,
                     label=rf"separation, friction only ($e^*=1$): $I'_f$ = "
                           rf"{sep1['I_prime']:.5f}, $E$ = {sep1['energy']:.4f} J")
    h2 = _separation(ax, sep2["I_prime"], sep2["energy"], SEP_E_STAR,
                     label=rf"separation, $e^*$ = {e_star:.4f}: $I'_f$ = "
                           rf"{sep2['I_prime']:.5f}, $E$ = {sep2['energy']:.4f} J")
    handles, _ = ax.get_legend_handles_labels()
    fig.legend(handles=handles + [h0, h1, h2], loc="outside lower center", ncol=1,
               fontsize=LEGEND_FONT, framealpha=0.95)
    ax.set_xlabel(r"normal impulse after stick $I' = I - I_s$ (kg m/s)"
                  rf"    [$I_s$ = {i_s:.6f} kg m/s]")
    ax.set_ylabel("kinetic energy of ball + bat (J)")
    ax.set_xlim(0.0, i_prime[-1])
    ax.set_ylim(0.0, 1.12 * energy_line)
    ax.set_title(f"Fig. 5 of {PAPER}: kinetic energy after stick (pure rotation)\n"
                 r"$\theta = \pi/400$, $w_0 = 0$, $\mu = 0.5$, ball at 4 m/s", fontsize=10)
    ax.grid(alpha=0.3)
    path = save_png(fig, outdir, "fig5_energy_after_stick")
    data = {"I": impulses, "I_prime": i_prime, "energy": h["energy"],
            "energy_line": energy_line, "stick_impulse": i_s, "friction_only": sep1,
            "e_star_separation": sep2, "compression": comp, "e_star": float(e_star)}
    return path, data
