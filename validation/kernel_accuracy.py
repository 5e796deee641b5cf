"""Accuracy of the impact kernel against the scipy reference on a hard random mix.

Run:  .venv/bin/python -m validation kernel_accuracy [--n 520] [--seed S] [--cache FILE]
          [--tolerances 5e-7,5e-8,5e-9,5e-10,5e-11] [--default-only] [--json FILE]
          [--jobs 2] [--reference-check]

The mix (harness.accuracy_mix.draw_mix): bats from 5 g to 5000 kg, spins up to
3000 rad/s, mu from 0 to 1 (some exactly 0), creeping slip at |f|/mu within 3 % of 1,
slip that stops and re-slips, tapered contacts; the modes are cycled over the cases. Each
case is solved once by the scipy reference (rtol 1e-12; in --jobs processes; --cache keeps
the references in a pickle, so a rerun skips them) and by the batch kernel at every
tolerance of --tolerances (the default tolerance is always included).

Printed:
  1. per mode and overall, the largest error of each column at the default tolerance, the
     target and pass/fail (columns: harness.accuracy_mix, module docstring;
     velocity relative to |v_ball_out - v_ball_in|, I_s relative, works and C relative to
     E_in), with the number of cases over the target and the worst cases;
  2. monotone convergence: per column, the (case, tolerance pair) violations, i.e.
     err(T/10) > 2 err(T) with err(T/10) > 1e-13, over consecutive tolerances (with
     --reference-check, also how many remain when each error may be off by the reference's
     own resolution in that case), then each violation with its errors over their
     tolerances relative to the case's median of that ratio (a value far below 1 at T
     says that the error nearly cancelled at T);
  3. per tolerance, the largest error per column, the mean RK4 steps per impact and the
     kernel time;
  4. with --reference-check, how far the references move when re-solved with rtol 1e-13
     and, separately, with its integration in I handing over to the slip-scaled time tau
     at 1e-12 |v(0)| instead of 1e-10 |v(0)|, in the same units: the resolution of the
     instrument itself;
  5. wall times (references, kernel compile, kernel runs).
NaN errors (the column does not apply, e.g. I_s when slip never stops in either solver)
are skipped; inf means the kernel failed or only one solver has a value.
"""

import argparse
import functools
import hashlib
import inspect
import json
import math
import multiprocessing
import pickle
import sys
import time
from pathlib import Path

import numpy as np

import harness
from harness import accuracy_mix, impact_mix
from harness.accuracy_mix import (
    DEFAULT_SEED,
    ERROR_COLUMNS,
    MODES,
    MONOTONE_FACTOR,
    MONOTONE_FLOOR,
    TARGETS,
    draw_mix,
    kernel_errors,
    monotone_violations,
    output_errors,
    reference_for,
    run_kernel,
)
from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS
from mcbat.core.cabo2012.contact import DEFAULT_TOLERANCE
from mcbat.testing import cabo2012_reference, reference_parts

DEFAULT_TOLERANCES = (5e-7, 5e-8, 5e-9, 5e-10, 5e-11)
DEFAULT_REFERENCE = (1e-12, None)
"""(rtol, slip_stop_fraction) of the references: reference_for's defaults."""
CHECK_REFERENCES = ((1e-13, None), (1e-12, 1e-12))
"""--reference-check: each knob of the reference tightened in turn (DOP853 tolerance; the
slip speed, relative to |v(0)|, at which the integration in I hands over to tau)."""
SHORT = dict(velocity="velocity", stick_impulse="I_s", normal_work="W_n",
             friction_work="W_fr", stick_criterion="C")
WORST_SHOWN = 3  # worst cases listed per column


def _fingerprint(cases):
    """Hash of the cases' inputs and of the reference's source: a cache of references
    belongs to exactly these cases, solved by exactly this reference."""
    values = np.array([[c[name] for name in INPUT_FIELDS] for c in cases], dtype=np.float64)
    digest = hashlib.sha256(values.tobytes())
    for module in (cabo2012_reference, reference_parts, impact_mix, accuracy_mix):
        digest.update(inspect.getsource(module).encode())
    return digest.hexdigest()


def compute_references(cases, jobs, settings=DEFAULT_REFERENCE):
    """References of all cases at ``settings = (rtol, slip_stop_fraction)``, in ``jobs``
    processes, with progress on stderr."""
    rtol, stop = settings
    refs = []
    t0 = time.perf_counter()
    step = max(1, len(cases) // 10)
    solve = functools.partial(reference_for, rtol=rtol, slip_stop_fraction=stop)
    label = f"rtol {rtol:g}" + ("" if stop is None else f", slip stop {stop:g}")
    # spawn: the workers need only scipy, never a fork of a process that runs numba threads.
    with multiprocessing.get_context("spawn").Pool(jobs) as pool:
        for i, ref in enumerate(pool.imap(solve, cases, chunksize=4), start=1):
            refs.append(ref)
            if i % step == 0 or i == len(cases):
                print(f"  references ({label}) {i}/{len(cases)}  "
                      f"{time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
    return refs


def load_or_compute_references(cases, seed, cache, jobs, settings=DEFAULT_REFERENCE):
    """References at ``settings`` from the cache when it holds them for these very cases,
    else computed (and added to the cache). Returns ``(refs, seconds, cached)``."""
    key = _fingerprint(cases)
    stored = dict(fingerprint=key, n=len(cases), seed=seed, refs={})
    if cache is not None and Path(cache).exists():
        with open(cache, "rb") as fh:
            previous = pickle.load(fh)
        if previous.get("fingerprint") == key:
            stored = previous
        else:
            print(f"cache {cache} holds other cases or another reference: recomputing",
                  file=sys.stderr)
    if settings in stored["refs"]:
        return stored["refs"][settings], 0.0, True
    t0 = time.perf_counter()
    stored["refs"][settings] = compute_references(cases, jobs, settings)
    seconds = time.perf_counter() - t0
    if cache is not None:
        with open(cache, "wb") as fh:
            pickle.dump(stored, fh)
    return stored["refs"][settings], seconds, False


def reference_resolution(cases, refs, others):
    """Per case and column, how far the references move under tighter settings (the
    largest over ``others``), in the error units: what the instrument cannot resolve."""
    resolution = {}
    for other in others:
        out, status = references_as_outputs(other)
        moved = output_errors(cases, refs, out, status)
        for col in ERROR_COLUMNS:
            resolution[col] = np.fmax(resolution.get(col, np.zeros(len(cases))),
                                      np.nan_to_num(moved[col]))
    return resolution


def references_as_outputs(refs):
    """References packed like kernel outputs (rows of ``OUTPUT_FIELDS``), so that
    ``output_errors`` can compare two references."""
    out = np.full((len(OUTPUT_FIELDS), len(refs)), np.nan)
    row = {name: i for i, name in enumerate(OUTPUT_FIELDS)}
    for i, r in enumerate(refs):
        for j, axis in enumerate("xyz"):
            out[row[f"ball_v{axis}"], i] = r["ball_v"][j]
            out[row[f"ball_w{axis}"], i] = r["ball_w"][j]
        out[row["stick_impulse"], i] = r["stick_impulse"]
        out[row["normal_work"], i] = r["normal_work"]
        out[row["friction_work"], i] = r["friction_work"]
        out[row["stick_criterion"], i] = -r["normal_work_at_stick"]
    return out, np.where([r["status"] == "ok" for r in refs], 0, 2)


def _max(values):
    """Largest value that applies (NaN skipped); NaN if none does."""
    values = np.asarray(values, dtype=float)
    values = values[~np.isnan(values)]
    return float(values.max()) if values.size else math.nan


def _fmt(x):
    if isinstance(x, float) and math.isnan(x):
        return "-"
    return f"{x:.1e}"


def default_table(cases, refs, errors):
    """Section 1: max error per mode and column at the default tolerance."""
    modes = np.array([c["mode"] for c in cases])
    width = 11
    head = f"{'mode':<10} {'n':>4} " + " ".join(f"{SHORT[c]:>{width}}" for c in ERROR_COLUMNS)
    lines = [head]
    summary = {}
    for mode in (*MODES, "all"):
        mask = np.ones(len(cases), bool) if mode == "all" else modes == mode
        maxima = {col: _max(errors[col][mask]) for col in ERROR_COLUMNS}
        summary[mode] = dict(n=int(mask.sum()), **maxima)
        lines.append(f"{mode:<10} {int(mask.sum()):>4} "
                     + " ".join(f"{_fmt(maxima[c]):>{width}}" for c in ERROR_COLUMNS))
    lines.append(f"{'target':<10} {'':>4} "
                 + " ".join(f"{_fmt(TARGETS[c]):>{width}}" for c in ERROR_COLUMNS))
    passed = {c: bool(summary["all"][c] <= TARGETS[c]) for c in ERROR_COLUMNS}
    lines.append(f"{'pass':<10} {'':>4} "
                 + " ".join(f"{'yes' if passed[c] else 'NO':>{width}}" for c in ERROR_COLUMNS))
    over = {c: int(np.sum(errors[c] > TARGETS[c])) for c in ERROR_COLUMNS}
    applies = {c: int(np.sum(~np.isnan(errors[c]))) for c in ERROR_COLUMNS}
    lines.append(f"{'over':<10} {'':>4} "
                 + " ".join(f"{over[c]:>{width}}" for c in ERROR_COLUMNS))
    lines.append(f"{'measured':<10} {'':>4} "
                 + " ".join(f"{applies[c]:>{width}}" for c in ERROR_COLUMNS))
    lines.append("(over: cases above the target; measured: cases where the column applies)")
    lines.append("worst cases (index mode/slip: error; reference phases):")
    for col in ERROR_COLUMNS:
        values = np.where(np.isnan(errors[col]), -1.0, errors[col])
        worst = [i for i in np.argsort(-values, kind="stable")[:WORST_SHOWN] if values[i] > 0]
        shown = "; ".join(
            f"{i} {cases[i]['mode']}/{cases[i]['slip']}: {_fmt(float(errors[col][i]))} "
            f"{'+'.join(refs[i]['phases'])}" for i in worst)
        lines.append(f"  {SHORT[col]:<9} {shown}")
    return "\n".join(lines), summary, passed, over


def monotone_table(tolerances, runs, resolution=None):
    """Section 2: violations of monotone convergence per column and tolerance pair; with a
    per-case ``resolution`` of the references, also the violations that stay violations
    when each error may be off by it (err(T/10) - res > 2 (err(T) + res))."""
    width = 11
    lines = [f"{'T -> T/10':<18} " + " ".join(f"{SHORT[c]:>{width}}" for c in ERROR_COLUMNS)]
    totals = dict.fromkeys(ERROR_COLUMNS, 0)
    resolved = dict.fromkeys(ERROR_COLUMNS, 0)
    violating_cases = set()
    pairs = []
    for coarse, fine in zip(tolerances[:-1], tolerances[1:]):
        counts = {}
        violations = monotone_violations(runs[coarse], runs[fine])
        for col in ERROR_COLUMNS:
            bad = violations[col]
            counts[col] = int(bad.sum())
            totals[col] += counts[col]
            violating_cases.update(np.flatnonzero(bad).tolist())
            if resolution is not None:
                res = resolution[col]
                resolved[col] += int(np.sum(bad & (runs[fine][col] - res
                                                   > MONOTONE_FACTOR * (runs[coarse][col] + res))))
        pairs.append(dict(coarse=coarse, fine=fine, **counts))
        lines.append(f"{f'{coarse:.0e} -> {fine:.0e}':<18} "
                     + " ".join(f"{counts[c]:>{width}}" for c in ERROR_COLUMNS))
    lines.append(f"{'total':<18} " + " ".join(f"{totals[c]:>{width}}" for c in ERROR_COLUMNS))
    if resolution is not None:
        lines.append(f"{'beyond ref. res.':<18} "
                     + " ".join(f"{resolved[c]:>{width}}" for c in ERROR_COLUMNS))
    lines.append(f"cases with a violation: {len(violating_cases)}")
    listed = _violation_list(tolerances, runs)
    if listed:
        lines.append("each violation; 'at T' and 'at T/10' are err/tolerance over the median of "
                     "err/tolerance over the case's tolerances (far below 1 at T: the error "
                     "nearly cancelled there, i.e. changed sign between tolerances):")
        lines.extend(f"  case {v['case']:5d} {SHORT[v['column']]:<5} {v['coarse']:.0e} -> "
                     f"{v['fine']:.0e}  err {v['err_coarse']:.1e} -> {v['err_fine']:.1e}  "
                     f"at T {v['scaled_coarse']:.3f}  at T/10 {v['scaled_fine']:.2f}"
                     for v in listed)
    summary = dict(pairs=pairs, totals=totals, violating_cases=sorted(violating_cases),
                   violations=listed,
                   beyond_reference_resolution=resolved if resolution is not None else None)
    return "\n".join(lines), summary


def _violation_list(tolerances, runs):
    """Every (case, column, tolerance pair) that violates monotone convergence, with each
    error over its tolerance, relative to the case's median of that ratio."""
    listed = []
    tols = np.asarray(tolerances, dtype=float)
    for col in ERROR_COLUMNS:
        scaled = np.array([runs[t][col] for t in tolerances]) / tols[:, None]
        for j, (coarse, fine) in enumerate(zip(tolerances[:-1], tolerances[1:])):
            for i in np.flatnonzero(monotone_violations(runs[coarse], runs[fine])[col]):
                median = float(np.nanmedian(scaled[:, i]))
                listed.append(dict(case=int(i), column=col, coarse=coarse, fine=fine,
                                   err_coarse=float(runs[coarse][col][i]),
                                   err_fine=float(runs[fine][col][i]),
                                   scaled_coarse=float(scaled[j, i]) / median,
                                   scaled_fine=float(scaled[j + 1, i]) / median))
    return listed


def tolerance_table(tolerances, runs, seconds):
    """Section 3: per tolerance, max error per column, mean steps and kernel time."""
    width = 11
    lines = [f"{'tolerance':<10} " + " ".join(f"{SHORT[c]:>{width}}" for c in ERROR_COLUMNS)
             + f" {'steps':>7} {'fail':>5} {'time s':>7}"]
    rows = []
    for tol in tolerances:
        maxima = {col: _max(runs[tol][col]) for col in ERROR_COLUMNS}
        steps = float(np.mean(runs[tol]["rk4_steps"]))
        failed = int(np.sum(runs[tol]["status"] != 0))
        rows.append(dict(tolerance=tol, mean_rk4_steps=steps, kernel_failures=failed,
                         kernel_seconds=seconds[tol], **maxima))
        lines.append(f"{tol:<10.0e} " + " ".join(f"{_fmt(maxima[c]):>{width}}"
                                                 for c in ERROR_COLUMNS)
                     + f" {steps:>7.1f} {failed:>5} {seconds[tol]:>7.3f}")
    return "\n".join(lines), rows


def _plain(x):
    """JSON-safe copy: NaN (not applicable) becomes null, inf the string "inf"."""
    if isinstance(x, dict):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, float) and not math.isfinite(x):
        return None if math.isnan(x) else ("inf" if x > 0 else "-inf")
    return x


def _parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=520)
    parser.add_argument("--seed", type=int, default=DEFAULT_SEED)
    parser.add_argument("--cache", metavar="FILE", help="pickle of the references")
    parser.add_argument("--tolerances", default=",".join(f"{t:g}" for t in DEFAULT_TOLERANCES),
                        help="comma-separated kernel tolerances (the default is added)")
    parser.add_argument("--default-only", action="store_true",
                        help=f"run only the default tolerance {DEFAULT_TOLERANCE:g}")
    parser.add_argument("--json", metavar="FILE", help="also write the figures as JSON")
    parser.add_argument("--jobs", type=int, default=2, help="processes for the references")
    parser.add_argument("--reference-check", action="store_true",
                        help="also solve the references with each knob tightened "
                        "(CHECK_REFERENCES) and print how far they move: the instrument's "
                        "own resolution")
    return parser.parse_args(argv)


def _print_header(args, cases, refs, cached):
    failed_refs = [(i, r["message"]) for i, r in enumerate(refs) if r["status"] != "ok"]
    phases = {}
    for r in refs:
        key = "+".join(r["phases"]) if r["status"] == "ok" else r["status"]
        phases[key] = phases.get(key, 0) + 1
    print(f"accuracy mix: n = {args.n}, seed = {args.seed}; references: "
          f"{args.n - len(failed_refs)} ok, {len(failed_refs)} failed"
          + (f" (from {args.cache})" if cached else ""))
    print("reference phases: " + ", ".join(f"{k} {v}" for k, v in sorted(phases.items())))
    for i, message in failed_refs:
        print(f"  reference failed on case {i} ({cases[i]['mode']}/{cases[i]['slip']}): "
              f"{message}")
    return failed_refs, phases


def main(argv=None):
    args = _parse_args(argv)
    t_start = time.perf_counter()
    tolerances = [DEFAULT_TOLERANCE]
    if not args.default_only:
        tolerances = sorted({float(t) for t in args.tolerances.split(",")} | {DEFAULT_TOLERANCE},
                            reverse=True)

    cases = draw_mix(args.n, args.seed)
    refs, ref_seconds, cached = load_or_compute_references(cases, args.seed, args.cache,
                                                           args.jobs)
    resolution, check_seconds = None, 0.0
    if args.reference_check:
        others = []
        for settings in CHECK_REFERENCES:
            other, seconds, _ = load_or_compute_references(cases, args.seed, args.cache,
                                                           args.jobs, settings)
            others.append(other)
            check_seconds += seconds
        resolution = reference_resolution(cases, refs, others)

    t0 = time.perf_counter()
    run_kernel(cases[:8], DEFAULT_TOLERANCE)  # compile or load the kernel outside the timing
    compile_seconds = time.perf_counter() - t0
    runs, seconds = {}, {}
    for tol in tolerances:
        t0 = time.perf_counter()
        runs[tol] = kernel_errors(cases, refs, tol)
        seconds[tol] = time.perf_counter() - t0
        print(f"  kernel at tolerance {tol:.0e}: {seconds[tol]:.2f} s", file=sys.stderr,
              flush=True)

    failed_refs, phases = _print_header(args, cases, refs, cached)
    text, summary, passed, over = default_table(cases, refs, runs[DEFAULT_TOLERANCE])
    print(f"\n1. max error at the default tolerance {DEFAULT_TOLERANCE:.0e} "
          f"(velocity / |dv_ball|, I_s relative, W_n, W_fr, C / E_in)")
    print(text)
    print(f"accuracy targets: {'met' if all(passed.values()) else 'NOT met'}")

    monotone = None
    if len(tolerances) > 1:
        text, monotone = monotone_table(tolerances, runs, resolution)
        print(f"\n2. monotone convergence: violations err(T/10) > {MONOTONE_FACTOR:g} err(T) "
              f"with err(T/10) > {MONOTONE_FLOOR:g}")
        print(text)
        print("monotone convergence: "
              + ("met" if not any(monotone["totals"].values()) else "NOT met"))

    text, rows = tolerance_table(tolerances, runs, seconds)
    print("\n3. per tolerance: max error per column, mean RK4 steps per impact, kernel "
          "failures, kernel time")
    print(text)

    resolution_max = None
    if resolution is not None:
        resolution_max = {col: float(resolution[col].max()) for col in ERROR_COLUMNS}
        print("\n4. reference resolution: max change of the references, in the error units, "
              "when re-solved with " + " and with ".join(
                  f"rtol {r:g}" + ("" if f is None else f", slip stop {f:g}")
                  for r, f in CHECK_REFERENCES))
        print(" ".join(f"{SHORT[c]} {_fmt(resolution_max[c])}" for c in ERROR_COLUMNS))

    wall = time.perf_counter() - t_start
    print(f"\n5. wall time {wall:.1f} s: references "
          + ("cached" if cached else f"{ref_seconds:.1f} s ({args.jobs} processes)")
          + (f", reference check {check_seconds:.1f} s" if args.reference_check else "")
          + f", kernel compile/load {compile_seconds:.1f} s, kernel runs "
          f"{sum(seconds.values()):.2f} s")

    # With ``python -m validation --results DIR``: the figures the docs' accuracy tables
    # are rendered from (python -m benchmarks render).
    harness.record("accuracy_mix", _plain(dict(
        by_mode=summary, passed=passed, over_target=over, per_tolerance=rows,
        monotone_totals=monotone["totals"] if monotone else None,
        monotone_cases=len(monotone["violating_cases"]) if monotone else None,
        reference_failures=len(failed_refs), wall_s=wall)),
        _plain(dict(n=args.n, seed=args.seed, default_tolerance=DEFAULT_TOLERANCE,
                    tolerances=tolerances, targets=TARGETS,
                    reference="scipy DOP853, rtol 1e-12", jobs=args.jobs,
                    references_cached=cached)))

    if args.json:
        Path(args.json).write_text(json.dumps(_plain(dict(
            n=args.n, seed=args.seed, default_tolerance=DEFAULT_TOLERANCE,
            tolerances=tolerances, targets=TARGETS, reference_failures=failed_refs,
            reference_phases=phases, default=summary, passed=passed, over_target=over,
            monotone=monotone, per_tolerance=rows, reference_resolution=resolution_max,
            seconds=dict(wall=wall, references=ref_seconds, references_cached=cached,
                         reference_check=check_seconds,
                         kernel_compile=compile_seconds,
                         kernel={f"{t:g}": s for t, s in seconds.items()}),
        )), indent=1, allow_nan=False) + "\n")


if __name__ == "__main__":
    main()
