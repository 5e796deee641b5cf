"""The generated numbers of ``docs/batting.md``: write them, or check them.

    NUMBA_NUM_THREADS=1 .venv/bin/python -m validation batting_doc           # check
    NUMBA_NUM_THREADS=1 .venv/bin/python -m validation batting_doc --write   # update
    NUMBA_NUM_THREADS=1 .venv/bin/python -m validation batting_doc --only location_q

The blocks (between ``<!-- begin generated: NAME -->`` and ``<!-- end generated: NAME -->``):

``location_q``
    ``q`` of a square, head-on hit on the R161 (86 mph pitch, 71.5 mph swing, level, no
    pitch spin, the game preset's restitution) against the distance of the contact from
    the barrel end, with each location table and without one (``mcbat.api.solve_game``).
``plate_pitches``
    The right-handed pitchers' four-seamers and curveballs of
    ``data/statcast_2020-09-03.csv`` at the plate (``mcbat.statcast.read``).
``run_game_fastball``
    What ``mcbat run studies/game_fastball.toml`` prints about the batted balls (the
    command itself is run, with the study's samples and seed); the numbers the text after
    it quotes come from the same dataset.
``run_real_pitches``
    What ``mcbat run studies/real_pitches.toml`` prints about the rows it drew from; its
    launch speeds and the selected rows of the file are numbers of the text.
``spin_vs_nathan``, ``presets_vs_real`` (rendered together, as ``presets_vs_real``)
    The presets' batted balls at their studies' samples and seeds, the median backspin
    per 5° against Nathan's average spin model (also with ``e_x = 0.2``), and the launch
    speeds and angles against the real balls in play of ``data/`` (the calculations of
    ``python -m validation presets_vs_statcast``).
``population_fit``
    ``mcbat fit --population`` of ``studies/mlb_population.toml`` to the 424 balls in play
    (the command and its output; ~30 s).

Numbers inside the text (:data:`INLINE`: each found by the words around it) are written
too, by the same names: the game preset's ``e*`` at 165.5 mph and the rigid model's ``q``
and ``r`` at the R161's sweet spot (``game_preset``); the exports' drag loss, slow
curveballs, left-handers and Darvish's four-seamers (``plate_pitches``); the day's balls
in play by kind and its fouls (``in_play``); the runs' (``run_game_fastball``,
``run_real_pitches``); the presets' sidespin, curveball backspin, distance from Nathan's
model and launch-speed sd (``presets_vs_real``); the fit's chi2, p-value and rounded
values (``population_fit``); the fit with the attack angle's mean free and the backspin
of its swing (``attack_free``). ``--only`` takes any of :data:`NAMES`.

Without ``--write`` the script exits 1 and prints the difference when a block of the doc
or a number of the text is not what the code gives now. ~1-2 min on one thread, most of it
the studies' ten runs and the two fits.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import numpy as np

from mcbat.papers.sawicki2003.doc import splice, stale_blocks

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "batting.md"

IN = 0.0254
MPH = 0.44704

#: Where along the bat the ``location_q`` table is evaluated (in from the barrel end).
LOCATION_Q_AT_IN = (1, 2, 3, 4.5, 6, 6.5, 8, 10, 12, 14, 16, 18)


def head_on_q(from_barrel_end_in, location):
    """``q`` of a square, head-on hit (no undercut, level swing, no pitch spin) of an
    86 mph pitch on a 71.5 mph swing of the R161 at each distance from the barrel end (in),
    with the game preset's restitution and the location table ``location`` (None: none)."""
    from mcbat.api import GameCase, solve_game
    from mcbat.bodies import ball_preset, bat_preset
    from mcbat.bodies.restitution import GAME_RESTITUTION, Restitution

    g = GAME_RESTITUTION
    rest = Restitution(e_ref=g.e_ref, e_slope=g.e_slope, e_speed_ref=g.e_speed_ref,
                       e_x=g.e_x, location=location)
    ball, bat = ball_preset("baseball"), bat_preset("r161")
    return np.array([solve_game(GameCase(ball=ball, bat=bat, pitch_speed=86 * MPH,
                                         bat_speed=71.5 * MPH, mu=0.5,
                                         from_barrel_end=z * IN, restitution=rest)
                                ).collision_efficiency for z in from_barrel_end_in])


def render_location_q() -> str:
    """The ``q`` table, each row's largest value in bold."""
    at = LOCATION_Q_AT_IN
    lines = ["| from the barrel end (in) | " + " | ".join(f"{z:g}" for z in at) + " |",
             "|---" * (len(at) + 1) + "|"]
    for label, location in (('`q`, `"assumed"`', "assumed"), ("`q`, no table", None),
                            ('`q`, `"illustrative"`', "illustrative")):
        q = np.round(head_on_q(at, location), 3)
        peak = int(np.argmax(q))
        cells = [f"**{v:.3f}**" if i == peak else f"{v:.3f}" for i, v in enumerate(q)]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _sd_from_quartiles(values):
    q1, q3 = np.percentile(values, [25, 75])
    return (q3 - q1) / 1.3490  # the interquartile range of a normal, in its sd


def render_plate_pitches() -> str:
    """Right-handed pitchers' four-seamers and curveballs at the plate: median (sd)."""
    from mcbat.statcast import read

    t = read(ROOT / "data" / "statcast_2020-09-03.csv")
    t = t[t["p_throws"] == "R"]
    lines = ["| pitch | pitches | release speed (median) | plate speed, median (sd; sd from "
             "the quartiles) | vertical approach | horizontal approach |",
             "|---|---|---|---|---|---|"]
    for label, kind in (("four-seamer (FF)", "FF"), ("curveball (CU)", "CU")):
        rows = t[t["pitch_type"] == kind]
        speed = rows["pitch_speed"].dropna().to_numpy(float)
        vaa = rows["vertical_approach_angle"].dropna().to_numpy(float)
        haa = rows["horizontal_approach_angle"].dropna().to_numpy(float)
        release = rows["release_speed"].dropna().to_numpy(float)
        lines.append(
            f"| {label} | {len(rows)} | {np.median(release):.1f} mph | "
            f"{np.median(speed):.1f} ({np.std(speed, ddof=1):.1f}; "
            f"{_sd_from_quartiles(speed):.1f}) mph | "
            f"{_signed(np.median(vaa))} ({np.std(vaa, ddof=1):.1f})° | "
            f"{_signed(np.median(haa), plus=True)} ({np.std(haa, ddof=1):.1f})° |")
    return "\n".join(lines)


def _signed(value, plus=False, digits=1):
    text = f"{value:.{digits}f}"
    if text.startswith("-"):
        return "−" + text[1:]
    return ("+" if plus else "") + text


def run_game_fastball() -> tuple[str, dict]:
    """``mcbat run studies/game_fastball.toml``'s batted-ball summary (run here) and the
    numbers the text after it quotes from the same dataset."""
    import mcbat
    from mcbat.statcast.spin import nathan_average_spin

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "g"
        done = subprocess.run(
            [sys.executable, "-m", "mcbat", "run", "studies/game_fastball.toml", "--out",
             str(out)], cwd=ROOT, capture_output=True, text=True, check=True)
        df = mcbat.load(out, columns=["status", "launch_speed", "launch_angle", "backspin",
                                      "bat_speed", "from_barrel_end"])
    lines = done.stdout.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("batted ball"))
    summary = [lines[start]] + [line for line in lines[start + 1:] if line.startswith("  ")]
    block = "\n".join(["```", "$ mcbat run studies/game_fastball.toml", *summary, "```"])

    df = df[df["status"] == 0]
    ls, la = df["launch_speed"].to_numpy(), df["launch_angle"].to_numpy()
    q_sweet = next(line for line in summary if "collision_efficiency" in line)
    study = tomllib.loads((ROOT / "studies" / "game_fastball.toml").read_text())
    pitch, bat = study["pitch"]["speed"], study["swing"]["bat_speed"]
    assert pitch["unit"] == bat["unit"] == "mph"
    pitch, bat = pitch["mean"], bat["mean"]
    square = 0.21 * pitch + 1.21 * bat  # q = 0.21, the preset's calibration
    top = ls >= np.quantile(ls, 0.995)
    z = df["from_barrel_end"].to_numpy() / IN
    la5, la95 = np.percentile(la, [5, 95])
    model = nathan_average_spin([la5, la95], [0.0, 0.0], ["R", "R"])[0]
    back5, back95 = np.percentile(df["backspin"].to_numpy(), [5, 95])
    values = {
        "q_sweet_run": q_sweet.split(": ")[1].split(" ")[0],
        "square_hit": f"{square:.1f}",
        "square_hit_point": f"{np.mean(ls < square) * 100:.0f}",
        "top_bat_speed": f"{np.median(df['bat_speed'].to_numpy()[top]):.1f}",
        "launch_speed_99": f"{np.quantile(ls, 0.99):.0f}",
        "launch_speed_999": f"{np.quantile(ls, 0.999):.0f}",
        "launch_speed_median": f"{np.median(ls):.1f}",
        "below_80": f"{np.mean(ls < 80) * 100:.1f}",
        "beyond_9_in": f"{np.mean(z > 9) * 100:.0f}",
        "within_3_in": f"{np.mean(z < 3) * 100:.0f}",
        "la_5": _signed(la5, digits=0), "la_95": f"{la95:.0f}",
        "model_back_5": _signed(round(model[0], -1), digits=0),
        "model_back_95": _signed(round(model[1], -1), digits=0, plus=True),
        "back_5": _signed(round(back5, -1), digits=0),
        "back_95": _signed(round(back95, -1), digits=0, plus=True),
    }
    return block, values


def _preset_balls(name, e_x=None, means=None):
    """The preset's batted balls (status 0) at its own samples and seed; ``e_x`` replaces
    its ``[restitution] e_x`` (the "at e_x = 0.2" columns), ``means`` its distributions'
    parameters (``{"swing.attack_angle.mean": 15.6}``, in the file's units)."""
    import mcbat
    from mcbat.study.spec import Study

    path = ROOT / "studies" / f"{name}.toml"
    text = path.read_text()
    data = tomllib.loads(text)
    if e_x is not None:
        data["restitution"]["e_x"] = e_x
    for key, value in (means or {}).items():
        section, field, parameter = key.split(".")
        data[section][field][parameter] = value
    study = Study.from_dict(data, source=str(path), text=text)
    with tempfile.TemporaryDirectory() as tmp:
        mcbat.run(study, Path(tmp) / "d", progress=False)
        df = mcbat.load(Path(tmp) / "d", columns=["launch_speed", "launch_angle",
                                                  "spray_angle", "backspin", "sidespin",
                                                  "handedness", "status"])
    return df[df["status"] == 0]


def _real(path, types=None):
    """Launch speeds and angles of the balls in play of a Statcast file (with both)."""
    from mcbat.statcast import balls_in_play, read

    t = read(path)
    t = t[balls_in_play(t)]
    if types is not None:
        t = t[t["pitch_type"].isin(types)]
    t = t[t["launch_speed"].notna() & t["launch_angle"].notna()]
    return t["launch_speed"].to_numpy(float), t["launch_angle"].to_numpy(float)


def _backspin_summary(spin, spin_02) -> dict:
    """How far the presets' backspin is from Nathan's model per bin, at ``e_x = 0.2`` (the
    real pitches) and at the presets' own ``e_x``."""
    under = [1.0 - o / n for _, _, o, n in spin_02["mlb_balls_in_play"]]
    _, _, ours, nathan = spin_02["mlb_balls_in_play"][0]

    def worst(name):
        return max(abs(o / n - 1.0) for _, _, o, n in spin[name][0])

    return {"ex02_under_min": f"{min(under) * 100:.0f}",
            "ex02_under_max": f"{max(under) * 100:.0f}",
            "ex02_gap_low": f"{nathan - ours:.0f}",
            "within_mlb": f"{worst('mlb_balls_in_play') * 100:.0f}",
            "within_fast": f"{worst('game_fastball') * 100:.0f}",
            "within_fast_run": f"{worst('game_fastball') * 100:.0f}"}


def presets_vs_real() -> tuple[dict, dict]:
    """The presets' batted balls against the real ones (``presets_vs_statcast``, each at
    its study's samples and seed): the spin table against Nathan's model, the KS table,
    and the numbers the text quotes from them."""
    from mcbat.stats.compare.comparison import ks_test
    from validation.presets_vs_statcast import spin_rows

    in_play = ROOT / "data" / "statcast_2020-09-03_in_play.csv"
    darvish = ROOT / "data" / "statcast_2019_darvish.csv"
    balls = {name: _preset_balls(name) for name in
             ("mlb_balls_in_play", "game_fastball", "game_curveball")}
    spin = {name: spin_rows(df) for name, df in balls.items()}
    spin_02 = {name: spin_rows(_preset_balls(name, e_x=0.2))[0]
               for name in ("mlb_balls_in_play", "game_fastball")}

    lines = ["| launch angle | `mlb_balls_in_play`: ours / Nathan | ratio | at `e_x = 0.2` | "
             "`game_fastball`: ours / Nathan | ratio | at `e_x = 0.2` |",
             "|---|---|---|---|---|---|---|"]
    for i in range(5):
        cells = []
        for name in ("mlb_balls_in_play", "game_fastball"):
            lo, _, ours, nathan = spin[name][0][i]
            _, _, ours_02, nathan_02 = spin_02[name][i]
            cells += [f"{ours:.0f} / {nathan:.0f}", f"{ours / nathan:.2f}",
                      f"{ours_02 / nathan_02:.2f}"]
        lines.append(f"| {lo}-{lo + 5}° | " + " | ".join(cells) + " |")
    spin_table = "\n".join(lines)

    def pct(x):
        return f"{x * 100:.1f} %"

    def row(study, label, real, p_values=False, median=True):
        ls, la = (balls[study][c].to_numpy() for c in ("launch_speed", "launch_angle"))
        rs, ra = real
        ks = [f"{k['statistic']:.3f}" + (f" (p = {k['p_value']:.2f})" if p_values else "")
              for k in (ks_test(ls, rs), ks_test(la, ra))]
        med = f" {np.median(ls):.1f} ({np.median(rs):.1f}) mph " if median else " "
        return (f"| {label[0]} | {label[1]} | {ks[0]} | {ks[1]} | {pct(np.mean(ls < 80))} "
                f"({pct(np.mean(rs < 80))}) | {pct(np.mean(la > 50))} "
                f"({pct(np.mean(ra > 50))}) |{med}|")

    every = _real(in_play)
    fast, curve, dar = _real(in_play, ("FF", "SI")), _real(in_play, ("CU", "KC")), _real(darvish)
    n = len(every[0])
    rows = [row("mlb_balls_in_play", (f"`mlb_balls_in_play` (the {n} pitches)", f"all {n}"),
                every, p_values=True),
            row("game_fastball", ("`game_fastball`", f"all {n}"), every),
            row("game_fastball", ("`game_fastball`",
                                  f"the {len(fast[0])} four-seamers and sinkers"), fast),
            row("game_curveball", ("`game_curveball`", f"all {n}"), every),
            row("game_curveball", ("`game_curveball`",
                                   f"the {len(curve[0])} curveballs and knuckle curves"), curve),
            row("mlb_balls_in_play", ("`mlb_balls_in_play`", f"Darvish's {len(dar[0])} balls "
                                      "in play, 2019 (not fitted)"), dar, p_values=True,
                median=False)]
    ks_table = "\n".join(["| study | real balls | KS `launch_speed` | KS `launch_angle` | "
                          "< 80 mph (real) | > 50° (real) | median launch speed (real) |",
                          "|---|---|---|---|---|---|---|", *rows])

    fast_side, mlb_side = spin["game_fastball"][1], spin["mlb_balls_in_play"][1]
    curve_rows = spin["game_curveball"][0]
    ls_mlb = balls["mlb_balls_in_play"]["launch_speed"].to_numpy()
    values = {
        # sidespins to 10 rpm
        "side_fast_median": _signed(round(fast_side[0], -1), digits=0),
        "side_fast_nathan": _signed(round(fast_side[1], -1), digits=0),
        "side_fast_10": _signed(round(fast_side[2], -1), digits=0),
        "side_fast_90": _signed(round(fast_side[3], -1), digits=0, plus=True),
        "side_fast_sd": f"{round(fast_side[4], -1):.0f}",
        "side_mlb_median": _signed(round(mlb_side[0], -1), digits=0),
        "side_mlb_nathan": _signed(round(mlb_side[1], -1), digits=0),
        "side_mlb_10": _signed(round(mlb_side[2], -1), digits=0),
        "side_mlb_90": _signed(round(mlb_side[3], -1), digits=0, plus=True),
        "side_mlb_sd": f"{round(mlb_side[4], -1):.0f}",
        **{f"curve_ratio_{i}": f"{o / m:.2f}" for i, (_, _, o, m) in enumerate(curve_rows)},
        "curve_low_ours": f"{curve_rows[0][2]:.0f}",
        "curve_low_nathan": f"{curve_rows[0][3]:.0f}",
        "curve_low_gap": f"{round(curve_rows[0][3] - curve_rows[0][2], -1):.0f}",
        **_backspin_summary(spin, spin_02),
        "sd_launch_speed": f"{np.std(ls_mlb):.1f}",
        "sd_launch_speed_real": f"{np.std(every[0]):.1f}",
    }
    return {"spin_vs_nathan": spin_table, "presets_vs_real": ks_table}, values


def plate_values() -> dict:
    """The numbers the text around ``plate_pitches`` quotes from the same exports."""
    from mcbat.statcast import read

    t = read(ROOT / "data" / "statcast_2020-09-03.csv")

    def of(hand, kind, column):
        rows = t[(t["p_throws"] == hand) & (t["pitch_type"] == kind)]
        return rows[column].dropna().to_numpy(float)

    loss = 1.0 - np.median(of("R", "FF", "pitch_speed")) / np.median(of("R", "FF",
                                                                         "release_speed"))
    darvish = read(ROOT / "data" / "statcast_2019_darvish.csv")
    darvish = darvish[darvish["pitch_type"] == "FF"]
    return {"drag_loss": f"{loss * 100:.1f}",
            "cu_p5": f"{np.percentile(of('R', 'CU', 'pitch_speed'), 5):.0f}",
            "lhp_ff_haa": _signed(np.median(of("L", "FF", "horizontal_approach_angle"))),
            "lhp_cu_haa": _signed(np.median(of("L", "CU", "horizontal_approach_angle"))),
            "darvish_speed": f"{np.median(darvish['pitch_speed'].dropna()):.1f}",
            "darvish_vaa": _signed(np.median(darvish["vertical_approach_angle"].dropna()))}


def run_real_pitches() -> tuple[str, dict]:
    """``mcbat run studies/real_pitches.toml``: the line on what it drew from (run here),
    its launch speeds, and the selected rows of the file (read here with the study's
    filters)."""
    from mcbat.statcast import read

    with tempfile.TemporaryDirectory() as tmp:
        done = subprocess.run(
            [sys.executable, "-m", "mcbat", "run", "studies/real_pitches.toml", "--out",
             str(Path(tmp) / "r")], cwd=ROOT, capture_output=True, text=True, check=True)
    lines = done.stdout.splitlines()
    drawn = next(line for line in lines if line.startswith("pitches: "))
    speed = next(line for line in lines if line.startswith("  launch_speed: "))
    median, low, high = re.fullmatch(r"  launch_speed: (\S+) mph \((\S+) to (\S+)\)",
                                     speed).groups()
    study = tomllib.loads((ROOT / "studies" / "real_pitches.toml").read_text())["pitches"]
    t = read(ROOT / "data" / "statcast_2020-09-03.csv")
    t = t[t["pitch_type"].isin(study["pitch_type"]) & (t["p_throws"] == study["p_throws"])]
    speeds = t["pitch_speed"].to_numpy(float)
    values = {"rp_rows": f"{len(t)}", "rp_min": f"{speeds.min():.1f}",
              "rp_max": f"{speeds.max():.1f}", "rp_mean": f"{speeds.mean():.1f}",
              "rp_release": f"{t['release_speed'].mean():.1f}",
              "rp_vaa": _signed(np.median(t["vertical_approach_angle"])),
              "rp_right": f"{int((t['handedness'] == 'R').sum())}",
              "rp_left": f"{int((t['handedness'] == 'L').sum())}",
              "rp_ls_median": median, "rp_ls_5": low, "rp_ls_95": high}
    return "\n".join(["```", drawn, "```"]), values


#: The population fit of the presets' swing and contact (the parameters it frees).
FIT_FREE = ("swing.bat_speed.mean", "swing.bat_speed.std", "swing.attack_angle.std",
            "contact.undercut.mean", "contact.undercut.std", "contact.from_barrel_end.std")


def population_fit() -> tuple[str, dict]:
    """``mcbat fit --population`` of ``studies/mlb_population.toml`` to the day's balls in
    play, run here: the command and its output (the list of freed parameters in its first
    line written ``...``), and its chi2 and p-value."""
    from scipy import stats

    data = "data/statcast_2020-09-03_in_play.csv"
    free = ",".join(FIT_FREE)
    done = subprocess.run(
        [sys.executable, "-m", "mcbat", "fit", "--population", "--study",
         "studies/mlb_population.toml", "--data", data, "--free", free],
        cwd=ROOT, capture_output=True, text=True, check=True,
        env={**os.environ, "NUMBA_NUM_THREADS": "1"})
    out = done.stdout.rstrip("\n").replace(f"population fit of {free} to",
                                            "population fit of ... to", 1)
    chi2, dof = re.search(r"chi2 / dof = (\S+) / (\d+)", out).groups()
    p = f"{stats.chi2.sf(float(chi2), int(dof)):.0e}".replace("e-0", "e-")
    command = ["```sh", "NUMBA_NUM_THREADS=1 mcbat fit --population --study "
               "studies/mlb_population.toml \\", f"    --data {data} \\", f"    --free {free}",
               "```"]
    fitted = {m[1]: (float(m[2]), max(-float(m[3]), float(m[4]))) for m in re.finditer(
        r"  (\S+) = (\S+) (\S+) \+(\S+) ", out)}
    bat, bat_error = fitted["swing.bat_speed.mean"]
    rounded = {"fit_bat_mean": f"{bat:.1f}", "fit_bat_mean_2": f"{bat:.1f}",
               "fit_bat_error": f"{bat_error:.1f}",
               "fit_bat_std": f"{fitted['swing.bat_speed.std'][0]:.1f}",
               "fit_attack_std": f"{fitted['swing.attack_angle.std'][0]:.1f}",
               "fit_undercut_mean": f"{fitted['contact.undercut.mean'][0]:.2f}",
               "fit_undercut_std": f"{fitted['contact.undercut.std'][0]:.2f}",
               "fit_contact_std": f"{fitted['contact.from_barrel_end.std'][0]:.1f}",
               "fit_contact_std_2": f"{fitted['contact.from_barrel_end.std'][0]:.1f}"}
    return ("\n".join([*command, "", "```", out, "```"]),
            {"fit_chi2": chi2, "fit_chi2_int": f"{float(chi2):.0f}", "fit_p": p, **rounded})


def attack_free_fit() -> dict:
    """The population fit with the attack angle's mean free and the undercut's held at 0,
    and the backspin of its swing and contact (``mlb_balls_in_play`` with the fitted values,
    ``e_x = 0.2``) against Nathan's model per 5° bin."""
    from validation.presets_vs_statcast import spin_rows

    free = [name for name in FIT_FREE if name != "contact.undercut.mean"]
    free.insert(2, "swing.attack_angle.mean")
    done = subprocess.run(
        [sys.executable, "-m", "mcbat", "fit", "--population", "--study",
         "studies/mlb_population.toml", "--data", "data/statcast_2020-09-03_in_play.csv",
         "--free", ",".join(free)], cwd=ROOT, capture_output=True, text=True, check=True,
        env={**os.environ, "NUMBA_NUM_THREADS": "1"})
    fitted = {m[1]: (float(m[2]), max(-float(m[3]), float(m[4]))) for m in re.finditer(
        r"  (\S+) = (\S+) (\S+) \+(\S+) ", done.stdout)}
    chi2 = re.search(r"chi2 / dof = (\S+) /", done.stdout)[1]
    means = {name: value for name, (value, _) in fitted.items()}
    means["contact.undercut.mean"] = 0.0
    rows = spin_rows(_preset_balls("mlb_balls_in_play", e_x=0.2, means=means))[0]
    ratios = [o / n for _, _, o, n in rows]
    attack, error = fitted["swing.attack_angle.mean"]
    return {"free_attack": f"{attack:.1f}", "free_attack_error": f"{error:.1f}",
            "free_attack_2": f"{attack:.1f}", "free_attack_error_2": f"{error:.1f}",
            "free_chi2": f"{float(chi2):.0f}", "free_chi2_2": f"{float(chi2):.0f}",
            **{f"free_ratio_{i}": f"{r:.2f}" for i, r in enumerate(ratios)},
            "free_under_min": f"{(1 - max(ratios)) * 100:.0f}",
            "free_under_max": f"{(1 - min(ratios)) * 100:.0f}"}


def in_play_values() -> dict:
    """The counts the text gives of the day's export and its balls in play."""
    from mcbat.statcast import balls_in_play, read

    in_play = read(ROOT / "data" / "statcast_2020-09-03_in_play.csv")
    kinds = in_play["bb_type"].value_counts()
    day = read(ROOT / "data" / "statcast_2020-09-03.csv")
    speed = day["launch_speed"].notna().to_numpy()
    return {"ground_balls": f"{kinds['ground_ball']}", "line_drives": f"{kinds['line_drive']}",
            "fly_balls": f"{kinds['fly_ball']}", "popups": f"{kinds['popup']}",
            "fouls_with_speed": f"{int((speed & ~balls_in_play(day)).sum())}",
            "rows_with_speed": f"{int(speed.sum())}"}


def game_preset_values() -> dict:
    """The game preset's restitution at 165.5 mph and the rigid model's ``q`` and ``r`` at
    the R161's sweet spot (6 in from the barrel end)."""
    from mcbat.bodies import ball_preset, bat_preset
    from mcbat.bodies.restitution import GAME_RESTITUTION as g

    ball, bat = ball_preset("baseball"), bat_preset("r161")
    e = g.e_ref - g.e_slope * (165.5 * MPH - g.e_speed_ref)
    d = bat.cm_from_barrel_end - 6 * IN
    r = ball.mass * (1.0 / bat.mass + d * d / bat.transverse_inertia)
    return {"e_star_165": f"{e:.4f}", "q_sweet_rigid": f"{(e - r) / (1 + r):.2f}",
            "r_sweet": f"{r:.4f}", "cm_from_barrel_end": f"{bat.cm_from_barrel_end / IN:.1f}"}


#: Numbers inside the text: ``name -> the words around it``, ``{}`` where the number
#: stands (any run of white space in the doc matches one space here).
INLINE = {
    "e_star_165": "on a 71.5 mph swing) `e* = {}`, where",
    "q_sweet_rigid": "the rigid model gives `q = {}` at the R161's sweet spot",
    "r_sweet": "sweet spot (`r = {}`): between",
    "q_sweet_run": "`q` at the sweet spot {} against 0.20-0.22",
    "square_hit": "1.21·69.5 = {} mph, sits",
    "square_hit_point": "sits at the {} % point of the cloud",
    "top_bat_speed": "have a median bat speed of {} mph",
    "launch_speed_99": "reaches {} mph at the 99 % point",
    "launch_speed_999": "and {} mph at 99.9 %",
    "launch_speed_median": "The median launch speed, {} mph, is",
    "below_80": "; {} % of the balls leave below 80 mph",
    "beyond_9_in": "off the barrel ({} % beyond 9 in,",
    "within_3_in": "beyond 9 in, {} % within 3 in of the end",
    "la_5": "at the 5/95 % launch angles, {}°",
    "la_95": "launch angles, −31° and {}°, the model",
    "model_back_5": "the model gives {} and",
    "model_back_95": "the model gives −4500 and {} rpm",
    "back_5": "5/95 % backspin of {} and",
    "back_95": "5/95 % backspin of −5500 and {} rpm",
    "drag_loss": "The ball loses ~{} % of its speed",
    "cu_p5": "(5 % below {} mph)",
    "lhp_ff_haa": "horizontal angle (FF {}°, CU",
    "lhp_cu_haa": "(FF −1.3°, CU {}°)",
    "darvish_speed": "`data/statcast_2019_darvish.csv`) agree: {} mph,",
    "darvish_vaa": "agree: 87.9 mph, {}°.",
    "rp_rows": "`mcbat run studies/real_pitches.toml`: the {} four-seamers",
    "rp_min": "plate speeds {}-91.8 mph",
    "rp_max": "plate speeds 78.1-{} mph",
    "rp_mean": "(mean {} mph, against a mean release speed",
    "rp_release": "a mean release speed of {} mph)",
    "rp_vaa": "vertical approach angle median {}°, 466",
    "rp_right": "median -5.4°, {} against right-handed",
    "rp_left": "and {} against left-handed batters",
    "rp_ls_median": "launch speed median {} mph (89.2 to",
    "rp_ls_5": "launch speed median 100.6 mph ({} to 110.0, 5-95 %)",
    "rp_ls_95": "launch speed median 100.6 mph (89.2 to {}, 5-95 %)",
    "ex02_under_min": "the backspin of the real pitches {}-24 % under the model",
    "ex02_under_max": "the backspin of the real pitches 12-{} % under the model",
    "ex02_gap_low": "under the model ({} rpm at 15-20°, outside the 300 rpm band)",
    "within_mlb": "brings every bin within {} % (real pitches",
    "within_fast": "averages over) or {} % (the four-seamer preset)",
    "within_fast_run": "Nathan's average spin model within {} % per 5° bin",
    "free_attack": "the population fit puts it at {} ± 1.0° (undercut mean held",
    "free_attack_error": "the population fit puts it at 15.2 ± {}° (undercut mean held",
    "free_chi2": "angles (chi2 {}/42 against 84/42)",
    "fit_chi2_int": "angles (chi2 71/42 against {}/42)",
    **{f"free_ratio_{i}": "backspin is " + ", ".join("{}" if j == i else "0.00" for j in range(5))
       + " of Nathan's per bin" for i in range(5)},
    "free_attack_2": "the fit prefers {} ± 1.0° at a slightly lower chi2",
    "free_attack_error_2": "the fit prefers 15.2 ± {}° at a slightly lower chi2",
    "free_chi2_2": "at a slightly lower chi2, {}/42, but",
    "free_under_min": "its backspin falls {}-65 % under Nathan's",
    "free_under_max": "its backspin falls 20-{} % under Nathan's",
    "fit_bat_mean": "fitted values rounded ({} ± 6.3 mph",
    "fit_bat_std": "rounded (69.5 ± {} mph, 10",
    "fit_attack_std": "mph, 10 ± {}°, undercut",
    "fit_undercut_mean": "undercut {} ± 0.94 in, contact",
    "fit_undercut_std": "undercut 0.24 ± {} in, contact",
    "fit_contact_std": "contact 6 ± {} in) and keep",
    "fit_bat_mean_2": "the bat speed of {} ± 0.8 mph is",
    "fit_bat_error": "the bat speed of 69.5 ± {} mph is",
    "fit_contact_std_2": "along the bat (sd {} in about the sweet spot)",
    "ground_balls": "(put in play; {} ground balls,",
    "line_drives": "ground balls, {} line drives,",
    "fly_balls": "line drives, {} fly balls,",
    "popups": "fly balls, {} pop-ups;",
    "fouls_with_speed": "exports ({} of the day's 785 rows with one)",
    "rows_with_speed": "exports (361 of the day's {} rows with one)",
    "fit_chi2": "(chi2 {} / 42, p = 1e-4)",
    "fit_p": "(chi2 84.0 / 42, p = {})",
    "side_fast_median": "median {} rpm against Nathan's",
    "side_fast_nathan": "rpm against Nathan's {} on the same balls",
    "side_fast_10": "ball by ball, is 10-90 % {} to",
    "side_fast_90": "is 10-90 % −860 to {} rpm (sd",
    "side_fast_sd": "ball by ball, is 10-90 % −860 to +1250 rpm (sd {})",
    "side_mlb_median": "the median is {} against",
    "side_mlb_nathan": "the median is −270 against {} and the",
    "side_mlb_10": "and the spread {} to",
    "side_mlb_90": "the spread −1030 to {} rpm",
    "side_mlb_sd": "the spread −1030 to +1090 rpm (sd {})",
    **{f"curve_ratio_{i}": "ratios " + ", ".join("{}" if j == i else "0.00" for j in range(5))
       + " over the five bins" for i in range(5)},
    "curve_low_ours": "over the five bins ({} against",
    "curve_low_gap": "rpm at 15-20°, {} rpm under the model",
    "curve_low_nathan": "bins (786 against {} rpm at 15-20°",
    "sd_launch_speed": "Launch speed sd: {} mph against",
    "sd_launch_speed_real": "mph against the real {}.",
}
_NUM = r"[−+\-]?[0-9][0-9.,]*(?:e[−+\-]?[0-9]+)?"
_NUMBER = f"({_NUM})"


def inline_pattern(name: str) -> re.Pattern:
    """The regex of ``INLINE[name]``: its one group is the number. The words on either
    side of another inline number (``−31°``) match any number there."""
    words = INLINE[name]
    before, after = words.split("{}")

    def loose(text):
        parts = re.split(f"(\\s+|{_NUM})", text)
        out = []
        for part in parts:
            if not part:
                continue
            if part.isspace():
                out.append(r"\s+")
            elif re.fullmatch(_NUM, part):
                out.append(_NUM)
            else:
                out.append(re.escape(part))
        return "".join(out)

    return re.compile(loose(before) + _NUMBER + loose(after))


def inline_values(text: str) -> dict:
    """``name -> the number the doc gives`` for every ``INLINE`` name (None: not found, or
    found more than once)."""
    out = {}
    for name in INLINE:
        found = inline_pattern(name).findall(text)
        out[name] = found[0] if len(found) == 1 else None
    return out


def splice_inline(text: str, values: dict) -> str:
    """``text`` with each inline number of ``values`` replaced."""
    for name, value in values.items():
        pattern = inline_pattern(name)
        if len(pattern.findall(text)) != 1:
            raise ValueError(f"{name}: the words {INLINE[name]!r} are not in the doc once")
        text = pattern.sub(lambda m, v=value: m[0][:m.start(1) - m.start(0)] + v
                           + m[0][m.end(1) - m.start(0):], text)
    return text


def render(names=None) -> tuple[dict, dict]:
    """The bodies of the doc's generated blocks named in ``names`` (default: every one)
    and the inline numbers they give (``game_preset``: the preset's own numbers)."""
    names = names or NAMES
    bodies, values = {}, {}
    for name in names:
        if name == "run_game_fastball":
            bodies[name], found = run_game_fastball()
            values.update(found)
        elif name == "run_real_pitches":
            bodies[name], found = run_real_pitches()
            values.update(found)
        elif name == "plate_pitches":
            bodies[name] = render_plate_pitches()
            values.update(plate_values())
        elif name == "attack_free":
            values.update(attack_free_fit())
        elif name == "in_play":
            values.update(in_play_values())
        elif name == "population_fit":
            bodies[name], found = population_fit()
            values.update(found)
        elif name == "presets_vs_real":
            found_bodies, found = presets_vs_real()
            bodies.update(found_bodies)
            values.update(found)
        elif name == "game_preset":
            values.update(game_preset_values())
        else:
            bodies[name] = RENDER[name]()
    return bodies, {k: v for k, v in values.items() if k in INLINE}


RENDER = {"location_q": render_location_q}
NAMES = ("location_q", "plate_pitches", "run_game_fastball", "run_real_pitches", "game_preset",
         "in_play", "presets_vs_real", "population_fit", "attack_free")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="update the doc")
    parser.add_argument("--only", help="comma-separated, of (default: every one): "
                                       + ", ".join(NAMES))
    parser.add_argument("--doc", default=str(DOC))
    args = parser.parse_args(argv)
    names = args.only.split(",") if args.only else None
    doc = Path(args.doc)
    text = doc.read_text(encoding="utf-8")
    bodies, values = render(names)
    if args.write:
        doc.write_text(splice_inline(splice(text, bodies), values), encoding="utf-8")
        print(f"updated {doc}")
        return 0
    stale = stale_blocks(doc.name, text, bodies)
    given = inline_values(text)
    for name, value in values.items():
        if given[name] != value:
            stale.append(name)
            print(f"{name}: the doc gives {given[name]}, the code {value} "
                  f"({INLINE[name]!r})")
    print("up to date" if not stale else f"stale: {', '.join(stale)}")
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
