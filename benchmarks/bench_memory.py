"""Peak memory of ``mcbat run`` against ``--samples``: flat for every kind of study.

Run:  nice -n 19 .venv/bin/python -m benchmarks memory
          [--study studies/game_fastball.toml] [--samples 1000000,10000000] [--limit 1.2]
          [--extra "--summary-only"]

Each run is a fresh ``mcbat run STUDY --samples N --threads 2 --quiet`` process into an
empty directory (removed afterwards; 10^7 rows of the game study with its flight are
8.7 GB on disk); its peak resident memory is the kernel's own account of that child
(``ru_maxrss`` from ``os.wait4``: no sampling, so no peak is missed). Prints, per sample
count, the peak, the wall time and the bytes on disk, then the ratio of the largest run's
peak to the smallest's; exits 1 when the ratio exceeds ``--limit`` (default 1.2).
"""

from __future__ import annotations

import argparse
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import harness

ROOT = Path(__file__).resolve().parents[1]


def peak_of_run(study, samples, work, extra=()):
    """``(peak MB, wall s, bytes on disk, closing report)`` of one run."""
    out = work / "ds"
    cmd = [sys.executable, "-m", "mcbat.cli", "run", str(study), "--out", str(out),
           "--samples", str(samples), "--threads", "2", "--quiet", *extra]
    t0 = time.perf_counter()
    with open(work / "stdout", "w") as stdout, open(work / "stderr", "w") as stderr:
        proc = subprocess.Popen(cmd, stdout=stdout, stderr=stderr)
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - t0
    if proc.returncode:
        raise SystemExit(f"{shlex.join(cmd)} failed ({proc.returncode}):\n"
                         f"{(work / 'stderr').read_text()}")
    size = sum(p.stat().st_size for p in out.iterdir()) if out.is_dir() else 0
    shutil.rmtree(out, ignore_errors=True)
    return usage.ru_maxrss / 1024, wall, size, (work / "stdout").read_text()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--study", type=Path, default=ROOT / "studies" / "game_fastball.toml")
    parser.add_argument("--samples", default="1000000,10000000",
                        help="comma-separated sample counts (default 10^6 and 10^7)")
    parser.add_argument("--extra", default="", help="more `mcbat run` flags, quoted")
    parser.add_argument("--limit", type=float, default=1.2,
                        help="largest allowed ratio of the peaks (default 1.2)")
    parser.add_argument("--work", type=Path, default=None,
                        help="scratch directory (default: a new one under /tmp)")
    args = parser.parse_args(argv)
    counts = [int(float(n)) for n in args.samples.split(",")]
    work = Path(tempfile.mkdtemp(prefix="mcbat-memory-", dir=args.work))
    peaks = {}
    try:
        print(f"study {args.study.name}, flags: {args.extra or '(none)'}", flush=True)
        for samples in counts:
            peak, wall, size, report = peak_of_run(args.study, samples, work,
                                                   shlex.split(args.extra))
            peaks[samples] = peak
            rows = next((line for line in report.splitlines() if line.startswith("rows:")),
                        "")
            print(f"--samples {samples:>12,}: peak {peak:8,.0f} MB, {wall:7.1f} s wall, "
                  f"{size / 1e9:6.2f} GB on disk; {rows}", flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    ratio = peaks[max(counts)] / peaks[min(counts)]
    print(f"peak at {max(counts):,} / peak at {min(counts):,}: {ratio:.3f} "
          f"(limit {args.limit})")
    harness.record("memory", {"peak_memory_mb": {str(n): p for n, p in peaks.items()},
                              "ratio": ratio},
                   {"study": args.study.name, "samples": counts, "extra": args.extra,
                    "limit": args.limit})
    return 0 if ratio <= args.limit else 1


if __name__ == "__main__":
    sys.exit(main())
