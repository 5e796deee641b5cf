"""Speed of the Statcast reader: ``mcbat.statcast.read`` on an export of Savant's largest
query size.

Run:  .venv/bin/python -m benchmarks statcast [--copies C] [--repeats K]

Builds a CSV of C copies of the rows of ``data/statcast_2020-09-03.csv`` (2,507 rows each;
the default 10 gives 25,070 rows, about the 25,000 rows a Savant query returns at most),
then times ``read`` on it: rows/s, median of K runs (the first run, which pays for imports,
is not counted).
"""

import argparse
import tempfile
from importlib import resources
from pathlib import Path

import harness
from mcbat.statcast import read

#: python -m benchmarks --quick statcast
QUICK_ARGS = ["--copies", "2", "--repeats", "3"]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--copies", type=int, default=10)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    lines = resources.files("mcbat.data").joinpath("statcast_2020-09-03.csv").read_text(
        encoding="utf-8").splitlines()
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "savant.csv"
        path.write_text("\n".join([lines[0]] + lines[1:] * args.copies) + "\n")
        rows = (len(lines) - 1) * args.copies
        timing = harness.median_time(lambda: read(path), args.repeats)  # warm-up: imports
        assert len(read(path)) == rows
        size = path.stat().st_size / 1e6
    times, median = timing.times, timing.median
    print(f"read: {rows:,} rows ({size:.1f} MB): {median:.2f} s, {rows / median:,.0f} rows/s "
          f"(median of {args.repeats}; min {min(times):.2f} s)")
    harness.record("statcast", {"rows_per_s": rows / median, "median_s": median,
                                "times_s": list(times)},
                   {"rows": rows, "megabytes": round(size, 2), "copies": args.copies,
                    "repeats": args.repeats, "export": "data/statcast_2020-09-03.csv"})


if __name__ == "__main__":
    main()
