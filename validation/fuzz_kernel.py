"""Fuzz the parallel batch kernel with extreme but valid impacts (plus invalid ones).

Run:  .venv/bin/python -m validation fuzz_kernel [--n 1000000] [--chunk 50000] [--seed 20260601]
      [--timeout 120]

Rows are drawn by a numpy ``Generator`` with a fixed seed. Every extreme dimension is
switched on independently for a share of the rows, so the categories also meet each other:

=================  ======  ===================================================================
category           share   what
=================  ======  ===================================================================
tiny_ball          15 %    ball radius 1e-4..1e-2 m, mass 1e-5..1e-2 kg (log-uniform)
huge_bat           15 %    bat mass and both inertias log-uniform up to 1e6 (kg, kg m^2)
taper              40 %    bat slope in [-0.5, 0.5] (a quarter of them exactly +-0.5)
grazing            20 %    contact azimuth +-(pi/2 - 10^-k), k in [1, 12]
tiny_vn            20 %    approach speed |v_n| = 10^U(-9, -3) m/s (a tenth exactly 1e-9)
high_spin          30 %    ball spin U(-1e4, 1e4) rad/s on every axis (else +-500)
moving_bat         50 %    bat velocity U(-50, 50) m/s and spin U(-1e3, 1e3) rad/s per axis
mu_zero / mu_high  10 / 25 mu exactly 0 / mu in [2, 10] (a fifth of those exactly 10)
e_zero / e_one     15 / 15 e* exactly 0 / exactly 1 (else uniform in [0, 1])
no_slip            5 %     no tangential relative velocity at the contact (to rounding)
not_approaching    3 %     v_n >= 0 (a quarter exactly 0): expects status not_approaching
invalid            2 %     one input NaN / +-inf / out of range: expects status invalid_input
=================  ======  ===================================================================

The approach speed is imposed to rounding: the ball velocity is shifted along the contact
normal until the relative normal velocity at the contact equals the drawn ``v_n``.

Checks (the exit code is 0 only if all hold): no exception, no chunk over the watchdog
time; every status a known code and every end state 0/1; on status ok every output finite
(except ``stick_impulse`` / ``stick_criterion``, which are NaN together when sliding never
stopped), no NaN at all beyond that pair, energy not gained beyond 1e-9 relative (nor
positive friction or normal work beyond 1e-9 E_in) and linear momentum conserved to 1e-9 of
``m_p |v_p| + m_b |v_b|``; on a non-ok status NaN velocity outputs; invalid rows flagged
``invalid_input`` and clearly receding rows ``not_approaching``.

Watchdog: each chunk runs in a worker thread (the kernel releases the GIL) and the main
thread waits at most ``--timeout`` seconds for it. A chunk still running then cannot be
stopped, so the campaign ends there and fails; loading or compiling the kernel happens
before the first timed chunk.
"""

import argparse
import math
import sys
import threading
import time

import numpy as np

import harness
from mcbat.core import status as st
from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE

FIELD = {name: i for i, name in enumerate(INPUT_FIELDS)}
OUT = {name: i for i, name in enumerate(OUTPUT_FIELDS)}
VELOCITY_OUTPUTS = [OUT[n] for n in OUTPUT_FIELDS[:12]]
STICK_OUTPUTS = [OUT["stick_impulse"], OUT["stick_criterion"]]
FINITE_OUTPUTS = [i for i in range(len(OUTPUT_FIELDS)) if i not in STICK_OUTPUTS]

CATEGORIES = ("tiny_ball", "huge_bat", "taper", "grazing", "tiny_vn", "high_spin",
              "moving_bat", "mu_zero", "mu_high", "e_zero", "e_one", "e_x", "no_slip",
              "not_approaching", "invalid")

ENERGY_RTOL = 1e-9
MOMENTUM_RTOL = 1e-9


def _loguniform(rng, lo, hi, n):
    return np.exp(rng.uniform(math.log(lo), math.log(hi), n))


def contact_normal_velocity(x, full=False):
    """Relative normal velocity at the contact (numpy mirror of the kernel's geometry).

    Returns ``(v_n, t3)`` (and the relative contact velocity ``v0`` if ``full``); ``x`` is
    a ``float64[len(INPUT_FIELDS), n]`` input array.
    """
    f = FIELD
    with np.errstate(invalid="ignore", over="ignore"):  # invalid rows carry NaN / inf
        c, s = np.cos(x[f["angle"]]), np.sin(x[f["angle"]])
        inv = 1.0 / np.sqrt(1.0 + x[f["bat_slope"]] ** 2)
        t3 = np.stack([c * inv, s * inv, -x[f["bat_slope"]] * inv])
        r_c = np.stack([x[f["bat_radius"]] * c, x[f["bat_radius"]] * s, x[f["axial"]]])
        rho = -x[f["ball_radius"]] * t3
        ball_v = x[[f["ball_vx_in"], f["ball_vy_in"], f["ball_vz_in"]]]
        ball_w = x[[f["ball_wx_in"], f["ball_wy_in"], f["ball_wz_in"]]]
        bat_v = x[[f["bat_vx_in"], f["bat_vy_in"], f["bat_vz_in"]]]
        bat_w = x[[f["bat_wx_in"], f["bat_wy_in"], f["bat_wz_in"]]]
        v0 = ball_v + np.cross(ball_w, rho, axis=0) - bat_v - np.cross(bat_w, r_c, axis=0)
        vn = np.sum(v0 * t3, axis=0)
    return (vn, t3, v0) if full else (vn, t3)


def extreme_inputs(n, rng):
    """``(inputs, flags)``: a ``float64[len(INPUT_FIELDS), n]`` array and a dict of boolean
    masks, one per entry of :data:`CATEGORIES`."""
    f = FIELD
    x = np.empty((len(INPUT_FIELDS), n))
    flag = {name: np.zeros(n, bool) for name in CATEGORIES}

    def share(p):
        return rng.random(n) < p

    # Ball.
    tiny = flag["tiny_ball"] = share(0.15)
    x[f["ball_mass"]] = np.where(tiny, _loguniform(rng, 1e-5, 1e-2, n), rng.uniform(0.05, 0.5, n))
    x[f["ball_radius"]] = np.where(tiny, _loguniform(rng, 1e-4, 1e-2, n),
                                   rng.uniform(0.02, 0.06, n))
    x[f["ball_inertia_factor"]] = rng.uniform(0.05, 2.0 / 3.0, n)
    # Bat.
    huge = flag["huge_bat"] = share(0.15)
    x[f["bat_mass"]] = np.where(huge, _loguniform(rng, 1.0, 1e6, n), rng.uniform(0.3, 3.0, n))
    x[f["bat_transverse_inertia"]] = np.where(huge, _loguniform(rng, 1e-3, 1e6, n),
                                              rng.uniform(0.005, 0.2, n))
    x[f["bat_axial_inertia"]] = np.where(huge, _loguniform(rng, 1e-4, 1e6, n),
                                         rng.uniform(1e-4, 2e-3, n))
    x[f["axial"]] = rng.uniform(-0.4, 0.4, n)
    x[f["bat_radius"]] = rng.uniform(0.01, 0.05, n)
    taper = flag["taper"] = share(0.4)
    slope = rng.uniform(-0.5, 0.5, n)
    exact = rng.random(n) < 0.25
    slope[exact] = np.where(rng.random(exact.sum()) < 0.5, -0.5, 0.5)
    x[f["bat_slope"]] = np.where(taper, slope, 0.0)
    # Contact azimuth.
    graze = flag["grazing"] = share(0.2)
    sign = np.where(rng.random(n) < 0.5, -1.0, 1.0)
    grazing_angle = sign * (math.pi / 2 - 10.0 ** -rng.uniform(1.0, 12.0, n))
    x[f["angle"]] = np.where(graze, grazing_angle, rng.uniform(-1.5, 1.5, n))
    # Velocities: the ball comes in along -x (as in the paper's Sec. V) with a transverse
    # component; spins and bat motion on every axis.
    speed = rng.uniform(0.5, 100.0, n)
    x[f["ball_vx_in"]] = -speed
    x[f["ball_vy_in"]] = rng.uniform(-20.0, 20.0, n)
    x[f["ball_vz_in"]] = rng.uniform(-20.0, 20.0, n)
    spin = flag["high_spin"] = share(0.3)
    for axis in "xyz":
        x[f[f"ball_w{axis}_in"]] = np.where(spin, rng.uniform(-1e4, 1e4, n),
                                            rng.uniform(-500.0, 500.0, n))
    moving = flag["moving_bat"] = share(0.5)
    for axis in "xyz":
        x[f[f"bat_v{axis}_in"]] = np.where(moving, rng.uniform(-50.0, 50.0, n), 0.0)
        x[f[f"bat_w{axis}_in"]] = np.where(moving, rng.uniform(-1e3, 1e3, n), 0.0)
    # Friction and restitution.
    u = rng.random(n)
    flag["mu_zero"] = u < 0.10
    flag["mu_high"] = u >= 0.75
    mu = np.where(u < 0.75, rng.uniform(0.0, 2.0, n), rng.uniform(2.0, 10.0, n))
    mu[flag["mu_zero"]] = 0.0
    mu[u >= 0.95] = 10.0
    x[f["mu"]] = mu
    u = rng.random(n)
    flag["e_zero"] = u < 0.15
    flag["e_one"] = (u >= 0.15) & (u < 0.30)
    x[f["e"]] = np.where(flag["e_zero"], 0.0, np.where(flag["e_one"], 1.0, rng.random(n)))
    flag["e_x"] = share(0.3)  # tangential compliance (Cross & Nathan's e_x), 1 at times
    x[f["e_x"]] = np.where(flag["e_x"], np.minimum(rng.uniform(0.0, 1.2, n), 1.0), 0.0)
    # Approach speed, imposed along the contact normal (and, for no_slip rows, nothing
    # left in the tangent plane).
    tiny_vn = flag["tiny_vn"] = share(0.2)
    vn = np.where(tiny_vn, -(10.0 ** -rng.uniform(3.0, 9.0, n)), -rng.uniform(0.05, 60.0, n))
    vn[tiny_vn & (rng.random(n) < 0.1)] = -1e-9
    receding = flag["not_approaching"] = share(0.03)
    vn[receding] = np.where(rng.random(receding.sum()) < 0.25, 0.0,
                            rng.uniform(1e-6, 10.0, receding.sum()))
    flag["tiny_vn"] &= ~receding
    current, t3, v0 = contact_normal_velocity(x, full=True)
    no_slip = flag["no_slip"] = share(0.05)
    shift = (vn - current) * t3 - np.where(no_slip, v0 - current * t3, 0.0)
    for k, axis in enumerate("xyz"):
        x[f[f"ball_v{axis}_in"]] += shift[k]
    # Invalid rows: one input non-finite or out of range.
    bad = flag["invalid"] = share(0.02)
    rows = np.flatnonzero(bad)
    field = rng.integers(0, len(INPUT_FIELDS), rows.size)
    kind = rng.integers(0, 4, rows.size)
    nonfinite = kind < 3
    x[field[nonfinite], rows[nonfinite]] = np.array([math.nan, math.inf, -math.inf])[
        kind[nonfinite]]
    out_of_range = {  # a value the kernel must reject for each field that has a range
        "ball_mass": 0.0, "ball_radius": -0.01, "ball_inertia_factor": 0.0,
        "bat_mass": -1.0, "bat_transverse_inertia": 0.0, "bat_axial_inertia": -1e-4,
        "bat_radius": 0.0, "mu": -1e-3, "e": np.nextafter(1.0, 2.0), "e_x": -1e-3,
    }
    names = list(out_of_range)
    pick = rows[kind == 3]
    choice = rng.integers(0, len(names), pick.size)
    for j, row in zip(choice, pick):
        x[FIELD[names[j]], row] = out_of_range[names[j]]
    return x, flag


def _solve_chunk(x, timeout):
    """Run ``solve_batch`` on ``x`` in a worker thread; ``(result, error, seconds, hung)``."""
    out, status, end_state = allocate_outputs(x.shape[1])
    box = {}

    def work():
        try:
            solve_batch(x, DEFAULT_STEPS, DEFAULT_TOLERANCE, DEFAULT_MAX_STEPS,
                        out, status, end_state)
        except BaseException as exc:  # noqa: BLE001 - any exception is a finding
            box["error"] = exc

    t0 = time.perf_counter()
    worker = threading.Thread(target=work, daemon=True)
    worker.start()
    worker.join(timeout)
    seconds = time.perf_counter() - t0
    if worker.is_alive():
        return None, None, seconds, True
    return (out, status, end_state), box.get("error"), seconds, False


def check_chunk(x, flags, out, status, end_state):
    """``(bad, worst)``: boolean masks of the rows that break each check, and the worst
    relative energy gain and momentum error over the ok rows."""
    f = FIELD
    ok = status == st.OK
    finite = np.isfinite(out)
    nan = np.isnan(out)
    stick_nan = nan[STICK_OUTPUTS]
    bad = {}
    bad["unknown_status"] = ~np.isin(status, list(st.STATUS_NAMES))
    bad["bad_end_state"] = ~np.isin(end_state, list(st.END_STATE_NAMES))
    bad["ok_non_finite"] = ok & ~finite[FINITE_OUTPUTS].all(axis=0)
    bad["ok_nan"] = ok & (nan[FINITE_OUTPUTS].any(axis=0) | (stick_nan[0] != stick_nan[1]))
    bad["flagged_not_nan"] = ~ok & ~nan[VELOCITY_OUTPUTS].all(axis=0)
    e_in, e_out = out[OUT["energy_in"]], out[OUT["energy_out"]]
    with np.errstate(invalid="ignore", over="ignore"):
        bad["energy_gained"] = ok & (e_out > e_in * (1.0 + ENERGY_RTOL))
        # Friction and the normal force (over the whole impact) only ever take energy out.
        bad["friction_work_positive"] = ok & (out[OUT["friction_work"]] > ENERGY_RTOL * e_in)
        bad["normal_work_positive"] = ok & (out[OUT["normal_work"]] > ENERGY_RTOL * e_in)
        m, mb = x[f["ball_mass"]], x[f["bat_mass"]]
        vp0 = x[[f["ball_vx_in"], f["ball_vy_in"], f["ball_vz_in"]]]
        vb0 = x[[f["bat_vx_in"], f["bat_vy_in"], f["bat_vz_in"]]]
        vp1 = out[[OUT["ball_vx"], OUT["ball_vy"], OUT["ball_vz"]]]
        vb1 = out[[OUT["bat_vx"], OUT["bat_vy"], OUT["bat_vz"]]]
        error = np.abs(m * (vp1 - vp0) + mb * (vb1 - vb0)).max(axis=0)
        scale = np.maximum(m * np.linalg.norm(vp0, axis=0) + mb * np.linalg.norm(vb0, axis=0),
                           m * np.linalg.norm(vp1, axis=0) + mb * np.linalg.norm(vb1, axis=0))
        bad["momentum_not_conserved"] = ok & ~(error <= MOMENTUM_RTOL * scale)
        gain = np.where(ok, (e_out - e_in) / e_in, -np.inf)
        drift = np.where(ok, error / scale, -np.inf)
    worst = dict(energy_gain=float(gain.max(initial=-np.inf)),
                 momentum_error=float(drift.max(initial=-np.inf)))
    bad["invalid_not_flagged"] = flags["invalid"] & (status != st.INVALID_INPUT)
    vn, _ = contact_normal_velocity(x)
    bad["receding_not_flagged"] = (flags["not_approaching"] & ~flags["invalid"] & (vn > 1e-9)
                                   & (status != st.NOT_APPROACHING))
    return bad, worst


CHECKS = ("unknown_status", "bad_end_state", "ok_non_finite", "ok_nan", "flagged_not_nan",
          "energy_gained", "friction_work_positive", "normal_work_positive",
          "momentum_not_conserved", "invalid_not_flagged", "receding_not_flagged")


def fuzz(n=1_000_000, chunk=50_000, seed=20260601, timeout=120.0, examples=3, log=print):
    """Run the fuzz campaign; return a summary dict (``summary["passed"]`` is the verdict)."""
    rng = np.random.default_rng(seed)
    s = dict(n=n, chunk=chunk, seed=seed, rows=0, crashes=0, crashed_rows=0, hung_chunks=0,
             by_status={name: 0 for name in st.STATUS_NAMES.values()},
             by_end_state={name: 0 for name in st.END_STATE_NAMES.values()},
             failures={name: 0 for name in CHECKS}, examples={name: [] for name in CHECKS},
             by_category={name: dict(rows=0, **{k: 0 for k in st.STATUS_NAMES.values()})
                          for name in CATEGORIES},
             max_steps=0, max_steps_row=None, mean_steps_ok=0.0,
             slowest_chunk=None, slowest_seconds=0.0, kernel_seconds=0.0,
             worst_energy_gain=-math.inf, worst_momentum_error=-math.inf)
    steps_sum = 0.0
    ok_rows = 0
    t_start = time.perf_counter()
    # Load / compile the kernel before the watchdog starts counting.
    warm, _ = extreme_inputs(64, np.random.default_rng(0))
    s["load_seconds"] = _solve_chunk(warm, None)[2]
    for index, start in enumerate(range(0, n, chunk)):
        size = min(chunk, n - start)
        x, flags = extreme_inputs(size, rng)
        result, error, seconds, hung = _solve_chunk(x, timeout)
        s["kernel_seconds"] += seconds
        if seconds > s["slowest_seconds"]:
            s["slowest_seconds"], s["slowest_chunk"] = seconds, index
        if hung:
            s["hung_chunks"] += 1
            log(f"chunk {index} (rows {start}..{start + size - 1}) still running after "
                f"{timeout:.0f} s: stopping the campaign")
            break
        if error is not None:
            s["crashes"] += 1
            log(f"chunk {index} raised {error!r}; isolating rows")
            for j in range(size):
                _, err, _, hung_row = _solve_chunk(np.ascontiguousarray(x[:, j:j + 1]), timeout)
                if err is not None or hung_row:
                    s["crashed_rows"] += 1
                    if s["crashed_rows"] <= examples:
                        log(f"  row {start + j}: {err!r} inputs {x[:, j].tolist()}")
            s["rows"] += size
            continue
        out, status, end_state = result
        s["rows"] += size
        for code, name in st.STATUS_NAMES.items():
            s["by_status"][name] += int(np.sum(status == code))
            for cat in CATEGORIES:
                s["by_category"][cat][name] += int(np.sum(flags[cat] & (status == code)))
        for cat in CATEGORIES:
            s["by_category"][cat]["rows"] += int(flags[cat].sum())
        ok = status == st.OK
        for code, name in st.END_STATE_NAMES.items():
            s["by_end_state"][name] += int(np.sum(ok & (end_state == code)))
        steps = out[OUT["rk4_steps"]]
        finite_steps = np.where(np.isfinite(steps), steps, 0.0)
        j = int(np.argmax(finite_steps))
        if finite_steps[j] > s["max_steps"]:
            s["max_steps"] = int(finite_steps[j])
            s["max_steps_row"] = dict(row=start + j, status=int(status[j]),
                                      inputs=dict(zip(INPUT_FIELDS, x[:, j].tolist())))
        steps_sum += float(finite_steps[ok].sum())
        ok_rows += int(ok.sum())
        bad, worst = check_chunk(x, flags, out, status, end_state)
        s["worst_energy_gain"] = max(s["worst_energy_gain"], worst["energy_gain"])
        s["worst_momentum_error"] = max(s["worst_momentum_error"], worst["momentum_error"])
        for name, mask in bad.items():
            count = int(mask.sum())
            s["failures"][name] += count
            for j in np.flatnonzero(mask)[:max(0, examples - len(s["examples"][name]))]:
                s["examples"][name].append(dict(
                    row=start + int(j), status=int(status[j]), end_state=int(end_state[j]),
                    inputs=dict(zip(INPUT_FIELDS, x[:, j].tolist())),
                    outputs=dict(zip(OUTPUT_FIELDS, out[:, j].tolist()))))
    s["mean_steps_ok"] = steps_sum / max(ok_rows, 1)
    s["wall_seconds"] = time.perf_counter() - t_start
    s["passed"] = (s["rows"] == n and s["crashes"] == 0 and s["hung_chunks"] == 0
                   and not any(s["failures"].values()))
    return s


def report(s, log=print):
    """Print the summary of :func:`fuzz`."""
    log(f"fuzz_kernel: {s['rows']:,} / {s['n']:,} rows, seed {s['seed']}, chunks of "
        f"{s['chunk']:,}, settings steps={DEFAULT_STEPS} tolerance={DEFAULT_TOLERANCE:g} "
        f"max_steps={DEFAULT_MAX_STEPS}")
    log(f"time: {s['wall_seconds']:.1f} s wall ({s['load_seconds']:.1f} s loading or compiling "
        f"the kernel), {s['kernel_seconds']:.1f} s in the kernel "
        f"({s['rows'] / max(s['kernel_seconds'], 1e-9):,.0f} rows/s); slowest chunk "
        f"#{s['slowest_chunk']} {s['slowest_seconds']:.2f} s")
    log(f"crashes: {s['crashes']} chunks ({s['crashed_rows']} rows); hung chunks: "
        f"{s['hung_chunks']}")
    log("rows by status: " + ", ".join(f"{k} {v:,}" for k, v in s["by_status"].items()))
    log("ok rows by end state: " + ", ".join(f"{k} {v:,}" for k, v in
                                              s["by_end_state"].items()))
    log(f"RK4 steps: max {s['max_steps']}, mean {s['mean_steps_ok']:.1f} over ok rows; "
        f"{s['by_status']['max_steps']:,} rows stopped at the limit of {DEFAULT_MAX_STEPS} "
        f"(status max_steps: the kernel reports 0 steps for them)")
    log(f"worst over ok rows: energy change (E_out - E_in) / E_in = "
        f"{s['worst_energy_gain']:.3g}, momentum error / scale = "
        f"{s['worst_momentum_error']:.3g}")
    names = list(st.STATUS_NAMES.values())
    log(f"{'category':<16}{'rows':>10}" + "".join(f"{k:>17}" for k in names))
    for cat, c in s["by_category"].items():
        log(f"{cat:<16}{c['rows']:>10,}" + "".join(f"{c[k]:>17,}" for k in names))
    log("checks (each must be 0):")
    for name, count in s["failures"].items():
        log(f"  {name:<24}{count:>8}  {'ok' if count == 0 else 'FAIL'}")
        for ex in s["examples"][name]:
            log(f"    row {ex['row']} status {ex['status']} inputs {ex['inputs']}")
    if s["max_steps_row"] is not None:
        log(f"row with the most RK4 steps: {s['max_steps_row']}")
    log("PASS" if s["passed"] else "FAIL")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1_000_000, help="rows to run")
    parser.add_argument("--chunk", type=int, default=50_000, help="rows per solve_batch call")
    parser.add_argument("--seed", type=int, default=20260601)
    parser.add_argument("--timeout", type=float, default=120.0,
                        help="watchdog: wall-clock seconds allowed per chunk")
    args = parser.parse_args(argv)
    summary = fuzz(args.n, args.chunk, args.seed, args.timeout)
    report(summary)
    # With ``python -m validation --results DIR``: the figures the docs quote (python -m
    # benchmarks render); the examples and the row with the most steps stay in the log.
    harness.record("fuzz_kernel", {
        "passed": summary["passed"], "rows": summary["rows"],
        "by_status": summary["by_status"], "failures": summary["failures"],
        "crashes": summary["crashes"], "hung_chunks": summary["hung_chunks"],
        "mean_steps_ok": summary["mean_steps_ok"], "max_steps": summary["max_steps"],
        "worst_energy_gain": summary["worst_energy_gain"],
        "worst_momentum_error": summary["worst_momentum_error"],
        "wall_s": summary["wall_seconds"], "kernel_s": summary["kernel_seconds"]},
        {"n": args.n, "chunk": args.chunk, "seed": args.seed, "timeout_s": args.timeout,
         "steps": DEFAULT_STEPS, "tolerance": DEFAULT_TOLERANCE,
         "max_steps": DEFAULT_MAX_STEPS})
    return 0 if summary["passed"] else 1


if __name__ == "__main__":
    sys.exit(main())
