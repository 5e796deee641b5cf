"""SHA-256 of every data column of the shipped studies' datasets: the proof that a
refactor left the data unchanged, bit for bit.

The datasets:

* ``throughput``: ``mcbat run studies/throughput.toml --samples 200000 --seed 7``;
* ``sec5``: ``mcbat run studies/cross_nathan_2006.toml`` with the study's defaults (the
  Monte Carlo dataset of ``mcbat reproduce``);
* every other study of ``studies/`` at ``SHIPPED_SAMPLES`` rows, seed 3.

Each column is hashed over its values in ``sample_id`` order (the raw little-endian bytes
of the numpy array; NaNs hash as their bit patterns). Schema metadata (units, versions,
the study text) is deliberately not hashed: it may change with the package.

**The environment.** The record holds the environment it was made in (numpy, numba and
Python versions, the machine, the CPU, numpy's SIMD targets found on it). The kernel's
columns (numba, glibc's libm) come out the same on every x86-64 machine tried, but the
columns derived with numpy's ``arctan2`` (:data:`ENVIRONMENT_DEPENDENT`) do not: on a CPU
with AVX-512 numpy evaluates it with its SVML kernels (up to 4 ulps from the true value;
numpy/numpy#19478, #23523), elsewhere with libm's (under 1 ulp), so their last bits depend
on the CPU. In the recording's environment every column must match bit for bit. In
another one those columns are instead (a) recomputed here from their inputs, which must
match bit for bit (``scattering_angle = degrees(arctan2(ball_vy, ball_vx))``), and
(b) compared with values recorded at every ``SAMPLE_EVERY``-th row within
:data:`ULPS` ulps of the row's ``scattering_angle``; the check says that it did so.

Usage::

    python -m validation data_fingerprint --record validation/data_fingerprint.json
    python -m validation data_fingerprint --check validation/data_fingerprint.json

``--check`` exits 1 and lists every column that differs (a column that exists on one side
only is listed too).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import platform
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
#: Every other study shipped in ``studies/``, at a size that runs in seconds: enough rows
#: to pass through every branch the study's draws reach, and any change to the sampler,
#: the solver, the flight or the derived columns changes their hashes.
SHIPPED_SAMPLES = 6000
DATASETS.update({
    path.stem: [f"studies/{path.name}", "--samples", str(SHIPPED_SAMPLES), "--seed", "3"]
    for path in sorted((ROOT / "studies").glob("*.toml"))
    if path.stem not in ("throughput", "cross_nathan_2006")})

#: Columns whose last bits depend on the CPU through numpy's ``arctan2`` (module docstring).
ENVIRONMENT_DEPENDENT = ("scattering_angle", "scattering_angle_measured")
#: Their definitions from bit-exact columns (the measured copy adds a noise draw that is
#: not stored, so it has none).
DEFINITIONS = {"scattering_angle":
               lambda c: np.degrees(np.arctan2(c["ball_vy"], c["ball_vx"]))}
#: Tolerance for those columns across environments, in ulps of the row's
#: ``scattering_angle``: two ``atan2`` 4 + 1 ulps apart at most, up to doubled by the
#: conversion to degrees, plus the rounding of the product and of the noise's sum.
ULPS = 12
#: Every how many rows the values of those columns are recorded.
SAMPLE_EVERY = 500


def environment() -> dict:
    """What the bits of the data may depend on."""
    import numba

    cpu = platform.processor()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
        simd = [f for f in __cpu_dispatch__ if __cpu_features__.get(f)]
    except ImportError:  # a numpy without this introspection
        simd = None
    return {"numpy": np.__version__, "numba": numba.__version__,
            "python": platform.python_version(), "machine": platform.machine(),
            "cpu": cpu, "numpy_simd": simd}


def read_columns(directory) -> dict:
    """``{column: values}`` of a dataset directory, rows in ``sample_id`` order."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    files = sorted(Path(directory).glob("chunk-*.parquet"))
    table = pa.concat_tables(pq.read_table(path) for path in files)
    order = np.argsort(table.column("sample_id").to_numpy(), kind="stable")
    return {name: np.ascontiguousarray(table.column(name).to_numpy()[order])
            for name in table.column_names}


def fingerprint(columns: dict) -> dict:
    """The record of one dataset: its rows, every column's hash, and the sampled values of
    the environment-dependent columns."""
    return {"rows": len(columns["sample_id"]),
            "columns": {name: hashlib.sha256(values.tobytes()).hexdigest()
                        for name, values in columns.items()},
            "samples": {name: [float(v) for v in columns[name][::SAMPLE_EVERY]]
                        for name in ENVIRONMENT_DEPENDENT if name in columns}}


def run(name: str) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / name
        command = [sys.executable, "-c", "import sys; from mcbat.cli import main; "
                   "sys.exit(main())", "run", *DATASETS[name], "--out", str(out), "--quiet"]
        subprocess.run(command, cwd=ROOT, check=True)
        return read_columns(out)


def within_ulps(recorded, current, reference, ulps=ULPS) -> tuple[bool, float]:
    """Whether ``current`` is within ``ulps`` ulps of ``reference`` from ``recorded``
    everywhere (NaN matches NaN), and the largest difference in those ulps."""
    recorded, current = np.asarray(recorded, float), np.asarray(current, float)
    both_nan = np.isnan(recorded) & np.isnan(current)
    spacing = np.spacing(np.abs(np.asarray(reference, float)))
    with np.errstate(invalid="ignore"):
        diff = np.where(both_nan, 0.0, np.abs(recorded - current) / spacing)
    worst = float(np.nanmax(diff)) if diff.size else 0.0
    ok = bool(np.all(np.isfinite(diff) | both_nan) and worst <= ulps)
    return ok, worst


def compare(name: str, before: dict, columns: dict, same_environment: bool) -> list[str]:
    """The differences of one dataset from its record, one line each."""
    after = fingerprint(columns)
    lines = []
    if before["rows"] != after["rows"]:
        lines.append(f"{name}: {before['rows']} rows recorded, {after['rows']} now")
    for column in sorted(set(before["columns"]) | set(after["columns"])):
        old, new = before["columns"].get(column), after["columns"].get(column)
        if old == new:
            continue
        if same_environment or column not in ENVIRONMENT_DEPENDENT or new is None \
                or old is None:
            lines.append(f"{name}: {column}: {old} -> {new}")
            continue
        definition = DEFINITIONS.get(column)
        if definition is not None:
            inputs_same = all(before["columns"].get(c) == after["columns"].get(c)
                              for c in ("ball_vx", "ball_vy"))
            exact = np.array_equal(definition(columns).view(np.int64),
                                   columns[column].view(np.int64))
            if not (inputs_same and exact):
                lines.append(f"{name}: {column}: not its definition of unchanged inputs")
                continue
        if len(before["samples"].get(column, [])) != len(after["samples"][column]):
            lines.append(f"{name}: {column}: recorded samples do not match the rows")
            continue
        reference = columns["scattering_angle"][::SAMPLE_EVERY]
        ok, worst = within_ulps(before["samples"][column], after["samples"][column],
                                reference)
        if not ok:
            lines.append(f"{name}: {column}: {worst:.3g} ulps from the recorded values "
                         f"(at most {ULPS})")
        else:
            print(f"{name}: {column}: hash differs in this environment; "
                  + ("its definition holds bit for bit, " if definition else "")
                  + f"the recorded rows within {worst:.3g} ulps (at most {ULPS})")
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--record", metavar="JSON", help="write the fingerprints here")
    mode.add_argument("--check", metavar="JSON", help="compare with the fingerprints here")
    args = parser.parse_args(argv)
    here = environment()
    if args.record:
        record = {"environment": here,
                  "datasets": {name: fingerprint(run(name)) for name in DATASETS}}
        Path(args.record).write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")
        count = sum(len(d["columns"]) for d in record["datasets"].values())
        print(f"recorded {count} column hashes to {args.record}")
        return 0
    recorded = json.loads(Path(args.check).read_text())
    there = recorded["environment"]
    same = {k: there.get(k) for k in here} == here
    if not same:
        print("environment differs from the recording's: " + "; ".join(
            f"{k} {there.get(k)} -> {here[k]}" for k in here if there.get(k) != here[k]))
        print(f"  columns from numpy's arctan2 ({', '.join(ENVIRONMENT_DEPENDENT)}) are "
              f"checked by their definition and within {ULPS} ulps; the others bit for bit")
    failures = []
    for name in DATASETS:
        columns = run(name)
        before = recorded["datasets"][name]
        lines = compare(name, before, columns, same)
        failures += lines
        for line in lines:
            print(line)
        print(f"{name}: {len(before['columns']) - len(lines)} of {len(before['columns'])} "
              f"columns as recorded, {len(columns['sample_id'])} rows")
    if failures:
        print(f"{len(failures)} differences")
    else:
        print("data unchanged, bit for bit" if same else
              "data unchanged (bit for bit but for the environment-dependent columns)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
