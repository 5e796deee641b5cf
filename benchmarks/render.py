"""The speed tables of README.md and docs/accuracy-and-speed.md, rendered from a results
directory (the JSON files of ``python -m benchmarks --results DIR ...``).

    python -m benchmarks render [--results DIR]    # rewrite the tables (default DIR:
                                                   # benchmarks/results, the committed set)
    python -m benchmarks render --check            # exit 1 if a table differs

Each table sits between ``<!-- begin generated: NAME -->`` and
``<!-- end generated: NAME -->``; nothing outside the markers is touched. A row appears
when its benchmark's result is in the directory.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from benchmarks import harness

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"

#: Where each generated block lives.
TARGETS = {"speed": ROOT / "docs" / "accuracy-and-speed.md",
           "speed-short": ROOT / "README.md"}


def sig(x: float, digits: int = 3) -> str:
    """``x`` to ``digits`` significant figures, with thousands separators: 1,234,567 ->
    '1,230,000'; 0.67 -> '0.67'."""
    if x == 0:
        return "0"
    rounded = float(f"{x:.{digits}g}")
    return f"{rounded:,.0f}" if abs(rounded) >= 10 ** (digits - 1) else f"{rounded:g}"


def _overview(r):
    m, s = r["metrics"], r["settings"]
    return [
        (f"kernel, 1 thread, `{s['study']}` mix, {s['kernel_impacts']:,} impacts",
         f"{sig(m['kernel_1_thread'])} impacts/s", "—"),
        ("kernel, 2 threads, same mix", f"**{sig(m['kernel_2_threads'])} impacts/s**",
         "≥ 1,200,000"),
        ("parallel efficiency, 2 threads against 1", f"{100 * m['efficiency']:.1f} %",
         "≥ 90 %"),
        (f"accuracy against the scipy reference, {s['reference_impacts']} impacts of the mix",
         f"{m['accuracy_max']:.1e} max, {m['accuracy_median']:.1e} median", "≤ 1e-8"),
        ("speed-up over the scipy reference, per impact (1 thread)",
         f"{sig(m['speedup'])}x ({1e3 * m['reference_s_per_impact']:.1f} ms against "
         f"{1e6 / m['kernel_1_thread']:.2f} µs)", "≥ 10,000x"),
        (f"end-to-end `mcbat run {s['study']}`, {s['end_to_end_samples']:,} rows, 2 threads "
         f"(median of {s['end_to_end_runs']})",
         f"**{sig(m['end_to_end_rows_per_s'])} rows/s** ({m['end_to_end_wall_s']:.1f} s for "
         "the whole process incl. start-up)", "≥ 500,000"),
        ("`mcbat impact`, one case, warm / cold numba cache",
         f"{m['impact_warm_s']:.2f} s / {m['impact_cold_s']:.1f} s", "warm ≤ 1.5 s"),
        (f"peak memory of a {s['memory_scan_samples']:,}-row scan",
         f"{sig(m['peak_memory_mb'])} MB ({m['peak_memory_wall_s']:.1f} s)", "≤ 2 GB"),
    ]


def _kernel(r):
    m, s = r["metrics"], r["settings"]
    return [(f"kernel, {s['threads']} thread, uniform random mix of the Sec. V bodies, "
             f"{s['impacts']:,} impacts", f"{sig(m['impacts_per_s'])} impacts/s "
             f"({m['steps_mean']:.1f} steps an impact)", "—")]


def _run(r):
    m, s = r["metrics"], r["settings"]
    return [(f"`mcbat run {s['study']}`, {s['samples']:,} samples, {s['threads']} threads "
             f"(median of {s['repeats']})",
             f"{sig(m['rows_per_s'])} rows/s within the run; whole process "
             f"{m['process_wall_s']:.2f} s; peak {sig(m['peak_memory_mb'])} MB", "—")]


def _flight(r):
    m, s = r["metrics"], r["settings"]
    rows = [(f"flight kernel alone: `fly_batch`, {s['launches']:,} random launches "
             f"({s['launch_ranges'].removesuffix(', seed 1')}), {s['threads']} threads",
             f"**{sig(m['flights_per_s'])} flights/s** ({m['steps_mean']:.1f} steps a "
             "flight)", "≥ 700,000")]
    if "game_run_rows_per_s" in m:
        rows.append((f"game study with flight: `mcbat run studies/game_fastball.toml`, "
                     f"{s['run_samples']:,} samples (median of {s['runs']})",
                     f"{sig(m['game_run_rows_per_s'])} rows/s", "≥ 300,000"))
    return rows


def _game(r):
    m, s = r["metrics"], r["settings"]
    return [(f"game kernel against the bat-frame kernel, `{s['study']}`, {s['rows']:,} rows, "
             f"{s['threads']} threads",
             f"{sig(m['game_kernel_rows_per_s'])} against "
             f"{sig(m['bat_frame_kernel_rows_per_s'])} rows/s: the field <-> bat-frame "
             f"transform {m['transform_ns_per_row']:.0f} ns a row "
             f"({100 * m['transform_fraction']:.1f} % of the kernel)", "—")]


def _statcast(r):
    m, s = r["metrics"], r["settings"]
    return [(f"Statcast reader, `mcbat.statcast.read`, {s['rows']:,} rows "
             f"({s['megabytes']:.1f} MB)", f"{sig(m['rows_per_s'])} rows/s", "—")]


def _inference(r):
    m, s = r["metrics"], r["settings"]
    stages = "read + infer + fly" if s["fly"] else "read + infer"
    return [(f"spin inference, {stages}: a Parquet table of {s['balls']:,} simulated balls "
             f"in play, {s['threads']} threads (median of {s['runs']})",
             f"{sig(m['balls_per_s'])} balls/s ({sig(m['balls_per_cpu_s'])} per CPU-second; "
             f"{m['iterations_mean']:.1f} Newton iterations a ball)", "—")]


#: The rows each benchmark contributes to the long table, in this order.
ROWS = {"overview": _overview, "kernel": _kernel, "run": _run, "flight": _flight,
        "game": _game, "inference": _inference, "statcast": _statcast}


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
        load = f"; load average {min(loads):g}-{max(loads):g}" if loads else ""
        lines.append(f"{line}{load}; {', '.join(dates)} "
                     f"({', '.join(f'`{n}`' for n in members)})")
    return lines


def speed_table(results: dict) -> str:
    names = [n for n in ROWS if n in results]
    lines = ["| metric | measured | target (full size, quiet machine) | command |",
             "|---|---|---|---|"]
    for name in names:
        command = results[name]["command"]
        for metric, measured, target in ROWS[name](results[name]):
            lines.append(f"| {metric} | {measured} | {target} | `{command}` |")
    lines += ["", "Measured on (CPU, cores, versions, numba threads, load while measured):", ""]
    lines += [f"- {line}" for line in _machines(results, names)]
    return "\n".join(lines)


def short_table(results: dict) -> str:
    rows = []
    if "overview" in results:
        m = results["overview"]["metrics"]
        rows += [("impact kernel, 2 threads", f"{sig(m['kernel_2_threads'])} impacts/s"),
                 ("`mcbat run`, every column to Parquet, 2 threads",
                  f"{sig(m['end_to_end_rows_per_s'])} rows/s"),
                 ("velocities against an independent scipy reference",
                  f"within {m['accuracy_max']:.0e} of the approach speed")]
    if "flight" in results:
        rows.append(("flight kernel, 2 threads",
                     f"{sig(results['flight']['metrics']['flights_per_s'])} flights/s"))
    lines = ["| what | measured |", "|---|---|"] + [f"| {a} | {b} |" for a, b in rows]
    cpus = sorted({f"{r['machine']['cpu']}, {r['machine']['cores']} cores"
                   for r in results.values()})
    loads = [r["machine"]["load_average_1min"] for r in results.values()
             if "load_average_1min" in r["machine"]]
    load = (f" (load average {min(loads):g}-{max(loads):g} while measured: the machine "
            "was shared)" if loads else "")
    lines += ["", f"Measured on {'; '.join(cpus)}{load}; commands, sizes and settings in "
              "[docs/accuracy-and-speed.md](docs/accuracy-and-speed.md#speed)."]
    return "\n".join(lines)


BLOCKS = {"speed": speed_table, "speed-short": short_table}


def render_blocks(results: dict) -> dict[str, str]:
    """``{block name: Markdown}`` for every generated block."""
    return {name: make(results) for name, make in BLOCKS.items()}


def _pattern(name: str) -> re.Pattern:
    return re.compile(rf"(<!-- begin generated: {re.escape(name)} -->\n)(.*?)\n?"
                      rf"(<!-- end generated: {re.escape(name)} -->)", re.S)


def read_block(text: str, name: str) -> str:
    """The text between a block's markers; ``KeyError`` if the markers are missing."""
    found = _pattern(name).search(text)
    if found is None:
        raise KeyError(f"no '<!-- begin generated: {name} -->' block")
    return found.group(2)


def replace_block(text: str, name: str, body: str) -> str:
    read_block(text, name)  # the markers must be there
    return _pattern(name).sub(lambda m: m.group(1) + body + "\n" + m.group(3), text, count=1)


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
    stale = []
    for name, body in render_blocks(results).items():
        path = TARGETS[name]
        text = path.read_text()
        try:
            current = read_block(text, name)
        except KeyError as error:
            parser.error(f"{path.relative_to(ROOT)}: {error.args[0]}")
        if current == body:
            continue
        stale.append(path)
        if not args.check:
            path.write_text(replace_block(text, name, body))
            print(f"rewrote the '{name}' table of {path.relative_to(ROOT)}")
    if args.check and stale:
        print("not rendered from the results: " + ", ".join(str(p.relative_to(ROOT))
                                                           for p in stale), file=sys.stderr)
        return 1
    return 0
