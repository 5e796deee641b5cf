"""Kernel throughput against the kernel of another commit (--baseline), interleaved.

Run:  .venv/bin/python -m benchmarks kernel_vs_baseline [--n 400000] [--rounds 5]
      [--baseline COMMIT]

The machine is shared, so absolute impacts/s drift with the load. This script samples the
``studies/throughput.toml`` mix once, then times ``solve_batch`` of this tree and of the
baseline tree (``git archive COMMIT mcbat``, default 39f1cf7, unpacked into a temporary
folder) in alternating subprocesses at 2 threads, and reports each round's rates and their
ratio.
"""

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
#: It needs --baseline COMMIT: not a run of `python -m benchmarks all`.
IN_ALL = False
BASELINE = "39f1cf7"

TIMER = r"""
import sys, time, numpy as np, numba
numba.set_num_threads(2)
from mcbat.core.batch import solve_batch, allocate_outputs
x = np.load(sys.argv[1])
solve_batch(x[:, :64].copy(), 8, float(sys.argv[2]), 20000, *allocate_outputs(64))
out = allocate_outputs(x.shape[1])
best = []
for _ in range(int(sys.argv[3])):
    t0 = time.perf_counter()
    solve_batch(x, 8, float(sys.argv[2]), 20000, *out)
    best.append(time.perf_counter() - t0)
steps = out[0][23]
print(x.shape[1] / min(best), float(np.nanmean(steps)))
"""


def sample(n, path):
    from mcbat.core.batch import INPUT_FIELDS
    from mcbat.study import load_study

    study = load_study(ROOT / "studies" / "throughput.toml")
    cols = study.sample(0, n)
    np.save(path, np.ascontiguousarray(np.stack([cols[k] for k in INPUT_FIELDS])))


def run(tree, data, tolerance, repeats):
    env = dict(os.environ, PYTHONPATH=str(tree), NUMBA_CACHE_DIR=str(Path(data).parent / tree.name))
    res = subprocess.run([sys.executable, "-c", TIMER, data, str(tolerance), str(repeats)],
                         cwd=tree, env=env, capture_output=True, text=True, check=True)
    rate, steps = res.stdout.split()
    return float(rate), float(steps)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=int, default=400_000)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--tolerance", type=float, default=None)
    p.add_argument("--baseline", default=BASELINE,
                   help=f"commit whose kernel is the baseline (default {BASELINE})")
    args = p.parse_args(argv)
    from mcbat.core.cabo2012.contact import DEFAULT_TOLERANCE

    tol = DEFAULT_TOLERANCE if args.tolerance is None else args.tolerance
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        base = tmp / "base"
        base.mkdir()
        subprocess.run(f"git -C {ROOT} archive {args.baseline} mcbat | tar -x -C {base}",
                       shell=True, check=True)
        data = str(tmp / "mix.npy")
        sample(args.n, data)
        ratios = []
        for r in range(args.rounds):
            b, bs = run(base, data, 5e-9, args.repeats)  # the baseline's own default
            k, ks = run(ROOT, data, tol, args.repeats)
            ratios.append(k / b)
            print(f"round {r}: baseline {b:,.0f}/s ({bs:.1f} steps), this tree {k:,.0f}/s "
                  f"({ks:.1f} steps), ratio {k / b:.3f}", flush=True)
        print(f"ratio median {np.median(ratios):.3f} (min {min(ratios):.3f}, "
              f"max {max(ratios):.3f}) over {args.rounds} rounds, n = {args.n:,}")


if __name__ == "__main__":
    main()
