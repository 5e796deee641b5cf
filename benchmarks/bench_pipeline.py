"""`mcbat run` against the kernel alone, measured in one process run after run.

Run:  .venv/bin/python -m benchmarks pipeline [--samples 2000000] [--repeats 5]
                                                   [--modes all,12,summary]
      .venv/bin/python -m benchmarks pipeline --scan 1000000000   # the big summary scan

Measured on ``studies/throughput.toml`` (2 threads), each run a fresh process into an empty
directory (one unmeasured warm-up run first), medians over ``--repeats``:

* the kernel alone (``solve_batch`` on 1,000,000 pre-drawn inputs, in this process),
  impacts/s, measured at the start of every round (a round runs each mode once), so a
  run's share of the kernel compares the two at the same moment of a shared machine;
* ``mcbat run`` with every column: rows/s within the run (its own closing line) and for the
  whole process (start-up included);
* ``--columns`` with 12 columns;
* ``--summary-only`` with a ``[summary]`` (40 bins of from_barrel_end, exit_speed and
  scattering_angle with 3 quantiles): rows/s and its ratio to the kernel alone.

``--scan N`` runs one summary-only scan of N samples instead (default chunks) and
reports its wall time, its bytes on disk and its peak memory (VmHWM); ``--memory`` runs
summary-only scans of 10 M and 100 M samples and compares their peak memory.
"""

from __future__ import annotations

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
THROUGHPUT = ROOT / "studies" / "throughput.toml"
SUMMARY = """
[summary]
by = { from_barrel_end = { bins = 40, low = 0, high = 70, unit = "cm" } }
columns = ["exit_speed", "scattering_angle"]
quantiles = [0.05, 0.5, 0.95]
"""
TWELVE = ("mu,e,from_barrel_end,angle,ball_vx_in,bat_wy_in,exit_speed,scattering_angle,"
          "spin,status,end_state,normal_impulse")


class KernelAlone:
    """Impacts/s of the batch kernel alone on the mix, 2 threads (1,000,000 pre-drawn
    samples in one call); measured again before every round of runs, so that each run is
    compared with the kernel at the same moment of a shared machine."""

    def __init__(self, samples):
        from mcbat.core.batch import INPUT_FIELDS, allocate_outputs, solve_batch
        from mcbat.study import load_study

        study = load_study(THROUGHPUT)
        self.n = min(samples, 1_000_000)
        cols = study.sample(0, self.n)
        self.inputs = np.stack([cols[name] for name in INPUT_FIELDS])
        solver = study.solver
        self.args = (solver["steps"], solver["tolerance"], solver["max_steps"])
        self.out = allocate_outputs(self.n)
        self.solve = solve_batch
        solve_batch(self.inputs[:, :64].copy(), *self.args, *allocate_outputs(64))

    def rate(self):
        """Impacts/s of one call."""
        t0 = time.perf_counter()
        self.solve(self.inputs, *self.args, *self.out)
        return self.n / (time.perf_counter() - t0)


def run(study, samples, extra, work):
    """One `mcbat run` in a fresh process: (rows/s of the run, wall s, peak kB, bytes)."""
    out = work / "ds"
    cmd = [sys.executable, "-m", "mcbat.cli", "run", str(study), "--out", str(out),
           "--samples", str(samples), "--threads", "2", "--quiet", *extra]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    peak = 0
    while proc.poll() is None:
        try:
            status = Path(f"/proc/{proc.pid}/status").read_text()
            peak = max(peak, int(re.search(r"VmHWM:\s+(\d+)", status).group(1)))
        except (OSError, AttributeError):
            pass
        time.sleep(0.2)
    stdout, stderr = proc.communicate()
    wall = time.perf_counter() - t0
    if proc.returncode:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{stderr}")
    rate = float(re.search(r"\(([\d,]+) rows/s\)", stdout).group(1).replace(",", ""))
    size = sum(p.stat().st_size for p in out.iterdir())
    shutil.rmtree(out)
    return rate, wall, peak, size


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=2_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--scan", type=int, default=None, metavar="N")
    parser.add_argument("--memory", action="store_true")
    parser.add_argument("--modes", default="all,12,summary",
                        help="which runs, comma-separated: all (every column), 12 (the "
                             "12 columns), summary (summary-only); default all three")
    args = parser.parse_args(argv)
    work = Path(tempfile.mkdtemp(prefix="mcbat-pipeline-"))
    try:
        summary_study = work / "throughput_summary.toml"
        summary_study.write_text(THROUGHPUT.read_text() + SUMMARY)
        scans = [args.scan] if args.scan else [10_000_000, 100_000_000] if args.memory else []
        for samples in scans:
            rate, wall, peak, size = run(summary_study, samples,
                                         ["--summary-only"], work)
            print(f"summary-only scan of {samples:,} samples: {wall / 60:.1f} min wall, "
                  f"{rate:,.0f} rows/s within the run, {size / 1e6:.2f} MB on disk, peak "
                  f"memory {peak / 1024:,.0f} MB", flush=True)
            harness.record(f"pipeline_scan_{samples}", {
                "rows_per_s": rate, "wall_s": wall, "peak_memory_mb": peak / 1024,
                "bytes_on_disk": size}, {"samples": samples, "mode": "summary only",
                                         "study": "studies/throughput.toml + [summary]"})
        if scans:
            return
        kernel_alone = KernelAlone(args.samples)
        modes = {"all columns": (THROUGHPUT, []),
                 "12 columns": (THROUGHPUT, ["--columns", TWELVE]),
                 "summary only": (summary_study, ["--summary-only"])}
        chosen = {"all": "all columns", "12": "12 columns", "summary": "summary only"}
        modes = {chosen[key]: modes[chosen[key]] for key in args.modes.split(",")}
        results = {name: [] for name in modes}
        kernels = []
        for study, extra in modes.values():
            run(study, 250_000, extra, work)  # warm-up: numba cache, page cache
        for _ in range(args.repeats):  # rounds: the kernel alone, then each mode once
            kernels.append(kernel_alone.rate())
            for name, (study, extra) in modes.items():
                results[name].append(run(study, args.samples, extra, work))
        kernel = float(np.median(kernels))
        metrics = {"kernel_impacts_per_s": kernel}
        import numba

        print(f"machine: {os.cpu_count()} cores, python {sys.version.split()[0]}, numba "
              f"{numba.__version__}; {args.samples:,} samples, 2 threads, medians of "
              f"{args.repeats}")
        print(f"kernel alone: {kernel:,.0f} impacts/s "
              f"(rounds: {', '.join(f'{k:,.0f}' for k in kernels)})")
        for name, rows in results.items():
            rate = np.median([r[0] for r in rows])
            share = np.median([r[0] / k for r, k in zip(rows, kernels)])
            wall = np.median([r[1] for r in rows])
            peak = max(r[2] for r in rows)
            size = np.median([r[3] for r in rows])
            print(f"{name}: {rate:,.0f} rows/s within the run ({share:.0%} of the kernel "
                  f"in the same round), whole process {wall:.2f} s = "
                  f"{args.samples / wall:,.0f} rows/s, "
                  f"peak {peak / 1024:,.0f} MB, {size / 1e6:,.1f} MB on disk "
                  f"(runs: {', '.join(f'{r[0]:,.0f}' for r in rows)})")
            metrics[name.replace(" ", "_")] = {
                "rows_per_s": float(rate), "share_of_kernel": float(share),
                "process_wall_s": float(wall), "peak_memory_mb": peak / 1024,
                "bytes_on_disk": float(size)}
        harness.record("pipeline", metrics, {"samples": args.samples, "repeats": args.repeats,
                                             "threads": 2, "modes": args.modes,
                                             "study": "studies/throughput.toml"})
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
