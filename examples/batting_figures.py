"""The figures of docs/batting.md: the field frame and the bat at contact, and the
batted-ball cloud of studies/game_fastball.toml.

    .venv/bin/python examples/batting_figures.py [DATASET_DIR]

Without a dataset directory it runs the study into a temporary one first.
"""

import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mcbat  # noqa: E402
from mcbat.api import GameCase, solve_game  # noqa: E402
from mcbat.bodies import Ball, bat_preset  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "figures"
MPH, RPM, DEG, IN = 0.44704, 2 * np.pi / 60, np.pi / 180, 0.0254


def _arrow(ax, start, vec, color, label, **kw):
    ax.quiver(*start, *vec, color=color, arrow_length_ratio=0.12, linewidth=2, **kw)
    end = np.asarray(start) + np.asarray(vec)
    ax.text(*end, label, color=color, fontsize=9)


def frame_drawing(path):
    """(a) the field frame with the bat at contact, pitch and swing; (b) the contact seen
    along the bat axis: undercut and the batted ball's spin components."""
    case = GameCase(ball=Ball(0.145, 0.036), bat=bat_preset("r161"), pitch_speed=94 * MPH,
                    bat_speed=72 * MPH, mu=0.5, vertical_approach_angle=-5 * DEG,
                    spin_rate=2300 * RPM, spin_axis=180 * DEG, attack_angle=10 * DEG,
                    vertical_bat_angle=-30 * DEG, undercut=0.8 * IN)
    res = solve_game(case)
    fig = plt.figure(figsize=(12, 5.6))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    o = np.zeros(3)
    for v, name in ((np.array([1, 0, 0]), "x (1st base)"), (np.array([0, 1, 0]), "y (pitcher)"),
                    (np.array([0, 0, 1]), "z (up)")):
        _arrow(ax, o, 0.6 * v, "k", name)
    # the bat at contact: axis n from knob to barrel, placed so the sweet spot is at
    # (0.25, 0.3, 0.9) m (illustrative position; only directions matter to the physics)
    a, b = 10 * DEG, -30 * DEG
    u = np.array([0.0, np.cos(a), np.sin(a)])
    big_b = -np.sin(b) * np.tan(a)
    n = np.array([np.sqrt(np.cos(b) ** 2 - big_b ** 2), big_b, np.sin(b)])
    sweet = np.array([0.25, 0.3, 0.9])
    knob = sweet - (0.84 - 0.1524) * n
    barrel = sweet + 0.1524 * n
    ax.plot(*np.c_[knob, barrel], color="saddlebrown", linewidth=6, label="bat (knob to barrel)")
    pivot = knob + 0.1524 * n
    ax.scatter(*pivot, color="k", s=20)
    ax.text(*pivot, " pivot", fontsize=8)
    _arrow(ax, sweet, 0.35 * u, "tab:blue", "")
    _arrow(ax, sweet + np.array([0, 0.6, 0.08]), 0.35 * np.array(res.pitch_velocity)
           / np.linalg.norm(res.pitch_velocity), "tab:red", "pitch")
    vout = np.array(res.ball_velocity) / np.linalg.norm(res.ball_velocity)
    _arrow(ax, sweet, 0.5 * vout, "tab:green", "")
    ax.text2D(0.02, 0.02, f"green: batted ball, {res.launch_speed:.0f} mph, launch angle "
              f"{res.launch_angle:.0f}° (undercut 0.8 in)\nblue: sweet-spot velocity "
              "(attack angle 10°); red: pitch (VAA -5°)", transform=ax.transAxes, fontsize=8)
    ax.set_xlim(-0.6, 0.8), ax.set_ylim(-0.2, 1.0), ax.set_zlim(0, 1.2)
    ax.set_xlabel("x (m)"), ax.set_ylabel("y (m)"), ax.set_zlabel("z (m)")
    ax.view_init(elev=18, azim=-62)
    ax.set_title("(a) field frame (right-handed batter), bat at contact\n"
                 "vertical bat angle -30°: barrel below the hands")
    ax.legend(loc="upper left", fontsize=8)

    ax2 = fig.add_subplot(1, 2, 2)
    r_bat, r_ball, d = 0.0313, 0.036, 0.8 * IN
    t = np.linspace(0, 2 * np.pi, 200)
    ax2.fill(r_bat * np.cos(t), r_bat * np.sin(t), color="burlywood")
    ax2.text(0, 0, "bat axis\n(into page)", ha="center", va="center", fontsize=8)
    # the ball approaches from the left (relative velocity to the right... drawn in the
    # plane perpendicular to the axis: horizontal = towards the pitcher, vertical = up)
    cx = -np.sqrt((r_bat + r_ball) ** 2 - d ** 2)
    ax2.plot(cx + r_ball * np.cos(t), d + r_ball * np.sin(t), color="tab:red")
    ax2.plot([cx - 0.09, 0.08], [d, d], "r--", linewidth=0.8)
    ax2.plot([-0.13, 0.08], [0, 0], "k:", linewidth=0.8)
    ax2.annotate("", (cx - 0.05, d), (cx - 0.1, d),
                 arrowprops=dict(arrowstyle="->", color="tab:red"))
    ax2.text(cx - 0.08, d - 0.03, "ball relative\nto the bat", color="tab:red", fontsize=8)
    ax2.annotate("", (0.06, 0), (0.06, d), arrowprops=dict(arrowstyle="<->"))
    ax2.text(0.064, d / 2, "undercut D > 0\n(ball centre above\nthe axis)", fontsize=8,
             va="center", ha="right")
    ax2.annotate("", (cx - 0.06, d + 0.05), (cx, d),
                 arrowprops=dict(arrowstyle="->", color="tab:green", linewidth=2))
    ax2.text(cx + 0.01, d + 0.07, "launch: up, with backspin\n(top of ball turns back)",
             color="tab:green", fontsize=8)
    ax2.set_aspect("equal")
    ax2.set_xlim(-0.16, 0.13), ax2.set_ylim(-0.08, 0.12)
    ax2.set_xlabel("towards the catcher <-   (m)   -> towards the pitcher")
    ax2.set_ylabel("up (m)")
    ax2.set_title("(b) the contact seen along the bat axis\n"
                  "spin of the batted ball (velocity v): backspin = ω·b, b = unit(v × z);\n"
                  "sidespin = ω·s, s = b × unit(v); gyrospin = ω·unit(v)", fontsize=9)
    # the mirror: the ball moves to -x in this view, so flip to put the pitcher on the left
    ax2.invert_xaxis()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def cloud(dataset, path):
    """Launch angle against launch speed, coloured by undercut."""
    df = mcbat.load(dataset)
    df = df[df.status == 0]
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    sc = ax.scatter(df.launch_speed, df.launch_angle, c=df.undercut / IN, s=2, cmap="coolwarm",
                    vmin=-1.5, vmax=1.5, rasterized=True)
    fig.colorbar(sc, label="undercut (in; > 0: ball centre above the bat axis)")
    ax.set_xlabel("launch speed (mph)")
    ax.set_ylabel("launch angle (deg)")
    ax.axhline(0, color="k", linewidth=0.5)
    q = np.percentile(df.launch_speed, [5, 50, 95])
    ax.set_title(f"game_fastball: {len(df):,} batted balls (median {q[1]:.1f} mph, "
                 f"5-95 % {q[0]:.1f}-{q[2]:.1f})", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    """Draw both figures into docs/figures."""
    OUT.mkdir(parents=True, exist_ok=True)
    frame_drawing(OUT / "batting_frame.png")
    if len(sys.argv) > 1:
        dataset = Path(sys.argv[1])
    else:
        dataset = Path(tempfile.mkdtemp()) / "game_fastball"
        mcbat.run(ROOT / "studies" / "game_fastball.toml", dataset, progress=False)
    cloud(dataset, OUT / "batting_cloud.png")


if __name__ == "__main__":
    main()
