"""The generated tables of ``docs/sawicki2003.md``: write them, or check them.

    NUMBA_NUM_THREADS=1 .venv/bin/python -m validation sawicki2003_doc           # check
    NUMBA_NUM_THREADS=1 .venv/bin/python -m validation sawicki2003_doc --write   # update

Two blocks:

``optimum``
    ``mcbat reproduce sawicki2003``'s table and verdict (its ``table.md``): run here into a
    temporary directory, or read from ``--results DIR`` (the command's ``DIR/sawicki2003``).
``steps``
    Where the optimal undercut goes when mcbat's setup moves towards Sawicki et al.'s, one
    change at a time (:mod:`mcbat.papers.sawicki2003.steps`), plus one what-if that mcbat's
    flight models cannot express: drag without its spin term (:func:`fly_spin_free_drag`).
    ``--steps-json PATH`` also writes the numbers.

Without ``--write`` the script exits 1 and prints the difference when a block of the doc
is not what the code gives now. ~2-4 min on one thread (the reproduction's four Monte Carlo
scans and the steps' two).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

from mcbat.papers.sawicki2003 import steps as st
from mcbat.papers.sawicki2003.carry import BALL, SETTINGS, fly
from mcbat.papers.sawicki2003.doc import splice, stale_blocks
from mcbat.papers.sawicki2003.reproduce import reproduce

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "sawicki2003.md"

_FT = 0.3048
_RPM = 60.0 / (2.0 * np.pi)


def fly_spin_free_drag(v, w, *, spin_drag=False, lift="sawicki2003", decay_time=None,
                       dt=1e-3):
    """A what-if flight (not one of mcbat's models): the reproduction's air, ball and
    launch point, ``C_D = 0.3008`` without the calculator's spin term
    ``0.0292 (spin / 1000 rpm)`` unless ``spin_drag``, the lift of ``lift`` (``nathan``
    or ``sawicki2003``), spin decay with ``decay_time`` (s; None: none). Classical RK4
    with step ``dt`` over all balls at once; the landing is interpolated (cubic Hermite)
    within the step that crosses the ground. Returns ``hit_distance`` (ft) and
    ``hang_time`` (s), NaN for a ball still in the air after 30 s."""
    v = np.array(v, np.float64)
    w = np.asarray(w, np.float64)
    n = v.shape[1]
    x = np.repeat(np.asarray(SETTINGS.start, np.float64)[:, None], n, axis=1)
    rate = np.linalg.norm(w, axis=0)
    axis = np.divide(w, rate, out=np.zeros_like(w), where=rate > 0)
    c0 = SETTINGS.density * np.pi * BALL.radius ** 2 / (2.0 * BALL.mass)
    gravity = 9.80665  # the kernel's (mcbat.core.flight.GRAVITY)

    def accel(t, vel):
        speed = np.linalg.norm(vel, axis=0)
        decay = 1.0 if decay_time is None else np.exp(-t * speed / (decay_time * 44.704))
        cd = 0.3008 + (0.0292 * rate * _RPM / 1000.0 * decay if spin_drag else 0.0)
        s = BALL.radius * rate * decay / speed
        if lift == "nathan":
            cl = 1.120 * s / (0.583 + 2.333 * s)
        else:
            cl = np.where(s < 0.1, 1.5 * s, 0.09 + 0.6 * s)
        a = -c0 * cd * speed * vel + c0 * cl * speed * np.cross(axis, vel, axis=0)
        a[2] -= gravity
        return a

    landed = np.full(n, np.nan)
    hang = np.full(n, np.nan)
    t = 0.0
    alive = np.ones(n, bool)
    for _ in range(int(30.0 / dt)):
        if not alive.any():
            break
        k1v = accel(t, v)
        k1x = v
        k2v = accel(t + dt / 2, v + dt / 2 * k1v)
        k2x = v + dt / 2 * k1v
        k3v = accel(t + dt / 2, v + dt / 2 * k2v)
        k3x = v + dt / 2 * k2v
        k4v = accel(t + dt, v + dt * k3v)
        k4x = v + dt * k3v
        x_new = x + dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
        v_new = v + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        down = alive & (x_new[2] <= 0.0) & (v_new[2] < 0.0)
        if down.any():
            # the step's cubic Hermite interpolant in time: root of z(s) on [0, 1]
            for i in np.flatnonzero(down):
                z0, z1, dz0, dz1 = x[2, i], x_new[2, i], v[2, i] * dt, v_new[2, i] * dt
                coef = [2 * z0 - 2 * z1 + dz0 + dz1, -3 * z0 + 3 * z1 - 2 * dz0 - dz1,
                        dz0, z0]
                roots = [r.real for r in np.roots(coef)
                         if abs(r.imag) < 1e-9 and -1e-9 <= r.real <= 1 + 1e-9]
                s = min(roots) if roots else 1.0
                h = [2 * s ** 3 - 3 * s ** 2 + 1, s ** 3 - 2 * s ** 2 + s,
                     -2 * s ** 3 + 3 * s ** 2, s ** 3 - s ** 2]
                xy = (h[0] * x[:2, i] + h[1] * v[:2, i] * dt + h[2] * x_new[:2, i]
                      + h[3] * v_new[:2, i] * dt)
                landed[i] = np.hypot(xy[0], xy[1]) / _FT
                hang[i] = t + s * dt
            alive &= ~down
        x, v = x_new, v_new
        t += dt
    return {"hit_distance": landed, "hang_time": hang}


def check_what_if_flight():
    """The what-if flight with the calculator's drag, lift and decay against mcbat's
    kernel on 200 launches of the scan's range; returns the largest difference (ft)."""
    rng = np.random.default_rng(3)
    n = 200
    speed = rng.uniform(40.0, 50.0, n)
    angle = np.radians(rng.uniform(10.0, 45.0, n))
    spray = np.radians(rng.uniform(-10.0, 10.0, n))
    v = speed * np.stack([np.cos(angle) * np.sin(spray), np.cos(angle) * np.cos(spray),
                          np.sin(angle)])
    b = np.stack([np.cos(spray), -np.sin(spray), np.zeros(n)])  # unit(v x z)
    w = b * rng.uniform(-100.0, 400.0, n)  # backspin (rad/s) along b; some topspin
    ours = fly_spin_free_drag(v, w, spin_drag=True, lift="nathan", decay_time=30.0)
    kernel = fly(v, w)
    return float(np.nanmax(np.abs(ours["hit_distance"] - kernel["hit_distance"])))


WHAT_IF = st.Step("their lift, spin-free drag (what-if)",
                  "their lift, no spin decay, and C_D = 0.3008 without the calculator's "
                  "spin term (not one of mcbat's flight models)")


WHAT_IF_LEVEL = st.Step("level bat + their lift, spin-free drag (what-if)",
                        "the level bat and the what-if flight together",
                        edits=(("swing", "vertical_bat_angle", {"value": 0.0, "unit": "deg"}),))


def run_all_steps(echo=print) -> dict:
    """The package's steps and the what-ifs (the table of the doc's ``steps`` block)."""
    result = st.run_steps(echo=echo)
    for step in (WHAT_IF, WHAT_IF_LEVEL):
        optima = {pitch: st.run_step(step, pitch, fly_fn=fly_spin_free_drag)
                  for pitch in result["steps"][0]["optimum"]}
        result["steps"].append({"name": step.name, "change": step.change,
                                "optimum": optima})
        echo(f"{step.name}: " + ", ".join(f"{p} {o['undercut_cm']:.2f} cm"
                                           for p, o in optima.items()))
    return result


def render(results_dir=None, steps_json=None, echo=print) -> dict:
    """The bodies of the doc's generated blocks, as the code gives them now."""
    if results_dir is None:
        with tempfile.TemporaryDirectory() as tmp:
            paths = reproduce(tmp, threads=1, echo=lambda *_: None)
            optimum = paths["markdown"].read_text().rstrip("\n")
    else:
        optimum = (Path(results_dir) / "sawicki2003" / "table.md").read_text().rstrip("\n")
    echo(f"what-if flight against the kernel (calculator's model): largest difference "
         f"{check_what_if_flight():.4f} ft on 200 launches")
    result = run_all_steps(echo=echo)
    if steps_json is not None:
        Path(steps_json).write_text(st.to_json(result))
    return {"optimum": optimum, "steps": st.format_markdown(result)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="update the doc's blocks")
    parser.add_argument("--results", help="read the reproduction from DIR/sawicki2003 "
                                          "instead of running it")
    parser.add_argument("--steps-json", help="also write the steps' numbers here")
    parser.add_argument("--doc", default=str(DOC))
    args = parser.parse_args(argv)
    doc = Path(args.doc)
    text = doc.read_text(encoding="utf-8")
    bodies = render(args.results, args.steps_json)
    if args.write:
        doc.write_text(splice(text, bodies), encoding="utf-8")
        print(f"updated {doc}")
        return 0
    stale = stale_blocks(doc.name, text, bodies)
    print("up to date" if not stale else f"stale blocks: {', '.join(stale)}")
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
