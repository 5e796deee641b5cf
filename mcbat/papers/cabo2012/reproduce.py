"""The project's main job: the paper's Sec. V, with Monte Carlo scatter, end to end.

``mcbat reproduce`` runs ``studies/cross_nathan_2006.toml`` into a Parquet dataset,
re-derives the paper's one fitted number with a root finder, draws Figs. 2-8 and writes a
summary of the headline numbers, all under one results directory::

    results/cross_nathan_2006/     the dataset (mcbat.load)
    results/calibration.json       e* (and the paper's e^2) from the target exit speed
    results/figures/fig*.png       Figs. 2-8
    results/summary.json           headline numbers per incoming spin

Everything is deterministic: rerunning keeps the dataset (the run resumes or does nothing)
and redraws the same figures.
"""

from __future__ import annotations

import json
import time
from importlib import resources
from pathlib import Path

from mcbat.dataset import load
from mcbat.papers.cabo2012 import figures, sec5, summary
from mcbat.papers.cabo2012.calibration import calibrate_restitution
from mcbat.papers.outputs import ResultsDirectory, echo_results
from mcbat.runner import run_study
from mcbat.study import load_study

__all__ = ["STUDY", "reproduce"]

#: The bundled study of the Monte Carlo dataset (``studies/cross_nathan_2006.toml``).
STUDY = "cross_nathan_2006.toml"
#: What the reproduction writes into its results directory, besides the dataset.
OUTPUT_NAMES = ("calibration.json", "figures", "summary.json")


def reproduce(out="results", *, samples=None, threads=None, progress=True, echo=print,
              overwrite=False):
    """Run the Sec. V reproduction into ``out``; returns a dict of the paths written.

    ``overwrite`` replaces a Monte Carlo dataset there that another sample count or an
    older mcbat wrote (it is otherwise kept and resumed, or refused), and files named like
    the reproduction's outputs that mcbat did not write (``mcbat.papers.outputs``)."""
    t0 = time.perf_counter()
    out = Path(out)
    results = ResultsDirectory(out, "cabo2012", OUTPUT_NAMES, overwrite=overwrite)
    with resources.as_file(resources.files("mcbat.studies").joinpath(STUDY)) as path:
        study = load_study(path)
    dataset_dir = out / study.name
    run = run_study(study, dataset_dir, samples=samples, threads=threads, progress=progress,
                    overwrite=overwrite)
    for line in run.lines():
        if not line.startswith("time: "):  # one time is reported: the whole job's, at the end
            echo(line)
    with results.writing():
        return _results(results, dataset_dir, echo, t0)


def _results(results, dataset_dir, echo, t0) -> dict:
    """The calibration, figures and summary of ``reproduce``, from its dataset."""
    out = results.root
    calibration = calibrate_restitution()
    calibration_path = results.write_text("calibration.json", json.dumps(
        {**calibration.to_dict(), "paper_loss_fraction": sec5.LOSS_FRACTION,
         "paper_e_star": sec5.e_star_paper()}, indent=2) + "\n")

    df = load(dataset_dir)
    e_star = sec5.e_star_paper()  # the study's restitution, so curves and cloud agree
    model = summary.model_curves(e_star)
    fig_dir = results.directory("figures")
    paths = []
    slip = figures.fig_slip_velocity(fig_dir)
    paths += [p for p, _ in (slip.values() if isinstance(slip, dict) else slip)]
    paths.append(figures.fig_energy_after_stick(fig_dir, e_star)[0])
    paths.append(figures.fig_speed_vs_angle(fig_dir, df, model, w0_values=(0.0,),
                                            name="fig6_speed_vs_angle_w0")[0])
    paths.append(figures.fig_speed_vs_angle(fig_dir, df, model, w0_values=(79.0, -72.0),
                                            name="fig7_speed_vs_angle_spin")[0])
    paths.append(figures.fig_spin_vs_impact_parameter(fig_dir, df, model)[0])

    headline = summary.summarize(df, model, calibration=calibration.to_dict())
    summary_path = results.write_text("summary.json", json.dumps(headline, indent=2) + "\n")
    echo("")
    echo(summary.format_table(headline))
    echo("")
    echo_results(echo, out, time.perf_counter() - t0,
                 [("dataset", f"{dataset_dir}/  (mcbat.load)"),
                  ("calibration", calibration_path), ("summary", summary_path)], paths, 13)
    return {"dataset": dataset_dir, "calibration": calibration_path, "summary": summary_path,
            "figures": [Path(p) for p in paths]}
