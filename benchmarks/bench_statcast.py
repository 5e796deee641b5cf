"""Speed of the Statcast reader: ``mcbat.statcast.read`` on an export of Savant's largest
query size.

Run:  .venv/bin/python benchmarks/bench_statcast.py [--copies C] [--repeats K]

Builds a CSV of C copies of the rows of ``data/statcast_2020-09-03.csv`` (2,507 rows each;
the default 10 gives 25,070 rows, about the 25,000 rows a Savant query returns at most),
then times ``read`` on it: rows/s, median of K runs (the first run, which pays for imports,
is not counted).
"""

import argparse
import statistics
import tempfile
import time
from importlib import resources
from pathlib import Path

from mcbat.statcast import read


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--copies", type=int, default=10)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    lines = resources.files("mcbat.data").joinpath("statcast_2020-09-03.csv").read_text(
        encoding="utf-8").splitlines()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "savant.csv"
        path.write_text("\n".join([lines[0]] + lines[1:] * args.copies) + "\n")
        rows = (len(lines) - 1) * args.copies
        read(path)  # imports and caches
        times = []
        for _ in range(args.repeats):
            start = time.perf_counter()
            df = read(path)
            times.append(time.perf_counter() - start)
        assert len(df) == rows
        size = path.stat().st_size / 1e6
    median = statistics.median(times)
    print(f"read: {rows:,} rows ({size:.1f} MB): {median:.2f} s, {rows / median:,.0f} rows/s "
          f"(median of {args.repeats}; min {min(times):.2f} s)")


if __name__ == "__main__":
    main()
