"""Every table of measured figures in the docs, rendered from one results directory (the
JSON files of ``python -m benchmarks --results DIR ...`` and ``python -m validation
--results DIR ...``).

    python -m benchmarks render [--results DIR]    # rewrite the tables (default DIR:
                                                   # benchmarks/results, the committed set)
    python -m benchmarks render --check            # exit 1 if a table differs

Each table sits between ``<!-- begin generated: NAME -->`` and
``<!-- end generated: NAME -->`` (:data:`BLOCKS` says which file holds which); nothing
outside the markers is touched. A row appears when its run's result is in the directory,
and every verdict on a target is computed here from the figures.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import harness

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"

def sig(x: float, digits: int = 3) -> str:
    """``x`` to ``digits`` significant figures, with thousands separators: 1,234,567 ->
    '1,230,000'; 0.67 -> '0.67'."""
    if x == 0:
        return "0"
    rounded = float(f"{x:.{digits}g}")
    return f"{rounded:,.0f}" if abs(rounded) >= 10 ** (digits - 1) else f"{rounded:g}"


def sci(x: float, digits: int = 1) -> str:
    """Scientific notation without padded exponents: 9.5e-9, 3.8e-11, 1e-8."""
    text = f"{x:.{digits}e}" if digits else f"{x:.0e}"
    mantissa, exponent = text.split("e")
    return f"{mantissa}e{int(exponent)}"


def verdict(target: str, ok: bool | dict[str, bool] | None) -> str:
    """A target with its verdict, computed from the measured figures (never typed); ``ok``
    is one bool, or ``{part: bool}`` for a target of several parts (the parts not met are
    named)."""
    if ok is None:
        return target
    if isinstance(ok, dict):
        missed = [part for part, met in ok.items() if not met]
        return (f"{target}: met" if not missed
                else f"{target}: **not met** ({', '.join(missed)})")
    return f"{target}: met" if ok else f"{target}: **not met**"


def power_of_ten(n: int) -> str:
    """10^9 for 1,000,000,000; other counts with thousands separators."""
    k = len(str(n)) - 1
    return f"10^{k}" if n == 10 ** k and k >= 4 else f"{n:,}"


def _overview(r):
    m, s = r["metrics"], r["settings"]
    return [
        (f"kernel, 1 thread, `{s['study']}` mix, {s['kernel_impacts']:,} impacts",
         f"{sig(m['kernel_1_thread'])} impacts/s", "—", None),
        ("kernel, 2 threads, same mix", f"**{sig(m['kernel_2_threads'])} impacts/s**",
         "≥ 1,200,000", m["kernel_2_threads"] >= 1.2e6),
        ("parallel efficiency, 2 threads against 1", f"{100 * m['efficiency']:.1f} %",
         "≥ 90 %", m["efficiency"] >= 0.9),
        (f"accuracy against the scipy reference, {s['reference_impacts']} impacts of the mix",
         f"{sci(m['accuracy_max'])} max, {sci(m['accuracy_median'])} median", "≤ 1e-8",
         m["accuracy_max"] <= 1e-8),
        ("speed-up over the scipy reference, per impact (1 thread)",
         f"{sig(m['speedup'])}x ({1e3 * m['reference_s_per_impact']:.1f} ms against "
         f"{1e6 / m['kernel_1_thread']:.2f} µs)", "≥ 10,000x", m["speedup"] >= 1e4),
        (f"end-to-end `mcbat run {s['study']}`, {s['end_to_end_samples']:,} rows, 2 threads "
         f"(median of {s['end_to_end_runs']})",
         f"**{sig(m['end_to_end_rows_per_s'])} rows/s** ({m['end_to_end_wall_s']:.1f} s for "
         "the whole process incl. start-up)", "≥ 500,000",
         m["end_to_end_rows_per_s"] >= 5e5),
        ("`mcbat impact`, one case, warm / cold numba cache",
         f"{m['impact_warm_s']:.2f} s / {m['impact_cold_s']:.1f} s", "warm ≤ 1.5 s",
         m["impact_warm_s"] <= 1.5),
        (f"peak memory of a {s['memory_scan_samples']:,}-row scan",
         f"{sig(m['peak_memory_mb'])} MB ({m['peak_memory_wall_s']:.1f} s)", "≤ 2 GB",
         m["peak_memory_mb"] <= 2048),
    ]


def _kernel(r):
    m, s = r["metrics"], r["settings"]
    return [(f"kernel, {s['threads']} thread, uniform random mix of the Sec. V bodies, "
             f"{s['impacts']:,} impacts", f"{sig(m['impacts_per_s'])} impacts/s "
             f"({m['steps_mean']:.1f} steps an impact)", "—", None)]


def _run(r):
    m, s = r["metrics"], r["settings"]
    return [(f"`mcbat run {s['study']}`, {s['samples']:,} samples, {s['threads']} threads "
             f"(median of {s['repeats']})",
             f"{sig(m['rows_per_s'])} rows/s within the run; whole process "
             f"{m['process_wall_s']:.2f} s; peak {sig(m['peak_memory_mb'])} MB", "—", None)]


def _flight(r):
    m, s = r["metrics"], r["settings"]
    return [(f"flight kernel alone: `fly_batch`, {s['launches']:,} random launches "
             f"({s['launch_ranges'].removesuffix(', seed 1')}), {s['threads']} threads",
             f"**{sig(m['flights_per_s'])} flights/s** ({m['steps_mean']:.1f} steps a "
             "flight)", "≥ 700,000", m["flights_per_s"] >= 7e5)]


def _game(r):
    m, s = r["metrics"], r["settings"]
    return [(f"game kernel against the bat-frame kernel, `{s['study']}`, {s['rows']:,} rows, "
             f"{s['threads']} threads",
             f"{sig(m['game_kernel_rows_per_s'])} against "
             f"{sig(m['bat_frame_kernel_rows_per_s'])} rows/s: the field <-> bat-frame "
             f"transform {m['transform_ns_per_row']:,.0f} ns a row "
             f"({100 * m['transform_fraction']:.1f} % of the kernel)", "—", None)]


def _statcast(r):
    m, s = r["metrics"], r["settings"]
    return [(f"Statcast reader, `mcbat.statcast.read`, {s['rows']:,} rows "
             f"({s['megabytes']:.1f} MB)", f"{sig(m['rows_per_s'])} rows/s", "—", None)]


def _population(r):
    m, s = r["metrics"], r["settings"]
    return [(f"population fit (`mcbat fit --population`), {s['rows']} rows, "
             f"{len(s['free'])} free parameters, {len(s.get('observables', [0, 0]))} "
             f"observables, {m['draws']:,} template draws, engine {s['engine']}, "
             f"{s['threads']} threads (median of {s['repeats']})",
             f"{m['wall_s']:.1f} s wall, {m['cpu_s']:.1f} s CPU",
             "< 5 min (2 cores)", m["wall_s"] < 300)]


def injection_table(results: dict) -> str:
    """The population fit's injection check, one table of every recorded table size."""
    runs = sorted((r for name, r in results.items()
                   if name.startswith("population_injection_")),
                  key=lambda r: r["settings"]["rows"], reverse=True)
    if not runs:
        return "No results."
    lines = ["| tables × rows | parameter (truth) | mean pull | pull sd | coverage | "
             "verdict |", "|---|---|---|---|---|---|"]
    for r in runs:
        s = r["settings"]
        for name, p in r["metrics"]["parameters"].items():
            lines.append(f"| {s['tables']} × {s['rows']} | `{name}` ({p['truth']:g}) | "
                         f"{p['mean_pull']:+.2f} ± {p['mean_pull_se']:.2f} | "
                         f"{p['pull_sd']:.2f} | {100 * p['coverage']:.1f} % | "
                         f"{'met' if p['holds'] else '**not met**'} |")
    lines += ["", "Criterion: mean pull within ±0.2, pull sd 0.8-1.2, coverage 68 ± 5 % "
              "(a table without an interval counts as not covering). Goodness of fit: "
              + "; ".join(f"{r['settings']['rows']} rows, p-values' mean "
                          f"{r['metrics']['p_value_mean']:.2f} (0.5 expected), "
                          f"{100 * r['metrics']['p_below_005']:.1f} % below 0.05"
                          for r in runs) + "."]
    lines += [f"- {_command_line(r)}" for r in runs]
    return "\n".join(lines)


def population_table(results: dict) -> str:
    return _table([("population_timing", _population)], results)


def _inference(r):
    m, s = r["metrics"], r["settings"]
    stages = "read + infer + fly" if s["fly"] else "read + infer"
    return [(f"spin inference, {stages}: a Parquet table of {s['balls']:,} simulated balls "
             f"in play, {s['threads']} threads (median of {s['runs']})",
             f"{sig(m['balls_per_s'])} balls/s ({sig(m['balls_per_cpu_s'])} per CPU-second; "
             f"{m['iterations_mean']:.1f} Newton iterations a ball)", "—", None)]


#: The rows each benchmark contributes to the speed table, in this order.
ROWS = {"overview": _overview, "kernel": _kernel, "run": _run, "flight": _flight,
        "game": _game, "inference": _inference, "statcast": _statcast}


# --- long runs: whole processes at full size --------------------------------------------

def _long_dask(r):
    m, s = r["metrics"], r["settings"]
    ratio = m["dask_over_local"]
    return [(f"`mcbat run` of `{s['study']}` with `--engine dask --workers {s['workers']}` "
             "(LocalCluster, 1 numba thread per worker) against the local engine, "
             f"{s['samples']:,} samples (medians of {s['repeats']})",
             f"**{100 * ratio:.1f} %** of the local engine's rows/s "
             f"({sig(m['dask_rows_per_s'])} against {sig(m['local_rows_per_s'])} rows/s); "
             f"whole process {m['dask_process_wall_s']:.1f} s against "
             f"{m['local_process_wall_s']:.1f} s incl. cluster start-up "
             f"({100 * m['local_process_wall_s'] / m['dask_process_wall_s']:.0f} %)",
             "≥ 80 %", ratio >= 0.8)]


def _long_game(r):
    m, s = r["metrics"], r["settings"]
    if "run_rows_per_s" not in m:
        return []
    game, bat = m["run_rows_per_s"]["game_fastball"], m["run_rows_per_s"]["throughput"]
    share = m["transform_share_of_run"]
    return [(f"game study: `mcbat run {s['study']}`, {s['rows']:,} samples, 2 threads, "
             f"against `studies/throughput.toml` (medians of {s['runs']} interleaved runs)",
             f"**{sig(game)} rows/s** against {sig(bat)}; the field <-> bat-frame transform "
             f"is **{100 * share:.1f} %** of the game run "
             f"({m['transform_ns_per_row']:.0f} ns of {1e9 / game:,.0f} ns per row; the game "
             f"kernel {sig(m['game_kernel_rows_per_s'])} rows/s, the bat-frame kernel "
             f"{sig(m['bat_frame_kernel_rows_per_s'])})", "transform ≤ 10 %", share <= 0.10)]


def _long_flight(r):
    m, s = r["metrics"], r["settings"]
    if "game_run_rows_per_s" not in m:
        return []
    rate = m["game_run_rows_per_s"]
    return [("game study with flight: `mcbat run studies/game_fastball.toml` (its `[flight]` "
             f"section), {s['run_samples']:,} samples, 2 threads (median of {s['runs']})",
             f"**{sig(rate)} rows/s**", "≥ 300,000", rate >= 3e5)]


def _long_pipeline(r):
    m, s = r["metrics"], r["settings"]
    n, rows = s["samples"], []
    kernel = m["kernel_impacts_per_s"]
    if "all_columns" in m:
        a = m["all_columns"]
        process = n / a["process_wall_s"]
        rows.append((f"`mcbat run {s['study']}`, every column, {n:,} samples, "
                     f"{s['threads']} threads (medians of {s['repeats']}; the kernel alone, "
                     f"measured at the start of each round, {sig(kernel)} impacts/s)",
                     f"**{sig(a['rows_per_s'])} rows/s** within the run "
                     f"({100 * a['share_of_kernel']:.0f} % of the kernel in the same round); "
                     f"whole process {a['process_wall_s']:.2f} s = {sig(process)} rows/s; "
                     f"{a['bytes_on_disk'] / 1e6:,.0f} MB on disk",
                     "≥ 1,000,000 within the run, ≥ 700,000 for the process",
                     {"within the run": a["rows_per_s"] >= 1e6,
                      "the process": process >= 7e5}))
    if "12_columns" in m:
        a = m["12_columns"]
        rows.append(("the same with `--columns` of 12 columns",
                     f"**{sig(a['rows_per_s'])} rows/s** "
                     f"({100 * a['share_of_kernel']:.0f} % of the kernel); whole process "
                     f"{a['process_wall_s']:.2f} s; {a['bytes_on_disk'] / 1e6:,.0f} MB on disk",
                     "≥ 1,200,000", a["rows_per_s"] >= 1.2e6))
    if "summary_only" in m:
        a = m["summary_only"]
        rows.append(("the same with `--summary-only` (40 bins of `from_barrel_end`, 2 columns, "
                     "3 quantiles)",
                     f"**{sig(a['rows_per_s'])} rows/s**, **{100 * a['share_of_kernel']:.0f} "
                     f"%** of the kernel in the same round; whole process "
                     f"{a['process_wall_s']:.2f} s; {a['bytes_on_disk'] / 1e6:.1f} MB on disk, "
                     f"peak {sig(a['peak_memory_mb'])} MB",
                     "≥ 85 % of the kernel", a["share_of_kernel"] >= 0.85))
    return rows


#: The full-size scan the targets are stated for, and its targets.
SCAN_SAMPLES, SCAN_MINUTES, SCAN_DISK_MB, SCAN_PEAK_MB = 10 ** 9, 20, 100, 1024


def _scans(results) -> dict[int, dict]:
    """The summary-only scans of ``python -m benchmarks pipeline --scan N | --memory``, by
    sample count."""
    return dict(sorted((r["settings"]["samples"], r) for name, r in results.items()
                       if name.startswith("pipeline_scan_")))


def _long_scan(results):
    scans = _scans(results)
    if not scans:
        return []
    n, r = max(scans.items())
    m = r["metrics"]
    # A scan smaller than the target's is judged pro rata: 10^9 rows in 20 min is a whole
    # process at 10^9 / 1200 s = 833,000 rows/s; its disk and memory do not grow with N.
    needed = SCAN_SAMPLES / (60 * SCAN_MINUTES)
    process = n / m["wall_s"]
    ok = {"time": process >= needed, "disk": m["bytes_on_disk"] / 1e6 < SCAN_DISK_MB,
          "memory": m["peak_memory_mb"] < SCAN_PEAK_MB}
    target = f"< {SCAN_MINUTES} min, < {SCAN_DISK_MB} MB on disk, < 1 GB"
    size = ""
    if n != SCAN_SAMPLES:
        target = (f"{power_of_ten(SCAN_SAMPLES)} rows in < {SCAN_MINUTES} min, i.e. a whole "
                  f"process ≥ {sig(needed)} rows/s; < {SCAN_DISK_MB} MB on disk; < 1 GB")
        size = (f" (measured at {power_of_ten(n)}, not {power_of_ten(SCAN_SAMPLES)}: the time "
                "target is judged pro rata)")
    return [(f"a {power_of_ten(n)}-impact summary scan of `throughput.toml` (`--summary-only`, "
             f"2^17-row chunks, the same `[summary]`){size}",
             f"**{m['wall_s'] / 60:.1f} min** wall ({sig(m['rows_per_s'])} rows/s within the "
             f"run, {sig(process)} for the whole process), "
             f"**{m['bytes_on_disk'] / 1e6:.2f} MB** on disk, peak memory "
             f"**{sig(m['peak_memory_mb'])} MB**", target, ok)]


def _long_scan_memory(results):
    scans = _scans(results)
    if len(scans) < 2:
        return []
    (small, a), (large, b) = min(scans.items()), max(scans.items())
    pa, pb = a["metrics"]["peak_memory_mb"], b["metrics"]["peak_memory_mb"]
    change = pb / pa - 1
    return [(f"peak memory of summary-only scans, {small:,} against {large:,} samples "
             "(`VmHWM`)",
             f"**{sig(pa)} MB** against **{sig(pb)} MB** ({100 * change:+.1f} %)",
             "same within 10 %", abs(change) <= 0.10)]


def _long_memory(r):
    m, s = r["metrics"], r["settings"]
    small, large = min(s["samples"]), max(s["samples"])
    peaks = m["peak_memory_mb"]
    extra = f", `{s['extra']}`" if s["extra"] else ", every column"
    return [(f"peak memory of a study that stores its rows (`mcbat run studies/{s['study']}`"
             f"{extra}), {large:,} against {small:,} samples (`ru_maxrss`)",
             f"**{sig(peaks[str(large)])} MB** against **{sig(peaks[str(small)])} MB** "
             f"({m['ratio']:.2f}x)", f"within {s['limit']:g}x", m["ratio"] <= s["limit"])]


#: The long-run table: (result name or None for rows made from several results, rows).
LONG = [("dask", _long_dask), ("game", _long_game), ("flight", _long_flight),
        ("pipeline", _long_pipeline), (None, _long_scan), (None, _long_scan_memory),
        ("memory", _long_memory)]


def _scan_sources(results, make) -> list[str]:
    """The scan results a row made from several results reads: the largest scan, or the
    smallest and the largest."""
    scans = [f"pipeline_scan_{n}" for n in _scans(results)]
    return scans[-1:] if make is _long_scan else [scans[0], scans[-1]]


def _table(entries, results) -> str:
    """Rows of ``entries`` (``(name, make)`` pairs: ``make(results[name])``, or
    ``make(results)`` for ``name`` None), with each row's commands and the machines."""
    lines = ["| metric | measured | target (full size, quiet machine): verdict of these "
             "figures | command |", "|---|---|---|---|"]
    used = []
    for name, make in entries:
        if name is None:
            rows = make(results)
            sources = _scan_sources(results, make) if rows else []
        elif name in results:
            rows, sources = make(results[name]), [name]
        else:
            continue
        commands = ", ".join(f"`{results[n]['command']}`" for n in sources)
        for metric, measured, target, ok in rows:
            lines.append(f"| {metric} | {measured} | {verdict(target, ok)} | {commands} |")
        if rows:
            used += [n for n in sources if n not in used]
    if not used:
        return "No results."
    lines += ["", "Measured on (CPU, cores, versions, numba threads, load while measured):", ""]
    lines += [f"- {line}" for line in _machines(results, used)]
    return "\n".join(lines)


def _span(values) -> str:
    """'1.2-3.4', or '1.2' when all are the same."""
    lo, hi = min(values), max(values)
    return f"{lo:g}" if lo == hi else f"{lo:g}-{hi:g}"


def _machines(results: dict, names) -> list[str]:
    """One line per machine and set of versions: the benchmarks measured on it, the load
    averages and the dates."""
    groups: dict[str, list[str]] = {}
    for name in names:
        groups.setdefault(harness.machine_line(results[name]["machine"]), []).append(name)
    lines = []
    for line, members in groups.items():
        loads = [results[n]["machine"].get("load_average_1min") for n in members]
        loads = [x for x in loads if x is not None]
        dates = sorted({results[n]["date"] for n in members})
        load = f"; load average {_span(loads)}" if loads else ""
        lines.append(f"{line}{load}; {', '.join(dates)} "
                     f"({', '.join(f'`{n}`' for n in members)})")
    return lines


def speed_table(results: dict) -> str:
    return _table([(name, make) for name, make in ROWS.items()], results)


def long_table(results: dict) -> str:
    return _table(LONG, results)


# --- accuracy: python -m validation kernel_accuracy and fuzz_kernel ---------------------

MODE_LABELS = {"free": "Sec. V bodies, free slip", "small": "small incoming slip",
               "zero": "zero-slip incidence", "reslip": "re-slip",
               "light_bat": "light bats (5-300 g)", "heavy_bat": "heavy bats (5-5000 kg)",
               "high_spin": "spins to 3000 rad/s", "creep": "creeping slip"}
ERROR_COLUMNS = (("velocity", "velocity"), ("stick_impulse", "`I_s`"),
                 ("normal_work", "`W_n`"), ("friction_work", "`W_fr`"),
                 ("stick_criterion", "`C`"))


def _error(x) -> str:
    """An error of the accuracy mix: '—' where the column applies to no case."""
    if x is None:
        return "—"
    if x == "inf":
        return "inf (a failure)"
    return "0" if x == 0 else sci(x)


#: Where the development data sit beside the repository; the docs name it ``DEV/``.
DEVELOPMENT_DATA = "../shared/data/"


def _command_line(r) -> str:
    command = r["command"]
    where = ""
    if DEVELOPMENT_DATA in command:
        command = command.replace(DEVELOPMENT_DATA, "DEV/")
        where = ("; DEV: the folder of development data, its files listed with their "
                 "sources in data/README.md")
    return (f"`{command}` ({r['date']}; {harness.machine_line(r['machine'])}; load "
            f"average {r['machine']['load_average_1min']:g}{where})")


def accuracy_table(results: dict) -> str:
    if "accuracy_mix" not in results:
        return "No results."
    r = results["accuracy_mix"]
    m, s = r["metrics"], r["settings"]
    head = "| mode | cases | " + " | ".join(label for _, label in ERROR_COLUMNS) + " |"
    lines = [head, "|---|---" + "|---" * len(ERROR_COLUMNS) + "|"]
    for mode, by in m["by_mode"].items():
        label = f"**all cases** (seed {s['seed']})" if mode == "all" else MODE_LABELS.get(mode,
                                                                                       mode)
        lines.append(f"| {label} | {by['n']} | "
                     + " | ".join(_error(by[c]) for c, _ in ERROR_COLUMNS) + " |")
    lines.append("| **target** | | " + " | ".join(sci(s["targets"][c], 0)
                                                  for c, _ in ERROR_COLUMNS) + " |")
    lines.append("| verdict | | " + " | ".join(
        "met" if m["passed"][c] else f"**not met** ({m['over_target'][c]} cases over)"
        for c, _ in ERROR_COLUMNS) + " |")
    lines += ["", f"At the default tolerance {sci(s['default_tolerance'], 0)}; "
              f"{m['reference_failures']} reference failures. {_command_line(r)}."]
    return "\n".join(lines)


def convergence_table(results: dict) -> str:
    if "accuracy_mix" not in results:
        return "No results."
    r = results["accuracy_mix"]
    m, s = r["metrics"], r["settings"]
    lines = ["| tolerance | " + " | ".join(label for _, label in ERROR_COLUMNS)
             + " | RK4 steps per impact | kernel failures |",
             "|---" * (len(ERROR_COLUMNS) + 3) + "|"]
    for row in m["per_tolerance"]:
        lines.append(f"| {sci(row['tolerance'], 0)} | "
                     + " | ".join(_error(row[c]) for c, _ in ERROR_COLUMNS)
                     + f" | {row['mean_rk4_steps']:.1f} | {row['kernel_failures']} |")
    if m["monotone_totals"] is not None:
        totals = m["monotone_totals"]
        lines += ["", f"Monotone convergence (a 10-fold tighter tolerance never makes an error "
                  f"more than 2x worse, unless it stays below 1e-13): cases that break it "
                  f"somewhere, {m['monotone_cases']} of {s['n']} ("
                  + ", ".join(f"{label} {totals[c]}" for c, label in ERROR_COLUMNS)
                  + " tolerance pairs)."]
    return "\n".join(lines)


def fuzz_paragraph(results: dict) -> str:
    if "fuzz_kernel" not in results:
        return "No results."
    r = results["fuzz_kernel"]
    m, s = r["metrics"], r["settings"]
    failed = {k: v for k, v in m["failures"].items() if v}
    if m["passed"]:
        checks = "every check passes"
    else:
        checks = ("checks fail: " + ", ".join(f"{k} {v:,} rows" for k, v in failed.items())
                  + f"; {m['crashes']} crashed and {m['hung_chunks']} hung chunks")
    return (f"**Fuzzed** with {m['rows']:,} extreme but valid (and some invalid) impacts, "
            f"seed {s['seed']}: {checks} (status codes, finite outputs, no energy gained, "
            f"momentum); {m['by_status']['max_steps']:,} rows end `max_steps` (the limit of "
            f"{s['max_steps']:,} steps), {m['mean_steps_ok']:.1f} steps per ok row on "
            f"average; the worst energy change of an ok row is "
            f"{sci(m['worst_energy_gain'])} of `E_in`, the worst momentum error "
            f"{sci(m['worst_momentum_error'])} of its scale. {_command_line(r)}.")


def cluster_table(results: dict) -> str:
    if "dask" not in results:
        return "No results."
    r = results["dask"]
    m, s = r["metrics"], r["settings"]
    ratio = m["dask_over_local"]
    return "\n".join([
        "| local, run rows/s | dask, run rows/s | dask / local (target ≥ 80 %) | "
        "whole process, local / dask |", "|---|---|---|---|",
        f"| {sig(m['local_rows_per_s'])} | {sig(m['dask_rows_per_s'])} | "
        f"**{100 * ratio:.1f} %**: {'met' if ratio >= 0.8 else '**not met**'} | "
        f"{m['local_process_wall_s']:.2f} s / {m['dask_process_wall_s']:.2f} s "
        f"({100 * m['local_process_wall_s'] / m['dask_process_wall_s']:.0f} %) |", "",
        f"{s['samples']:,} samples of `{s['study']}`, {s['workers']} workers, medians of "
        f"{s['repeats']}. {_command_line(r)}."])


def short_table(results: dict) -> str:
    rows = []
    if "overview" in results:
        m = results["overview"]["metrics"]
        rows += [("impact kernel, 2 threads", f"{sig(m['kernel_2_threads'])} impacts/s"),
                 ("`mcbat run`, every column to Parquet, 2 threads",
                  f"{sig(m['end_to_end_rows_per_s'])} rows/s"),
                 ("velocities against an independent scipy reference",
                  f"within {sci(m['accuracy_max'], 0)} of the approach speed")]
    if "accuracy_mix" in results:
        r = results["accuracy_mix"]
        worst = r["metrics"]["by_mode"]["all"]["velocity"]
        target = r["settings"]["targets"]["velocity"]
        rows.append((f"velocities on a {r['settings']['n']}-case hard mix, against the same "
                     "reference",
                     f"within {_error(worst)} of the velocity change ("
                     + verdict(f"target {sci(target, 0)}", worst is not None and worst <= target)
                     + ")"))
    if "flight" in results:
        rows.append(("flight kernel, 2 threads",
                     f"{sig(results['flight']['metrics']['flights_per_s'])} flights/s"))
    lines = ["| what | measured |", "|---|---|"] + [f"| {a} | {b} |" for a, b in rows]
    # the machine and load of the results this table shows, not of every recorded run
    shown = [results[n] for n in ("overview", "accuracy_mix", "flight") if n in results]
    cpus = sorted({f"{r['machine']['cpu']}, {r['machine']['cores']} cores" for r in shown})
    loads = [r["machine"]["load_average_1min"] for r in shown
             if "load_average_1min" in r["machine"]]
    load = (f" (load average {_span(loads)} while measured: the machine "
            "was shared)" if loads else "")
    lines += ["", f"Measured on {'; '.join(cpus)}{load}; commands, sizes and settings in "
              "[docs/accuracy-and-speed.md](docs/accuracy-and-speed.md#speed)."]
    return "\n".join(lines)


def first_call_table(results: dict) -> str:
    """Each command's first call with an empty numba cache, and its second call."""
    if "first_call" not in results:
        return "No results."
    r = results["first_call"]
    lines = ["| command | first call: wall, CPU | then (cached): wall, CPU | said it compiles "
             "(first call, then) | first call ≤ 20 s of wall time on 2 cores: verdict |",
             "|---|---|---|---|---|"]
    for m in r["metrics"]["commands"].values():
        said = ("yes" if m["cold_announced"] else "no") + ", " + (
            "yes" if m["warm_announced"] else "no")
        lines.append(f"| `{m['argv']}` | {m['cold_wall_s']:.1f} s, {m['cold_cpu_s']:.1f} s | "
                     f"{m['warm_wall_s']:.1f} s, {m['warm_cpu_s']:.1f} s | {said} | "
                     f"{verdict('≤ 20 s', m['cold_wall_s'] <= 20.0)} |")
    lines += ["", f"Measured with `{r['command']}` on {r['date']}: "
              f"{harness.machine_line(r['machine'])}; load average "
              f"{r['machine']['load_average_1min']:g} before the run (on a shared machine "
              "wall times are longer than on a quiet one). The CPU time counts the helper "
              "process's too."]
    return "\n".join(lines)


def _stats(s: dict) -> str:
    return "—" if not s or not s.get("n") else (f"{s['median']:+.1f} / {s['rms']:.1f} "
                                                  f"({s['n']:,})")


def flight_seasons_table(results: dict) -> str:
    """The season table with its in-sample and out-of-sample residuals, side by side."""
    if "flight_seasons" not in results:
        return "No results."
    r = results["flight_seasons"]
    m, s = r["metrics"], r["settings"]
    lines = ["| season | `drag_scale` | balls fitted | in sample | out of sample "
             "(leave one file out) | published model, same air | folds |",
             "|---|---|---|---|---|---|---|"]
    for season, v in m["seasons"].items():
        lines.append(f"| {season} | {v['values']['drag_scale']:.3f} ± "
                     f"{v['errors']['drag_scale']:.3f} | {v['balls']:,} | "
                     f"{_stats(v['in_sample'])} | {_stats(v['out_of_sample'])} | "
                     f"{_stats(v['published'])} | {v['folds']} |")
    o = m["out_of_sample"]
    months = ", ".join(f"{k} {_stats(v)}" for k, v in o["month"].items())
    slope = o.get("temperature_slope_ft_per_degF")
    lines += ["", "Median / rms of predicted minus measured (ft) and the number of fly balls "
              "and home runs of 20-50 deg. Out of sample, all seasons: "
              f"**{_stats(o['all'])}**, {o['compared']:,} of {o['eligible']:,} eligible "
              f"balls compared ({100 * o['compared'] / o['eligible']:.1f} %). By month "
              f"(01-12): {months}."]
    if slope:
        lines.append("")
        lines.append(f"Against the recorded game temperature ({slope['balls']:,} balls with "
                     f"a weather row): **{slope['value']:+.3f} ± {slope['error']:.3f} ft per "
                     f"°F**. The recorded wind is felt at a scale of {m['wind_scale']:.2f} "
                     f"(the least rms of {len(m['wind_scan'])} scales tried from 0 to "
                     f"{max(map(float, m['wind_scan']), default=0):.2f}).")
    lines += ["", f"{len(s['files'])} files, weather `{s['weather']}`; left out as selected "
              f"on the outcome: {', '.join(s['left_out_selected_on_outcome']) or 'none'}. "
              f"{_command_line(r)}."]
    return "\n".join(lines)


def season_benchmark_table(results: dict) -> str:
    """A season's export through the commands: time, rows/s and peak memory."""
    if "season" not in results:
        return "No results."
    r = results["season"]
    m, s = r["metrics"], r["settings"]
    lines = ["| command | wall time | rows/s | peak memory (target ≤ 3 GB) |",
             "|---|---|---|---|"]
    for name, v in m.items():
        lines.append(f"| `mcbat {name}` | {v['median_s']:.1f} s | {sig(v['rows_per_s'])} | "
                     f"{v['peak_mb']:,.0f} MB: "
                     f"{'met' if v['peak_mb'] <= 3072 else '**not met**'} |")
    lines += ["", f"An export of {s['rows']:,} pitches ({s['megabytes']:,.0f} MB, copies of "
              f"`{s['source']}`), medians of {s['repeats']} runs, each command its own "
              f"process. {_command_line(r)}."]
    return "\n".join(lines)


#: Every generated block: its name, the file it sits in and what writes it.
BLOCKS = {"speed": (ROOT / "docs" / "accuracy-and-speed.md", speed_table),
          "long-runs": (ROOT / "docs" / "accuracy-and-speed.md", long_table),
          "accuracy": (ROOT / "docs" / "accuracy-and-speed.md", accuracy_table),
          "convergence": (ROOT / "docs" / "accuracy-and-speed.md", convergence_table),
          "fuzz": (ROOT / "docs" / "accuracy-and-speed.md", fuzz_paragraph),
          "cluster": (ROOT / "docs" / "cluster.md", cluster_table),
          "speed-short": (ROOT / "README.md", short_table),
          "population-speed": (ROOT / "docs" / "population.md", population_table),
          "population-injection": (ROOT / "docs" / "population.md", injection_table),
          "flight-seasons": (ROOT / "docs" / "flight.md", flight_seasons_table),
          "season-benchmark": (ROOT / "docs" / "statcast.md", season_benchmark_table),
          "first-call": (ROOT / "docs" / "accuracy-and-speed.md", first_call_table)}
#: Where each generated block lives.
TARGETS = {name: path for name, (path, _) in BLOCKS.items()}


def render_blocks(results: dict) -> dict[str, str]:
    """``{block name: Markdown}`` for every generated block."""
    return {name: make(results) for name, (_, make) in BLOCKS.items()}


def _pattern(name: str) -> re.Pattern:
    return re.compile(rf"(<!-- begin generated: {re.escape(name)} -->\n)(.*?)\n?"
                      rf"(<!-- end generated: {re.escape(name)} -->)", re.S)


def read_block(text: str, name: str, where: str = "the text") -> str:
    """The text between a block's markers; ``KeyError`` if the markers are missing."""
    found = _pattern(name).search(text)
    if found is None:
        raise KeyError(f"no '<!-- begin generated: {name} -->' block in {where}")
    return found.group(2)


def replace_block(text: str, name: str, body: str) -> str:
    read_block(text, name)  # the markers must be there
    return _pattern(name).sub(lambda m: m.group(1) + body + "\n" + m.group(3), text, count=1)


def stale_blocks(results: dict, texts: dict[Path, str]) -> list[str]:
    """The blocks whose text in ``texts`` (``{file: its text}``) is not what ``results``
    render; ``KeyError`` if a block's markers are missing."""
    return [name for name, body in render_blocks(results).items()
            if read_block(texts[TARGETS[name]], name, TARGETS[name].name) != body]


def marked_blocks(text: str) -> list[str]:
    """The names of the generated blocks a text holds, in order."""
    return re.findall(r"<!-- begin generated: ([\w-]+) -->", text)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks render",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--results", type=Path, default=RESULTS, metavar="DIR")
    parser.add_argument("--check", action="store_true",
                        help="change nothing; exit 1 if a table is not what DIR renders")
    args = parser.parse_args(argv)
    results = harness.load_results(args.results)
    if not results:
        parser.error(f"no results (*.json) in {args.results}")
    texts = {path: path.read_text() for path in set(TARGETS.values())}
    try:
        stale = stale_blocks(results, texts)
    except KeyError as error:
        parser.error(error.args[0])
    if args.check:
        if stale:
            print("not rendered from the results: " + ", ".join(
                f"'{name}' in {TARGETS[name].relative_to(ROOT)}" for name in stale),
                file=sys.stderr)
            return 1
        return 0
    blocks = render_blocks(results)
    for name in stale:
        path = TARGETS[name]
        texts[path] = replace_block(texts[path], name, blocks[name])
        print(f"rewrote the '{name}' block of {path.relative_to(ROOT)}")
    for path in {TARGETS[name] for name in stale}:
        path.write_text(texts[path])
    return 0
