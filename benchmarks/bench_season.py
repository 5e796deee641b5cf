"""A season's export through ``mcbat statcast``, ``mcbat infer`` and ``mcbat reproduce
statcast``: wall time, rows/s and peak memory of each command.

Run:  .venv/bin/python -m benchmarks season [--rows N] [--repeats K] [--source FILE]

Builds a Savant export of ``N`` pitches (default 700,000: a regular season's ~720,000) from
the real rows of ``--source`` (default the shipped 2020-09-03 day), repeated with each
copy's ``game_pk`` moved out of the way so that no pitch repeats, then runs each command on
it as its own process and reads the process's peak resident memory from the kernel
(``ru_maxrss`` of the finished child). The medians of ``K`` runs are reported (the
commands' numba kernels are compiled and cached by an untimed first run).
"""

import argparse
import csv
import io
import json
import resource
import subprocess
import sys
import tempfile
import time
from importlib import resources
from pathlib import Path

import harness

#: python -m benchmarks --quick season
QUICK_ARGS = ["--rows", "50000", "--repeats", "1"]

COMMANDS = {
    "statcast": ["statcast", "{file}"],
    "infer": ["infer", "{file}", "--out", "{out}/spin.parquet"],
    "reproduce statcast": ["reproduce", "statcast", "--data", "{file}", "--out",
                           "{out}/reproduce", "--overwrite"],
}


def build_export(source_text: str, rows: int, path: Path) -> int:
    """Write ``rows`` pitches made of copies of ``source_text``'s rows; returns the
    count. Each copy adds 10^7 times its number to ``game_pk``."""
    reader = csv.reader(io.StringIO(source_text))
    header = next(reader)
    body = [row for row in reader if row]
    column = header.index("game_pk")
    written = 0
    with path.open("w", newline="", encoding="utf-8") as out:
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(header)
        copy = 0
        while written < rows:
            for row in body:
                if written == rows:
                    break
                moved = list(row)
                moved[column] = str(int(float(row[column])) + copy * 10_000_000)
                writer.writerow(moved)
                written += 1
            copy += 1
    return written


def run_once(args):
    """Wall time (s) and peak resident memory (MB) of one command, run as this process's
    only child (``ru_maxrss`` of the children is then that command's)."""
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "mcbat", *args], capture_output=True,
                          text=True)
    wall = time.perf_counter() - t0
    if done.returncode != 0:
        raise SystemExit(f"mcbat {' '.join(args)} failed ({done.returncode}): "
                         f"{done.stderr.strip()[-500:]}")
    return wall, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0


def measure(args):
    """:func:`run_once` in a fresh helper process, so that each command's peak memory is
    its own."""
    code = ("import json, sys; from benchmarks.bench_season import run_once; "
            "print(json.dumps(run_once(sys.argv[1:])))")
    done = subprocess.run([sys.executable, "-c", code, *args], capture_output=True,
                          text=True)
    if done.returncode != 0:
        raise SystemExit(done.stderr.strip()[-800:])
    wall, peak = json.loads(done.stdout.strip().splitlines()[-1])
    return wall, peak


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=700_000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--source", default=None, metavar="FILE")
    args = parser.parse_args(argv)
    if args.source is None:
        text = resources.files("mcbat.data").joinpath("statcast_2020-09-03.csv").read_text(
            encoding="utf-8-sig")
        source = "data/statcast_2020-09-03.csv"
    else:
        text = Path(args.source).read_text(encoding="utf-8-sig")
        source = Path(args.source).name
    metrics, settings = {}, {"rows": args.rows, "repeats": args.repeats, "source": source}
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "season.csv"
        rows = build_export(text, args.rows, path)
        size = path.stat().st_size / 1e6
        settings["megabytes"] = round(size, 1)
        print(f"export: {rows:,} pitches, {size:.0f} MB (copies of {source})")
        for name, template in COMMANDS.items():
            command = [a.format(file=path, out=tmp) for a in template]
            measure(command)  # compiles and caches the kernels; not counted
            runs = [measure(command) for _ in range(args.repeats)]
            walls = sorted(w for w, _ in runs)
            wall = walls[len(walls) // 2]
            peak = max(p for _, p in runs)
            metrics[name] = {"median_s": wall, "rows_per_s": rows / wall, "peak_mb": peak,
                             "times_s": [w for w, _ in runs]}
            print(f"mcbat {name:<20} {wall:7.1f} s  {rows / wall:10,.0f} rows/s  "
                  f"peak {peak:6,.0f} MB  (median of {args.repeats})")
    harness.record("season", metrics, settings)


if __name__ == "__main__":
    main()
