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

Numbers inside the text (``INLINE``: each found by the words around it) are written too:
the game preset's ``e*`` at 165.5 mph and the rigid model's ``q`` and ``r`` at the
R161's sweet spot (``game_preset``), and the run's (``run_game_fastball``). ``--only``
takes the names above and ``game_preset``.

Without ``--write`` the script exits 1 and prints the difference when a block of the doc
or a number of the text is not what the code gives now. ~1 min on one thread, most of it
the study's run (its flight).
"""

from __future__ import annotations

import argparse
import difflib
import re
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import numpy as np

from mcbat.papers.sawicki2003.doc import blocks, splice

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
    from mcbat.papers.statcast.spin import nathan_average_spin

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
}
_NUMBER = r"([−+\-]?[0-9][0-9.,]*)"


def inline_pattern(name: str) -> re.Pattern:
    """The regex of ``INLINE[name]``: its one group is the number. The words on either
    side of another inline number (``−31°``) match any number there."""
    words = INLINE[name]
    before, after = words.split("{}")

    def loose(text):
        parts = re.split(r"(\s+|[−+\-]?[0-9][0-9.,]*)", text)
        out = []
        for part in parts:
            if not part:
                continue
            if part.isspace():
                out.append(r"\s+")
            elif re.fullmatch(r"[−+\-]?[0-9][0-9.,]*", part):
                out.append(r"[−+\-]?[0-9][0-9.,]*")
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
    names = names or [*RENDER, "run_game_fastball", "game_preset"]
    bodies, values = {}, {}
    for name in names:
        if name == "run_game_fastball":
            bodies[name], found = run_game_fastball()
            values.update(found)
        elif name == "game_preset":
            values.update(game_preset_values())
        else:
            bodies[name] = RENDER[name]()
    return bodies, {k: v for k, v in values.items() if k in INLINE}


RENDER = {"location_q": render_location_q, "plate_pitches": render_plate_pitches}
NAMES = (*RENDER, "run_game_fastball", "game_preset")


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
    current = blocks(text)
    stale = [name for name in bodies if current.get(name) != bodies[name]]
    for name in stale:
        sys.stdout.writelines(difflib.unified_diff(
            (current.get(name, "") + "\n").splitlines(True),
            (bodies[name] + "\n").splitlines(True), f"{doc.name} ({name})", f"code ({name})"))
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
