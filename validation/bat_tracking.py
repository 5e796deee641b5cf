"""Real pitches and measured swings against tracked balls in play, in and out of sample.

Fits what the measured swing does not fix (the contact's place along the bat and its
undercut, the measurement errors of attack angle and bat speed) to the tracked balls in
play of the ``--fit`` files, each row conditioned on its measured pitch and swing, and
judges ``studies/bat_tracking.toml`` with the fitted values on the ``--judge`` files, the
fit files beside them (docs/bat_tracking.md)::

    NUMBA_NUM_THREADS=1 .venv/bin/python -m validation bat_tracking \\
        --fit statcast_2024_skubal.csv --judge statcast_2025-05-01.csv

Files are names in ``../shared/data/statcast/`` (or paths). Steps:

1. the measurement errors: for each pair of error sds on a grid, the contact fitted with
   ``fit_population`` (``swing = true``), then the slopes of launch speed on measured bat
   speed and of launch angle on measured attack angle simulated for the fit files' rows;
   the pair whose slopes lie nearest the fit files' measured slopes (in units of their
   bootstrap errors) is kept (a file without attack angles says nothing about its error);
2. the contact fitted again at those errors (the reported values and errors);
3. per file: KS distances of launch speed and angle (``samples`` draws), each row's
   calibration (the share of rows whose measured value lies above the row's simulated
   90th percentile, below its 10th), the mean launch speed per bat-speed bin (rows >= 100
   are held to 2 mph), and the two slopes.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd

import mcbat.statcast as sc
from mcbat.runner.pitches import load_pitches
from mcbat.stats.population import fit_population
from mcbat.stats.population_table import write_pitches
from mcbat.stats.simulate import solve_game_inputs
from mcbat.study.spec import Study

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data" / "statcast"
STUDY = ROOT / "studies" / "bat_tracking.toml"
FREE = ("contact.from_barrel_end.mean", "contact.from_barrel_end.std",
        "contact.undercut.mean", "contact.undercut.std")
BINS = (0.0, 65.0, 70.0, 75.0, 80.0, 200.0)
ERROR_GRID = {"attack_angle": (0.0, 2.0, 3.0, 4.0, 5.0, 6.0),
              "bat_speed": (0.0, 1.0, 2.0, 3.0)}
IN_ALL = False
QUICK_ARGS = ["--fit", "statcast_2024_skubal.csv", "--judge", "statcast_2025-05-01.csv",
              "--samples", "20000"]


def resolve(name) -> Path:
    """A file name in the shared Statcast folder, or a path."""
    path = Path(name)
    return path if path.exists() else DATA / name


def tracked(names) -> pd.DataFrame:
    """The tracked balls in play (a batted-ball type, bat speed, launch speed and angle, the
    pitch at the plate) of the files, as one tidy table (``file``: which file)."""
    frames = []
    for name in names:
        t = sc.read(resolve(name))
        keep = (t["bb_type"].notna() & t["bat_speed"].notna() & t["launch_speed"].notna()
                & t["launch_angle"].notna() & t["pitch_speed"].notna()
                & t["vertical_approach_angle"].notna()
                & t["handedness"].isin(["R", "L"]))
        t = t[keep].copy()
        if "attack_angle" in t:
            t = t[~(t["attack_angle"].abs() > 45.0)]  # (the study's range check)
        t["file"] = Path(name).name
        frames.append(t)
    out = pd.concat(frames, ignore_index=True)
    out.attrs = frames[0].attrs
    return out


def study_definition(values=None, errors=None) -> dict:
    """``studies/bat_tracking.toml`` with fitted contact ``values`` (``{"contact.undercut.
    mean": in, ...}``) and swing errors (``{"attack_angle": deg, "bat_speed": mph}``)."""
    data = tomllib.loads(STUDY.read_text())
    for name, value in (values or {}).items():
        section, key, field = name.split(".")
        data[section][key][field] = float(value)
    for key, value in (errors or {}).items():
        unit = "deg" if key != "bat_speed" else "mph"
        data["pitches"].setdefault("swing_error", {})[key] = {"value": float(value),
                                                              "unit": unit}
    return data


def _study(data, table, workdir):
    """The study drawing its pitches and swings from ``table``'s rows (in order)."""
    data = json.loads(json.dumps(data))
    path = Path(workdir) / f"rows{len(table)}_{id(table)}.csv"
    write_pitches(table.reset_index(drop=True), path)
    data["pitches"] = {k: v for k, v in data["pitches"].items() if k != "bb_type"}
    data["pitches"]["file"] = str(path)
    return load_pitches(Study.from_dict(data, source=STUDY))


def simulate(data, table, samples, seed, workdir):
    """Draws of the study for ``table``'s rows: ``(row, launch_speed, launch_angle)``."""
    study = _study(data, table, workdir)
    inputs = study.sample_inputs(0, samples, seed)
    row = study.pitch_identifiers(0, samples, seed)["source_row"]
    out, ok = solve_game_inputs(study, inputs)
    return row[ok], out["launch_speed"][ok], out["launch_angle"][ok]


def slopes(bat, ls, attack, la):
    """Least-squares slopes of launch speed on bat speed and launch angle on attack angle
    (NaN without attack angles)."""
    s_ls = float(np.polyfit(bat, ls, 1)[0])
    ok = np.isfinite(attack)
    s_la = float(np.polyfit(attack[ok], la[ok], 1)[0]) if ok.sum() > 10 else float("nan")
    return s_ls, s_la


def data_slopes(table, boots=300, seed=0):
    """The measured slopes and their bootstrap errors."""
    bat, ls = table["bat_speed"].to_numpy(float), table["launch_speed"].to_numpy(float)
    attack = (table["attack_angle"].to_numpy(float) if "attack_angle" in table
              else np.full(len(table), np.nan))
    la = table["launch_angle"].to_numpy(float)
    rng = np.random.default_rng(seed)
    reps = [slopes(bat[i], ls[i], attack[i], la[i])
            for i in (rng.integers(0, len(table), len(table)) for _ in range(boots))]
    return slopes(bat, ls, attack, la), tuple(np.nanstd(np.array(reps), axis=0))


def fit(table, errors, seed=1):
    """The contact fitted with ``fit_population`` at the swing ``errors``."""
    study = _study_obj(study_definition(errors=errors))
    t = table.copy()
    t.attrs = table.attrs
    return fit_population(study, t, FREE, seed=seed)


def _study_obj(data):
    """The study itself (its own [pitches] file is replaced by the fit's rows)."""
    with tempfile.TemporaryDirectory() as tmp:
        return _study(data, _placeholder(), tmp)


def _placeholder():
    t = pd.DataFrame({"pitch_speed": [40.0], "vertical_approach_angle": [-6.0],
                      "horizontal_approach_angle": [0.0], "spin_rate": [2200.0],
                      "spin_axis": [180.0], "bat_speed": [70.0], "attack_angle": [10.0],
                      "attack_direction": [0.0], "handedness": ["R"]})
    return t


def choose_errors(table, samples, workdir):
    """The error pair whose simulated slopes lie nearest the measured ones."""
    (s_ls, s_la), (e_ls, e_la) = data_slopes(table)
    best = None
    has_attack = "attack_angle" in table and table["attack_angle"].notna().any()
    grid_aa = ERROR_GRID["attack_angle"] if has_attack else (0.0,)
    for ea in grid_aa:
        for eb in ERROR_GRID["bat_speed"]:
            errors = {"attack_angle": ea, "bat_speed": eb}
            result = fit(table, errors)
            values = {p["name"]: p["value"] for p in result.parameters}
            data = study_definition(values, errors)
            row, ls, la = simulate(data, table, samples, 7, workdir)
            m_ls, m_la = slopes(table["bat_speed"].to_numpy(float)[row], ls,
                                table["attack_angle"].to_numpy(float)[row]
                                if has_attack else np.full(row.size, np.nan), la)
            d = ((m_ls - s_ls) / e_ls) ** 2 + (((m_la - s_la) / e_la) ** 2
                                               if has_attack else 0.0)
            print(f"  errors aa {ea:.0f} deg, bat {eb:.0f} mph: slopes {m_ls:.3f} "
                  f"{m_la:.3f} (data {s_ls:.3f} +- {e_ls:.3f}, {s_la:.3f} +- {e_la:.3f}); "
                  f"chi2 of the contact fit {result.chi2:.1f}/{result.dof}; distance {d:.2f}",
                  flush=True)
            if best is None or d < best[0]:
                best = (d, errors)
    return best[1]


def judge(data, table, samples, seed, workdir) -> dict:
    """The acceptance numbers of the study ``data`` on ``table``'s rows."""
    from scipy import stats

    row, ls, la = simulate(data, table, samples, seed, workdir)
    out = {"rows": len(table)}
    m_ls, m_la = table["launch_speed"].to_numpy(float), table["launch_angle"].to_numpy(float)
    out["ks_launch_speed"] = float(stats.ks_2samp(ls, m_ls).statistic)
    out["ks_launch_angle"] = float(stats.ks_2samp(la, m_la).statistic)
    for name, sim, meas in (("launch_speed", ls, m_ls), ("launch_angle", la, m_la)):
        above = below = used = 0
        order = np.argsort(row, kind="stable")
        cuts = np.searchsorted(row[order], np.arange(len(table) + 1))
        for r in range(len(table)):
            draws = sim[order[cuts[r]:cuts[r + 1]]]
            if draws.size < 20:
                continue
            lo, hi = np.quantile(draws, [0.1, 0.9])
            used += 1
            above += meas[r] > hi
            below += meas[r] < lo
        out[f"{name}_above_p90"] = above / used
        out[f"{name}_below_p10"] = below / used
    bat = table["bat_speed"].to_numpy(float)
    bins = []
    for lo, hi in zip(BINS[:-1], BINS[1:]):
        rows = (bat >= lo) & (bat < hi)
        sims = (bat[row] >= lo) & (bat[row] < hi)
        bins.append({"bin": f"{lo:.0f}-{hi:.0f}" if hi < 200 else f"{lo:.0f}+",
                     "rows": int(rows.sum()),
                     "measured": float(m_ls[rows].mean()) if rows.any() else float("nan"),
                     "model": float(ls[sims].mean()) if sims.any() else float("nan")})
    out["bat_speed_bins"] = bins
    attack = (table["attack_angle"].to_numpy(float) if "attack_angle" in table
              else np.full(len(table), np.nan))
    out["attack_bins"] = []
    if np.isfinite(attack).sum() > 10:
        for lo in range(-15, 35, 5):
            rows = (attack >= lo) & (attack < lo + 5)
            sims = (attack[row] >= lo) & (attack[row] < lo + 5)
            if rows.sum() >= 10:
                out["attack_bins"].append({"bin": lo + 2.5, "rows": int(rows.sum()),
                                           "measured": float(m_la[rows].mean()),
                                           "model": float(la[sims].mean())})
    out["slopes_model"] = slopes(bat[row], ls, attack[row], la)
    out["slopes_data"] = slopes(bat, m_ls, attack, m_la)
    out["above_50_model"] = float(np.mean(la > 50.0))
    out["above_50_data"] = float(np.mean(m_la > 50.0))
    return out


def verdict(r) -> list[str]:
    """Which acceptance numbers hold."""
    ok = []
    ok.append(("KS launch speed <= 0.05", r["ks_launch_speed"] <= 0.05))
    ok.append(("KS launch angle <= 0.05", r["ks_launch_angle"] <= 0.05))
    for name in ("launch_speed", "launch_angle"):
        for tail in ("above_p90", "below_p10"):
            ok.append((f"{name} {tail} in 7-13 %", 0.07 <= r[f"{name}_{tail}"] <= 0.13))
    for b in r["bat_speed_bins"]:
        if b["rows"] >= 100:
            ok.append((f"bin {b['bin']} within 2 mph", abs(b["model"] - b["measured"]) <= 2))
    return [f"{'PASS' if good else 'FAIL'} {what}" for what, good in ok]


def report(label, r) -> list[str]:
    """Lines of one judged file."""
    lines = [f"{label}: {r['rows']} rows",
             f"  KS launch speed {r['ks_launch_speed']:.3f}, launch angle "
             f"{r['ks_launch_angle']:.3f}",
             f"  launch speed: above row's p90 {r['launch_speed_above_p90']:.1%}, below p10 "
             f"{r['launch_speed_below_p10']:.1%}",
             f"  launch angle: above row's p90 {r['launch_angle_above_p90']:.1%}, below p10 "
             f"{r['launch_angle_below_p10']:.1%}",
             f"  slopes model {r['slopes_model'][0]:.2f} mph/mph, {r['slopes_model'][1]:.2f} "
             f"deg/deg; data {r['slopes_data'][0]:.2f}, {r['slopes_data'][1]:.2f}",
             f"  launch angle > 50 deg: model {r['above_50_model']:.1%}, data "
             f"{r['above_50_data']:.1%}"]
    for b in r["bat_speed_bins"]:
        lines.append(f"  bat speed {b['bin']:>6} mph: {b['rows']:4d} rows, measured "
                     f"{b['measured']:6.1f}, model {b['model']:6.1f} mph")
    lines += ["  " + v for v in verdict(r)]
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m validation bat_tracking",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--fit", required=True, help="comma-separated files to fit")
    parser.add_argument("--judge", required=True, help="comma-separated files to judge")
    parser.add_argument("--samples", type=int, default=100000)
    parser.add_argument("--seed", type=int, default=2025)
    parser.add_argument("--figure", help="write the figure of bin means to this PNG")
    parser.add_argument("--errors", help="attack_angle,bat_speed error sds (deg,mph): skip "
                                         "the scan")
    args = parser.parse_args(argv)
    errors = None
    if args.errors:
        ea, eb = (float(x) for x in args.errors.split(","))
        errors = {"attack_angle": ea, "bat_speed": eb}
    outcome = run(args.fit.split(","), args.judge.split(","), args.samples, args.seed, errors)
    if args.figure:
        figure(outcome, args.figure)
    return 0


def _centre(label) -> float:
    """Where a bat-speed bin is drawn (mph): the open end bins 2.5 mph past their edge."""
    lo = float(label.rstrip("+").split("-")[0])
    return BINS[1] - 2.5 if lo == BINS[0] else lo + 2.5


def figure(outcome, path):
    """Mean launch speed per bat-speed bin and mean launch angle per attack-angle bin, data
    and model, in sample (left) and out of sample (right)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(10, 8), sharey="row")
    for col, label in enumerate(("in sample", "out of sample")):
        for (lab, name), r in outcome["results"].items():
            if lab != label:
                continue
            b = [x for x in r["bat_speed_bins"] if x["rows"] >= 10]
            centres = [_centre(x["bin"]) for x in b]
            line = axes[0, col].errorbar(centres, [x["measured"] for x in b], fmt="o",
                                         label=f"{name} (data)")
            axes[0, col].plot(centres, [x["model"] for x in b], "-",
                              color=line[0].get_color(), label=f"{name} (model)")
            if r["attack_bins"]:
                a = r["attack_bins"]
                line = axes[1, col].plot([x["bin"] for x in a], [x["measured"] for x in a],
                                         "o", label=f"{name} (data)")
                axes[1, col].plot([x["bin"] for x in a], [x["model"] for x in a], "-",
                                  color=line[0].get_color(), label=f"{name} (model)")
        axes[0, col].set_title(label)
        axes[0, col].set_xlabel("measured bat speed (mph; bins of 5, < 65 and 80+ at the ends)")
        axes[1, col].set_xlabel("measured attack angle (deg; bins of 5)")
        for ax in axes[:, col]:
            ax.legend(fontsize=7)
            ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel("mean launch speed (mph)")
    axes[1, 0].set_ylabel("mean launch angle (deg)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run(fit_files, judge_files, samples=100000, seed=2025, errors=None) -> dict:
    """Fit on ``fit_files``, judge on both; prints the report and returns
    ``{"errors", "values", "fit", "results": {(label, file): judge(...)}}``."""
    table = tracked(fit_files)
    with tempfile.TemporaryDirectory() as workdir:
        if errors is None:
            print(f"scanning the swing errors on {', '.join(fit_files)} ({len(table)} rows)")
            errors = choose_errors(table, min(samples, 40000), workdir)
        result = fit(table, errors)
        values = {p["name"]: p["value"] for p in result.parameters}
        print(f"fit on {', '.join(fit_files)} ({result.rows} rows): chi2 {result.chi2:.1f}/"
              f"{result.dof}; swing errors: attack angle {errors['attack_angle']:g} deg, bat "
              f"speed {errors['bat_speed']:g} mph")
        for p in result.parameters:
            print(f"  {p['name']} = {p['value']:.2f} -{p['lower_error']:.2f} "
                  f"+{p['upper_error']:.2f} {p['unit']}")
        data = study_definition(values, errors)
        results = {}
        for label, names in (("in sample", fit_files), ("out of sample", judge_files)):
            for name in names:
                results[(label, name)] = judge(data, tracked([name]), samples, seed,
                                               workdir)
    blocks = [report(f"{label}: {name}", r) for (label, name), r in results.items()]
    width = max(len(line) for block in blocks for line in block) + 2
    ins = [b for (label, _), b in zip(results, blocks) if label == "in sample"]
    outs = [b for (label, _), b in zip(results, blocks) if label != "in sample"]
    for k in range(max(len(ins), len(outs))):
        left = ins[k] if k < len(ins) else []
        right = outs[k] if k < len(outs) else []
        for i in range(max(len(left), len(right))):
            a = left[i] if i < len(left) else ""
            b = right[i] if i < len(right) else ""
            print(f"{a:<{width}}{b}")
        print()
    return {"errors": errors, "values": values, "fit": result, "results": results}


if __name__ == "__main__":
    main()
