"""The whole benchmark suite in one command; prints the machine and every metric.

Run:  .venv/bin/python -m benchmarks [--results DIR] overview [--quick]

Metrics (medians of several runs; targets in brackets):
  * kernel impacts/s on the studies/throughput.toml mix, 1 and 2 threads   [>= 1,000,000 at 2]
  * parallel efficiency, 2 threads against 1                               [>= 90 %]
  * end-to-end `mcbat run` rows/s at 2,000,000 samples, 2 threads          [>= 500,000]
  * accuracy of the default settings against the scipy reference integrator
    on a random subset of the mix (max and median relative error)          [max <= 1e-8]
  * speed-up over the reference integrator, per impact, in the same run    [>= 10,000x]
  * cold (empty numba cache) and warm start of `mcbat impact`, wall time    [warm <= 1.5 s]
  * peak memory of a 10,000,000-row scan                                   [<= 2 GB]

``--quick`` runs smaller sizes (for a smoke test); the figures in
docs/accuracy-and-speed.md come from the full run.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import harness

ROOT = Path(__file__).resolve().parents[1]
THROUGHPUT = ROOT / "studies" / "throughput.toml"
EXAMPLE_CASE = ROOT / "examples" / "cabo2012_sec5.json"
#: python -m benchmarks --quick overview
QUICK_ARGS = ["--quick"]


def kernel_throughput(n, repeats):
    """Impacts/s of the batch kernel on the throughput mix, at 1 and 2 threads."""
    import numba

    from mcbat.core.batch import INPUT_FIELDS, allocate_outputs, solve_batch
    from mcbat.study import load_study

    study = load_study(THROUGHPUT)
    cols = study.sample(0, n)
    inputs = np.stack([cols[name] for name in INPUT_FIELDS])
    solver = study.solver
    args = (solver["steps"], solver["tolerance"], solver["max_steps"])
    solve_batch(inputs[:, :64].copy(), *args, *allocate_outputs(64))  # load the kernel
    out = allocate_outputs(n)
    rates = {}
    for threads in (1, 2):
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
        times = []
        for _ in range(repeats):
            t0 = time.perf_counter()
            solve_batch(inputs, *args, *out)
            times.append(time.perf_counter() - t0)
        rates[threads] = n / float(np.median(times))
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    return rates, inputs, out


def accuracy_and_speedup(inputs, out, n_cases, seed=7):
    """Kernel against the scipy reference on a random subset of the mix."""
    from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS
    from mcbat.core.cabo2012.contact import DEFAULT_ACCURACY
    from mcbat.core.cabo2012.impact import ImpactInputs, solve_impact
    from mcbat.core.geometry import contact_frame
    from mcbat.core.rigid_bodies import relative_contact_velocity
    from mcbat.testing.cabo2012_reference import reference_impact

    f = {name: i for i, name in enumerate(INPUT_FIELDS)}
    o = {name: i for i, name in enumerate(OUTPUT_FIELDS)}
    status = out[1]
    rng = np.random.default_rng(seed)
    rows = rng.choice(np.flatnonzero(status == 0), size=n_cases, replace=False)
    errors, t_ref, t_kernel = [], 0.0, 0.0
    for i in rows:
        x = inputs[:, i]
        def vec(p, x=x):
            return tuple(float(x[f[f"{p}{c}_in"]]) for c in "xyz")

        t0 = time.perf_counter()
        ref = reference_impact(
            x[f["ball_mass"]], x[f["ball_radius"]], x[f["ball_inertia_factor"]],
            x[f["bat_mass"]], x[f["bat_transverse_inertia"]], x[f["bat_axial_inertia"]],
            axial=x[f["axial"]], angle=x[f["angle"]], radius=x[f["bat_radius"]],
            slope=x[f["bat_slope"]], ball_v=vec("ball_v"), ball_w=vec("ball_w"),
            bat_v=vec("bat_v"), bat_w=vec("bat_w"), mu=x[f["mu"]], e=x[f["e"]])
        t_ref += time.perf_counter() - t0
        t0 = time.perf_counter()
        solve_impact(ImpactInputs(*[float(v) for v in x]), DEFAULT_ACCURACY)
        t_kernel += time.perf_counter() - t0
        t1, t2, t3, r_c = contact_frame(x[f["axial"]], x[f["angle"]], x[f["bat_radius"]],
                                        x[f["bat_slope"]])
        v0 = np.linalg.norm(relative_contact_velocity(
            x[f["ball_radius"]], t3, r_c, vec("ball_v"), vec("ball_w"), vec("bat_v"),
            vec("bat_w")))
        mine = out[0][[o["ball_vx"], o["ball_vy"], o["ball_vz"]], i]
        errors.append(np.max(np.abs(mine - ref["ball_v"])) / v0)
    errors = np.array(errors)
    # Per impact: the reference's time against the batch kernel's (single thread) rate.
    return errors, t_ref / n_cases


def run_cli_timed(args, env=None):
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "mcbat.cli", *map(str, args)],
                          capture_output=True, text=True, env=env, check=True)
    wall = time.perf_counter() - t0
    peak = max(before, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
    return proc, wall, peak


def peak_memory_run(args):
    """Run ``mcbat ARGS`` in a fresh Python and return (wall s, peak RSS in kB).

    The peak is the child's own ``VmHWM`` (its address space's high-water mark, reset at
    exec), read by the child itself: ``ru_maxrss`` of children also counts the pages a
    forked child shares with this (large) benchmark process.
    """
    code = ("import sys\nfrom mcbat.cli import main\nrc = main(sys.argv[1:])\n"
            "hwm = [l for l in open('/proc/self/status') if l.startswith('VmHWM')][0]\n"
            "print('PEAK_KB', hwm.split()[1])\nsys.exit(rc)\n")
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True,
                          text=True, check=True)
    wall = time.perf_counter() - t0
    return wall, int(re.search(r"PEAK_KB (\d+)", proc.stdout).group(1))


def impact_start_times(repeats):
    """Cold (empty numba cache) and warm wall time of `mcbat impact` for one case."""
    cache = Path(tempfile.mkdtemp(prefix="mcbat-numba-cache-"))
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    try:
        _, cold, _ = run_cli_timed(["impact", EXAMPLE_CASE], env)
        warm = [run_cli_timed(["impact", EXAMPLE_CASE], env)[1] for _ in range(repeats)]
    finally:
        shutil.rmtree(cache, ignore_errors=True)
    return cold, float(np.median(warm))


def end_to_end(samples, repeats):
    work = Path(tempfile.mkdtemp(prefix="mcbat-bench-"))
    rates, walls, peak = [], [], 0
    try:
        for i in range(repeats):
            out = work / f"run{i}"
            proc, wall, peak_kb = run_cli_timed(["run", THROUGHPUT, "--out", out, "--samples",
                                                 samples, "--threads", 2, "--quiet"])
            rates.append(float(re.search(r"\(([\d,]+) rows/s\)", proc.stdout).group(1)
                               .replace(",", "")))
            walls.append(wall)
            peak = max(peak, peak_kb)
            shutil.rmtree(out)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return float(np.median(rates)), float(np.median(walls)), peak


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes, for a smoke test")
    args = parser.parse_args(argv)
    quick = args.quick
    n_kernel = 200_000 if quick else 2_000_000
    repeats = 2 if quick else 5
    print(f"machine: {harness.machine_line()}", flush=True)

    rates, inputs, out = kernel_throughput(n_kernel, repeats)
    efficiency = rates[2] / (2 * rates[1])
    errors, ref_per_impact = accuracy_and_speedup(inputs, out, 20 if quick else 200)
    speedup = ref_per_impact * rates[1]
    cold, warm = impact_start_times(2 if quick else 5)
    e2e_rate, e2e_wall, e2e_peak = end_to_end(200_000 if quick else 2_000_000,
                                               1 if quick else 3)
    big = 1_000_000 if quick else 10_000_000
    work = Path(tempfile.mkdtemp(prefix="mcbat-bench-big-"))
    try:
        big_wall, big_peak = peak_memory_run(["run", THROUGHPUT, "--out", work / "big",
                                              "--samples", big, "--threads", 2, "--quiet"])
    finally:
        shutil.rmtree(work, ignore_errors=True)

    rows = [
        ("kernel, 1 thread (throughput mix)", f"{rates[1]:,.0f} impacts/s", ""),
        ("kernel, 2 threads", f"{rates[2]:,.0f} impacts/s", ">= 1,000,000"),
        ("parallel efficiency, 2 vs 1 thread", f"{100 * efficiency:.1f} %", ">= 90 %"),
        (f"end-to-end mcbat run, {2_000_000 if not quick else 200_000:,} rows, 2 threads",
         f"{e2e_rate:,.0f} rows/s ({e2e_wall:.1f} s wall incl. start-up)", ">= 500,000"),
        (f"accuracy vs reference ({len(errors)} impacts), max", f"{errors.max():.2e}",
         "<= 1e-8"),
        ("accuracy vs reference, median", f"{np.median(errors):.2e}", ""),
        ("speed-up over the scipy reference, per impact",
         f"{speedup:,.0f}x ({1e3 * ref_per_impact:.1f} ms vs {1e6 / rates[1]:.2f} us)",
         ">= 10,000x"),
        ("mcbat impact, one case, cold (empty numba cache)", f"{cold:.2f} s", ""),
        ("mcbat impact, one case, warm", f"{warm:.2f} s", "<= 1.5 s"),
        (f"peak memory, {big:,}-row scan", f"{big_peak / 1024:,.0f} MB ({big_wall:.1f} s)",
         "<= 2 GB"),
    ]
    width = max(len(r[0]) for r in rows)
    vwidth = max(len(r[1]) for r in rows)
    print(f"{'metric':<{width}}  {'measured':<{vwidth}}  target")
    for name, value, target in rows:
        print(f"{name:<{width}}  {value:<{vwidth}}  {target}")
    harness.record("overview", {
        "kernel_1_thread": rates[1], "kernel_2_threads": rates[2], "efficiency": efficiency,
        "end_to_end_rows_per_s": e2e_rate, "end_to_end_wall_s": e2e_wall,
        "accuracy_max": float(errors.max()), "accuracy_median": float(np.median(errors)),
        "speedup": speedup, "reference_s_per_impact": ref_per_impact,
        "impact_cold_s": cold, "impact_warm_s": warm, "peak_memory_mb": big_peak / 1024,
        "peak_memory_wall_s": big_wall,
    }, {
        "kernel_impacts": n_kernel, "repeats": repeats, "reference_impacts": len(errors),
        "impact_repeats": 2 if quick else 5,
        "end_to_end_samples": 200_000 if quick else 2_000_000,
        "end_to_end_runs": 1 if quick else 3, "memory_scan_samples": big,
        "study": "studies/throughput.toml",
    })

if __name__ == "__main__":
    main()
