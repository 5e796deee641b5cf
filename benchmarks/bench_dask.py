"""Throughput of `mcbat run` with the Dask engine against the local engine.

Run:  .venv/bin/python -m benchmarks dask [--samples 2000000] [--repeats 5]
      [--workers 2] [--study studies/throughput.toml] [--chunk-size C]

Each repeat runs, in fresh processes and alternating which goes first,

    mcbat run STUDY --out DIR --samples N --quiet                                   (local)
    mcbat run STUDY --out DIR --samples N --quiet --engine dask --workers W         (dask)

into empty directories (the local engine uses all cores; each of the W dask workers gets
cores / W numba threads). Reported, as medians over the repeats:

* run rows/s: what the run itself reports, from the first chunk to the last file written.
  It excludes start-up for both engines: Python imports, loading the compiled kernel and,
  for dask, starting the LocalCluster and warming its workers.
* whole-process wall time, and rows/s over it: everything included.

One untimed pair first warms the numba cache. Needs the Dask extra (pip install -e
".[dask]").
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import harness

ROOT = Path(__file__).resolve().parents[1]


def run(cmd):
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{proc.stderr}")
    rate = float(re.search(r"\(([\d,]+) rows/s\)", proc.stdout).group(1).replace(",", ""))
    return rate, wall


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--study", default=str(ROOT / "studies" / "throughput.toml"))
    parser.add_argument("--samples", type=int, default=2_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--chunk-size", type=int, default=None)
    args = parser.parse_args(argv)
    work = Path(tempfile.mkdtemp(prefix="mcbat-bench-dask-"))
    base = [sys.executable, "-m", "mcbat.cli", "run", args.study, "--samples",
            str(args.samples), "--quiet"]
    if args.chunk_size:
        base += ["--chunk-size", str(args.chunk_size)]
    engines = {"local": [], "dask": ["--engine", "dask", "--workers", str(args.workers)]}
    results = {name: {"rate": [], "wall": []} for name in engines}
    try:
        for i in range(args.repeats + 1):  # the first pair warms the numba cache
            order = list(engines) if i % 2 == 0 else list(engines)[::-1]
            for name in order:
                out = work / f"{name}{i}"
                rate, wall = run([*base, "--out", str(out), *engines[name]])
                shutil.rmtree(out)
                if i:
                    results[name]["rate"].append(rate)
                    results[name]["wall"].append(wall)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    import numba

    print(f"machine: {os.cpu_count()} cores, python {sys.version.split()[0]}, "
          f"numba {numba.__version__}")
    print(f"study: {Path(args.study).name}, samples: {args.samples:,}, repeats: "
          f"{args.repeats}, dask: LocalCluster of {args.workers} worker processes")
    print()
    print("| engine | run rows/s (median) | runs | whole process, s (median) | rows/s incl. "
          "start-up |")
    print("|---|---|---|---|---|")
    med = {}
    for name, res in results.items():
        med[name] = (np.median(res["rate"]), np.median(res["wall"]))
        runs = ", ".join(f"{r:,.0f}" for r in res["rate"])
        print(f"| {name} | {med[name][0]:,.0f} | {runs} | {med[name][1]:.2f} | "
              f"{args.samples / med[name][1]:,.0f} |")
    print()
    print(f"dask / local, run rows/s: {med['dask'][0] / med['local'][0]:.1%}; "
          f"whole process: {med['local'][1] / med['dask'][1]:.1%}")
    harness.record("dask", {
        **{f"{name}_rows_per_s": float(m[0]) for name, m in med.items()},
        **{f"{name}_process_wall_s": float(m[1]) for name, m in med.items()},
        "dask_over_local": float(med["dask"][0] / med["local"][0]),
    }, {"study": Path(args.study).name, "samples": args.samples, "repeats": args.repeats,
        "workers": args.workers, "chunk_size": args.chunk_size})


if __name__ == "__main__":
    main()
