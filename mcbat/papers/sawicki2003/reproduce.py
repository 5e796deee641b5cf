"""``mcbat reproduce sawicki2003``: the optimal swing against a fastball and a curveball.

For each pitch (``game_fastball``, ``game_curveball``) and each impact model (rigid,
``e_x = 0``; compliant, the game preset's ``e_x``), ``mcbat.papers.sawicki2003.scan``
solves the undercut x attack-angle grid with Monte Carlo scatter and flies every batted
ball to the ground. The optimum is the cell of greatest mean carry. Writes, under one
results directory::

    results/sawicki2003/summary.json     per pitch and model: the optimum and its numbers
    results/sawicki2003/table.txt        the printed table
    results/sawicki2003/table.md         the same as Markdown (docs/sawicki2003.md's)
    results/sawicki2003/figures/*.png    distance vs undercut; spray chart; distance vs
                                         launch angle coloured by launch speed

Deterministic: the same files at every run (fixed seed, common random numbers).
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np

from mcbat.papers.outputs import ResultsDirectory, echo_results
from mcbat.papers.sawicki2003 import figures
from mcbat.papers.sawicki2003.carry import FLIGHT_SETTINGS, fly
from mcbat.papers.sawicki2003.scan import MODELS, PER_CELL, PITCHES, run_scan, scan_study
from mcbat.runner.plan import positive_int, set_threads

__all__ = ["cell_means", "format_markdown", "format_table", "markdown_row", "optimum",
           "optimum_cell", "reproduce", "verdict", "verdict_lines"]

_REPORTED = ("launch_speed", "launch_angle", "backspin", "sidespin")


def cell_means(scan) -> dict:
    """Per (attack angle, undercut) cell: the mean and standard error of the distance and
    the means of the launch quantities (ok rows only). Arrays over the cells, sorted by
    attack angle, then undercut."""
    keys = np.stack([scan.attack_angle, scan.undercut])
    cells, inverse = np.unique(keys, axis=1, return_inverse=True)
    inverse = inverse.ravel()
    ok = scan.ok & np.isfinite(scan.flight["hit_distance"])
    count = np.bincount(inverse, weights=ok, minlength=cells.shape[1])

    def mean(values):
        return np.bincount(inverse, weights=np.where(ok, values, 0.0),
                           minlength=cells.shape[1]) / count

    distance = scan.flight["hit_distance"]
    d_mean = mean(distance)
    d_var = mean(np.where(ok, distance, 0.0) ** 2) - d_mean ** 2
    out = {"attack_angle": cells[0], "undercut": cells[1], "count": count,
           "distance": d_mean,
           "distance_sd": np.sqrt(np.maximum(d_var, 0.0) * count / np.maximum(count - 1, 1)),
           "hang_time": mean(scan.flight["hang_time"])}
    out["distance_se"] = out["distance_sd"] / np.sqrt(count)
    for name in _REPORTED:
        out[name] = mean(scan.batted[name])
    return out


def optimum(means: dict) -> dict:
    """The cell of greatest mean distance, with its numbers (JSON-ready floats)."""
    best = int(np.nanargmax(means["distance"]))
    return {name: float(values[best]) for name, values in means.items()}


def optimum_cell(pitch: str, model: str, attack_angle: float, undercut: float,
                 per_cell: int = PER_CELL) -> dict:
    """The numbers of one cell of the scan (as ``optimum`` gives them for the best
    cell), solving only that cell's samples: the same draws, hence the same numbers, as
    in the whole scan."""
    study = scan_study(pitch, model, per_cell)
    scan = run_scan(pitch, model, fly, per_cell, study=study,
                    cell=(attack_angle, undercut))
    means = cell_means(scan)
    if means["count"].shape != (1,):
        raise ValueError("the cell's samples span more than one cell")
    return optimum(means)


def verdict(results: dict) -> dict:
    """Curveball minus fastball, at each one's optimum, per model (ft, with the standard
    error of the difference of two cell means)."""
    out = {}
    for model in MODELS:
        fb, cb = results["fastball"][model], results["curveball"][model]
        diff = cb["distance"] - fb["distance"]
        se = math.hypot(cb["distance_se"], fb["distance_se"])
        out[model] = {"curveball_minus_fastball_ft": diff, "standard_error_ft": se,
                      "curveball_farther": bool(diff > 0),
                      "significant_2sigma": bool(abs(diff) > 2 * se)}
    return out


def format_table(results: dict, comparison: dict) -> str:
    """The printed table: one line per pitch and model, then the verdict."""
    head = (f"{'pitch':<10} {'model':<10} {'undercut':>9} {'attack':>7} {'launch':>9} "
            f"{'angle':>6} {'backspin':>9} {'distance':>14}")
    units = (f"{'':<10} {'':<10} {'(in)':>9} {'(deg)':>7} {'(mph)':>9} {'(deg)':>6} "
             f"{'(rpm)':>9} {'(ft, mean±se)':>14}")
    lines = [head, units]
    for pitch in PITCHES:
        for model in MODELS:
            r = results[pitch][model]
            lines.append(
                f"{pitch:<10} {model:<10} {r['undercut']:9.2f} {r['attack_angle']:7.1f} "
                f"{r['launch_speed']:9.1f} {r['launch_angle']:6.1f} {r['backspin']:9.0f} "
                f"{r['distance']:8.1f} ± {r['distance_se']:3.1f}")
    lines.append("")
    lines += verdict_lines(comparison)
    return "\n".join(lines)


def verdict_lines(comparison: dict) -> list:
    """One line per model: how much farther or shorter the optimal curveball carries."""
    lines = []
    for model, v in comparison.items():
        sign = "farther" if v["curveball_farther"] else "shorter"
        lines.append(f"{model}: the optimally hit curveball carries "
                     f"{abs(v['curveball_minus_fastball_ft']):.1f} ± "
                     f"{v['standard_error_ft']:.1f} ft {sign} than the fastball"
                     + ("" if v["significant_2sigma"] else " (within 2 standard errors)"))
    return lines


def format_markdown(results: dict, comparison: dict) -> str:
    """The table and the verdict as Markdown (the block of ``docs/sawicki2003.md``)."""
    lines = ["| pitch | model | undercut (in) | attack (°) | launch speed (mph) | "
             "launch angle (°) | backspin (rpm) | carry (ft, mean ± se) |",
             "|---|---|---|---|---|---|---|---|"]
    lines += [markdown_row(pitch, model, results[pitch][model])
              for pitch in PITCHES for model in MODELS]
    lines.append("")
    lines += [f"- {line}" for line in verdict_lines(comparison)]
    return "\n".join(lines)


def markdown_row(pitch: str, model: str, r: dict) -> str:
    """One row of ``format_markdown``'s table: ``r`` as ``optimum`` gives it."""
    return (f"| {pitch} | {model} | {r['undercut']:.2f} | {r['attack_angle']:.0f} | "
            f"{r['launch_speed']:.1f} | {r['launch_angle']:.1f} | {r['backspin']:.0f} | "
            f"{r['distance']:.1f} ± {r['distance_se']:.1f} |")


def reproduce(out="results", *, threads=None, per_cell=PER_CELL, echo=print,
              overwrite=False) -> dict:
    """Run the scans, write the summary, the table and the figures under
    ``out/sawicki2003``; returns the paths written. ``threads``: numba threads for the
    kernels (default: all). ``overwrite``: replace files named like the outputs that
    mcbat did not write (``mcbat.papers.outputs``)."""
    t0 = time.perf_counter()
    set_threads(threads)
    per_cell = positive_int(per_cell, "per_cell")
    results = ResultsDirectory(Path(out) / "sawicki2003", "sawicki2003",
                               ("figures", "summary.json", "table.md", "table.txt"),
                               overwrite=overwrite)
    scans, optima = {}, {}
    for pitch in PITCHES:
        optima[pitch] = {}
        for model in MODELS:
            scan = run_scan(pitch, model, fly, per_cell)
            scans[pitch, model] = (scan, cell_means(scan))
            optima[pitch][model] = optimum(scans[pitch, model][1])
            echo(f"{pitch} / {model}: {scan.undercut.size:,} impacts and flights")
    comparison = verdict(optima)
    with results.writing():
        return _write(results, scans, optima, comparison, per_cell, echo, t0)


def _write(results, scans, optima, comparison, per_cell, echo, t0) -> dict:
    """The figures, summary and table of ``reproduce``."""
    root = results.root
    fig_dir = results.directory("figures")
    paths = [figures.distance_vs_undercut(fig_dir, scans, optima),
             figures.spray_chart(fig_dir, scans, optima),
             figures.distance_vs_launch_angle(fig_dir, scans)]
    summary = {"paper": "Sawicki, Hubbard & Stronge, Am. J. Phys. 71, 1152 (2003)",
               "per_cell": per_cell, "models_e_x": MODELS, "flight": FLIGHT_SETTINGS,
               "optimum": optima, "curveball_vs_fastball": comparison,
               "units": {"undercut": "in", "attack_angle": "deg", "launch_speed": "mph",
                         "launch_angle": "deg", "backspin": "rpm", "sidespin": "rpm",
                         "distance": "ft", "distance_sd": "ft", "distance_se": "ft",
                         "hang_time": "s", "count": "rows"}}
    summary_path = results.write_text("summary.json",
                                      json.dumps(summary, indent=2, allow_nan=False) + "\n")
    table = format_table(optima, comparison)
    table_path = results.write_text("table.txt", table + "\n")
    markdown_path = results.write_text("table.md",
                                       format_markdown(optima, comparison) + "\n")
    echo("")
    echo(table)
    echo("")
    echo_results(echo, root, time.perf_counter() - t0,
                 [("summary", summary_path), ("table", table_path),
                  ("markdown", markdown_path)], paths, 9)
    return {"summary": summary_path, "table": table_path, "markdown": markdown_path,
            "figures": paths}
