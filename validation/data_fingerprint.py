"""SHA-256 of every data column of two reference datasets: the proof that a refactor left
the data unchanged, bit for bit.

The two datasets:

* ``throughput``: ``mcbat run studies/throughput.toml --samples 200000 --seed 7``;
* ``sec5``: ``mcbat run studies/cross_nathan_2006.toml`` with the study's defaults (the
  Monte Carlo dataset of ``mcbat reproduce``).

Each column is hashed over its values in ``sample_id`` order (the raw little-endian bytes
of the numpy array; NaNs hash as their bit patterns). Schema metadata (units, versions,
the study text) is deliberately not hashed: it may change with the package.

Usage::

    python -m validation data_fingerprint --record validation/data_fingerprint.json
    python -m validation data_fingerprint --check validation/data_fingerprint.json

``--check`` exits 1 and lists every column whose hash differs (a column that exists on one
side only is listed too).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
DATASETS = {
    "throughput": ["studies/throughput.toml", "--samples", "200000", "--seed", "7"],
    "sec5": ["studies/cross_nathan_2006.toml"],
}


def fingerprint(directory) -> dict:
    """``{column: sha256 hex}`` of a dataset directory, rows in ``sample_id`` order."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    files = sorted(Path(directory).glob("chunk-*.parquet"))
    table = pa.concat_tables(pq.read_table(path) for path in files)
    order = np.argsort(table.column("sample_id").to_numpy(), kind="stable")
    out = {}
    for name in table.column_names:
        values = np.ascontiguousarray(table.column(name).to_numpy()[order])
        out[name] = hashlib.sha256(values.tobytes()).hexdigest()
    out["_rows"] = str(table.num_rows)
    return out


def run_and_fingerprint(name: str) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / name
        command = [sys.executable, "-c", "import sys; from mcbat.cli import main; "
                   "sys.exit(main())", "run", *DATASETS[name], "--out", str(out), "--quiet"]
        subprocess.run(command, cwd=ROOT, check=True)
        return fingerprint(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--record", metavar="JSON", help="write the fingerprints here")
    mode.add_argument("--check", metavar="JSON", help="compare with the fingerprints here")
    args = parser.parse_args(argv)
    current = {name: run_and_fingerprint(name) for name in DATASETS}
    if args.record:
        Path(args.record).write_text(json.dumps(current, indent=1, sort_keys=True) + "\n")
        print(f"recorded {sum(len(v) - 1 for v in current.values())} column hashes "
              f"to {args.record}")
        return 0
    recorded = json.loads(Path(args.check).read_text())
    failures = 0
    for name in DATASETS:
        before, after = recorded[name], current[name]
        for column in sorted(set(before) | set(after)):
            if before.get(column) != after.get(column):
                failures += 1
                print(f"{name}: {column}: {before.get(column)} -> {after.get(column)}")
        same = sum(1 for c in before if c != "_rows" and before[c] == after.get(c))
        print(f"{name}: {same} of {len(before) - 1} columns identical, "
              f"{after.get('_rows')} rows")
    print("data unchanged, bit for bit" if not failures else f"{failures} differences")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
