"""The main job (`mcbat reproduce`): files produced, and each figure's data checked against
the single-impact solver at a few points."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

import mcbat
from mcbat.api import contact_problem, history, solve
from mcbat.papers.cabo2012 import figures, sec5, summary
from mcbat.papers.cabo2012.reproduce import reproduce

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
E_STAR = sec5.e_star_paper()


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("results")
    lines = []
    paths = reproduce(out, samples=9_000, progress=False, echo=lines.append)
    return out, paths, lines


def test_every_file_is_produced_and_non_empty(run):
    out, paths, lines = run
    assert len(paths["figures"]) == 7
    names = sorted(p.name for p in paths["figures"])
    assert names == sorted(["fig2_v1.png", "fig3_v2.png", "fig4_slip_speed.png",
                            "fig5_energy_after_stick.png", "fig6_speed_vs_angle_w0.png",
                            "fig7_speed_vs_angle_spin.png",
                            "fig8_spin_vs_impact_parameter.png"])
    for path in paths["figures"]:
        assert path.read_bytes()[:8] == PNG_MAGIC
        image = imread(path)
        assert image.shape[0] > 400 and image.shape[1] > 600
        assert image.std() > 0.05  # not a blank canvas
    df = mcbat.load(paths["dataset"])
    assert len(df) == 9_000 and (df["status"] == 0).all()
    assert {"exit_speed_measured", "scattering_angle_measured"} <= set(df.columns)
    calibration = json.loads(paths["calibration"].read_text())
    assert calibration["loss_fraction"] == pytest.approx(0.6183822, abs=5e-4)
    headline = json.loads(paths["summary"].read_text())
    assert json.dumps(headline)  # plain JSON
    text = "\n".join(lines)
    assert str(out) in text and "fig8_spin_vs_impact_parameter.png" in text
    # One e*, the dataset's (the paper's e^2), and one time, the whole job's.
    assert text.count("e* =") == 1 and f"e* = {E_STAR:.7f}" in text
    assert not any(line.startswith("time: ") for line in lines)
    assert sum(line.startswith(f"results in {out}/ (") for line in lines) == 1


def test_summary_numbers(run):
    out, paths, _ = run
    df = mcbat.load(paths["dataset"])
    model = summary.model_curves(E_STAR, n=41)
    headline = summary.summarize(df, model)
    text = json.dumps(headline)
    assert "NaN" not in text or "null" in text
    # The paper's calibration point: w0 = 0, alpha = 0 gives the target speed to 3 digits.
    flat = json.loads(text)
    found = [v for k, v in _walk(flat) if "alpha" in k and "model" in k]
    assert found, "the summary reports the model's exit speed at alpha = 0"
    assert any(abs(v - sec5.TARGET_SPEED) < 2e-3 for v in found if isinstance(v, float))
    print(summary.format_table(headline))


def _walk(obj, prefix=""):
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _walk(v, f"{prefix}.{k}")
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            yield from _walk(v, f"{prefix}[{i}]")
    else:
        yield prefix, obj


def test_slip_figures_match_the_solver(tmp_path):
    results = figures.fig_slip_velocity(tmp_path, n=201)
    (p2, d2), (p3, d3), (p4, d4) = results
    case = sec5.case(e=1.0)
    v0 = contact_problem(case)["v0"]
    assert d2["I"][0] == 0.0 and d2["v1"][0] == pytest.approx(v0[0], rel=1e-12)
    assert d3["v2"][0] == pytest.approx(v0[1], abs=1e-15)
    i_s = solve(case).stick_impulse
    assert d4["stick_impulse"] == pytest.approx(i_s, rel=1e-6)
    # Along the curve: the plotted slip speed is the history's, which vanishes at I_s and
    # stays zero in stick.
    at = history(case, np.array([0.5 * i_s, i_s, 1.1 * i_s]))
    assert at["slip_speed"][0] > 0.1 * v0[0]
    assert at["slip_speed"][1] < 1e-7 * v0[0] and at["slip_speed"][2] < 1e-7 * v0[0]
    j = np.searchsorted(d4["I"], 0.5 * i_s)
    assert np.interp(0.5 * i_s, d4["I"], d4["slip_speed"]) == pytest.approx(
        at["slip_speed"][0], rel=1e-3)
    assert j > 0


def test_energy_figure_matches_the_solver(tmp_path):
    path, data = figures.fig_energy_after_stick(tmp_path, E_STAR)
    for e_star, point in ((1.0, data["friction_only"]), (E_STAR, data["e_star_separation"])):
        r = solve(sec5.case(e=e_star))
        assert point["I"] == pytest.approx(r.normal_impulse, rel=1e-12)
        # The plotted curve, evaluated independently at the separation impulse, reaches
        # the solver's outgoing energy there.
        curve = history(sec5.case(e=e_star), np.array([r.normal_impulse]))
        assert curve["energy"][0] == pytest.approx(r.energy_out, rel=1e-7)
    r1 = solve(sec5.case(e=1.0))
    assert data["energy_line"] == pytest.approx(r1.energy_in + r1.friction_work, rel=1e-9)
    # The energy line is the friction-only separation energy (paper: 1.1599823...).
    assert data["energy_line"] == pytest.approx(1.1599823562526097, rel=1e-7)


@pytest.mark.parametrize("which", ["fig6", "fig7", "fig8"])
def test_monte_carlo_figures_match_the_solver(run, tmp_path, which):
    _, paths, _ = run
    df = mcbat.load(paths["dataset"])
    model = summary.model_curves(E_STAR, n=21)
    if which == "fig6":
        _, data = figures.fig_speed_vs_angle(tmp_path, df, model, w0_values=(0.0,),
                                             name="fig6")
        x, y = "scattering_angle", "exit_speed"
    elif which == "fig7":
        _, data = figures.fig_speed_vs_angle(tmp_path, df, model, w0_values=(79.0, -72.0),
                                             name="fig7")
        x, y = "scattering_angle", "exit_speed"
    else:
        _, data = figures.fig_spin_vs_impact_parameter(tmp_path, df, model)
        x, y = "impact_parameter_in", "spin_axial"
    curve = data["model"]
    assert len(curve) > 0
    for _, row in curve.sample(4, random_state=1).iterrows():
        r = solve(sec5.case_at_impact_parameter(row["impact_parameter"], row["w0"],
                                                e=E_STAR))
        expected = {"exit_speed": r.exit_speed, "scattering_angle": r.scattering_angle,
                    "spin_axial": r.ball_spin[2]}
        assert row[y] == expected[y]
        if x != "impact_parameter_in":
            assert row[x] == expected[x]
    # The plotted median of a bin is the median of the Monte Carlo rows in it.
    band = data["binned"].iloc[len(data["binned"]) // 2]
    nominal = np.array(sec5.SPINS)[np.argmin(np.abs(
        df["ball_wz_in"].to_numpy()[:, None] - np.array(sec5.SPINS)[None, :]), axis=1)]
    rows = df[(nominal == band["w0"]) & (df["status"] == 0)]
    xs = rows["impact_parameter"] / 0.0254 if x == "impact_parameter_in" else rows[x]
    inside = rows[(xs >= band["x_low"]) & (xs <= band["x_high"])]
    assert band["count"] == len(inside)
    assert band["q50"] == pytest.approx(inside[y].median(), rel=1e-12)
    assert band["q16"] <= band["q50"] <= band["q84"]
    assert not math.isnan(band["q50"])


def test_rerun_keeps_the_dataset(run):
    out, paths, _ = run
    stamps = {p.name: p.stat().st_mtime_ns for p in Path(paths["dataset"]).iterdir()}
    lines = []
    reproduce(out, samples=9_000, progress=False, echo=lines.append)
    assert {p.name: p.stat().st_mtime_ns
            for p in Path(paths["dataset"]).iterdir()} == stamps
    assert any("0 computed, 3 kept" in line or "kept from before" in line for line in lines)
