"""End-to-end throughput of `mcbat run` (sampling, solving, Parquet writing) and peak memory.

Run:  .venv/bin/python -m benchmarks run [--samples 2000000] [--threads 2] [--repeats 3]
      [--study studies/throughput.toml]

Each repeat runs ``mcbat run`` in a fresh process into an empty directory. Reported per run:
the rows/s the run itself measures (sampling + kernel + Parquet, after start-up), the wall
time of the whole process (including Python start-up, imports and loading the cached numba
code) and its peak resident memory. Figures are medians over the repeats.
"""

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
#: python -m benchmarks --quick run
QUICK_ARGS = ["--samples", "200000", "--repeats", "2"]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--study", default=str(ROOT / "studies" / "throughput.toml"))
    parser.add_argument("--samples", type=int, default=2_000_000)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--chunk-size", type=int, default=None)
    args = parser.parse_args(argv)
    work = Path(tempfile.mkdtemp(prefix="mcbat-bench-"))
    run_rates, walls, peaks = [], [], []
    try:
        for i in range(args.repeats + 1):  # the first run warms the numba cache
            out = work / f"run{i}"
            cmd = [sys.executable, "-m", "mcbat.cli", "run", args.study, "--out", str(out),
                   "--samples", str(args.samples), "--threads", str(args.threads), "--quiet"]
            if args.chunk_size:
                cmd += ["--chunk-size", str(args.chunk_size)]
            before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
            t0 = time.perf_counter()
            proc = subprocess.run(cmd, capture_output=True, text=True, check=True)
            wall = time.perf_counter() - t0
            peak_kb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
            rate = float(re.search(r"\(([\d,]+) rows/s\)", proc.stdout).group(1).replace(",", ""))
            shutil.rmtree(out)
            if i == 0:
                continue
            run_rates.append(rate)
            walls.append(wall)
            peaks.append(max(peak_kb, before))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    import numba

    print(f"machine: {os.cpu_count()} cores, python {sys.version.split()[0]}, "
          f"numba {numba.__version__}")
    print(f"study: {Path(args.study).name}, samples: {args.samples:,}, threads: {args.threads}, "
          f"repeats: {args.repeats}")
    print(f"run throughput (sampling + kernel + Parquet): {np.median(run_rates):,.0f} rows/s "
          f"(runs: {', '.join(f'{r:,.0f}' for r in run_rates)})")
    print(f"whole process incl. start-up: {np.median(walls):.2f} s wall, "
          f"{args.samples / np.median(walls):,.0f} rows/s")
    print(f"peak memory (max RSS of the runs): {max(peaks) / 1024:,.0f} MB")
    harness.record("run", {
        "rows_per_s": float(np.median(run_rates)), "runs_rows_per_s": run_rates,
        "process_wall_s": float(np.median(walls)), "peak_memory_mb": max(peaks) / 1024,
    }, {"study": Path(args.study).relative_to(ROOT).as_posix()
        if Path(args.study).resolve().is_relative_to(ROOT) else Path(args.study).name,
        "samples": args.samples, "threads": args.threads, "repeats": args.repeats,
        "chunk_size": args.chunk_size})


if __name__ == "__main__":
    main()
