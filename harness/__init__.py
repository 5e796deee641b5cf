"""What every benchmark and validation run shares: the command line, timing, the machine
and the JSON results.

``benchmarks/`` (speed) and ``validation/`` (correctness) both use this package and never
import each other. ``python -m benchmarks NAME [ARGS]`` and ``python -m validation NAME
[ARGS]`` import ``PACKAGE.NAME`` (or ``PACKAGE.bench_NAME``) and call its ``main(ARGS)``;
``all`` runs every module of the folder, one at a time. A run reports its figures with
:func:`record`, which writes ``DIR/NAME.json`` when the run was given ``--results DIR``.
:mod:`harness.population` holds the population fit's injected truth, which the injection
check (validation) and the fit's timing (benchmarks) share. The instruments of the checks
at scale live here too, outside the package: the kernel's accuracy on a hard mix
(:mod:`harness.impact_mix`, :mod:`harness.accuracy_mix`), measurement tables made without
the fit's machinery (:mod:`harness.drop_tables`, :mod:`harness.game_tables`), their fits
(:mod:`harness.fit_validation`) and the textbook fit (:mod:`harness.textbook_fit`).
"""

from __future__ import annotations

import argparse
import datetime
import importlib
import json
import os
import pkgutil
import platform
import shlex
import statistics
import sys
import time
from dataclasses import dataclass
from pathlib import Path

#: Modules of the two folders that are not runs.
NOT_RUNS = {"render", "__main__"}

#: Set by :func:`main` for the run in progress: where :func:`record` writes, and how the
#: run was called (stored in its JSON).
_RESULTS_DIR: Path | None = None
_COMMAND: str | None = None


@dataclass(frozen=True)
class Timing:
    """The wall times of repeated calls, in seconds, and their median."""

    times: tuple[float, ...]

    @property
    def median(self) -> float:
        """The median wall time, in seconds."""
        return statistics.median(self.times)


def median_time(fn, runs: int, warmup: int = 1) -> Timing:
    """Call ``fn()`` ``warmup`` times untimed (numba's first call loads or compiles the
    kernel), then ``runs`` times, each timed with ``time.perf_counter``."""
    for _ in range(warmup):
        fn()
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return Timing(tuple(times))


def cpu_model() -> str:
    """The processor's name (from /proc/cpuinfo where there is one)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def machine() -> dict:
    """The machine and the versions that decide a benchmark's figures."""
    import numba
    import numpy
    import pyarrow
    import scipy

    return {
        "cpu": cpu_model(), "cores": os.cpu_count(),
        "system": f"{platform.system()} {platform.machine()}",
        "python": platform.python_version(), "numpy": numpy.__version__,
        "numba": numba.__version__, "scipy": scipy.__version__,
        "pyarrow": pyarrow.__version__,
        "numba_num_threads": numba.config.NUMBA_NUM_THREADS,
        # The machine may be shared: its load when the figures were taken.
        "load_average_1min": round(os.getloadavg()[0], 2),
    }


def machine_line(m: dict | None = None) -> str:
    """One line naming the machine ``m`` (a :func:`machine` dict; this one by default)."""
    m = machine() if m is None else m
    return (f"{m['cpu']}, {m['cores']} cores, {m['system']}, Python {m['python']}, numpy "
            f"{m['numpy']}, numba {m['numba']}, scipy {m['scipy']}, pyarrow {m['pyarrow']}, "
            f"NUMBA_NUM_THREADS={m['numba_num_threads']}")


def record(name: str, metrics: dict, settings: dict) -> Path | None:
    """The figures of one benchmark: written to ``DIR/NAME.json`` under the run's
    ``--results DIR`` (nothing without it), with the settings, the machine and the
    command. Returns the file written, if any."""
    if _RESULTS_DIR is None:
        return None
    _RESULTS_DIR.mkdir(parents=True, exist_ok=True)
    path = _RESULTS_DIR / f"{name}.json"
    payload = {
        "benchmark": name,
        "command": _COMMAND or shlex.join([Path(sys.executable).name, *sys.argv]),
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d"),
        "machine": machine(),
        "settings": settings,
        "metrics": metrics,
    }
    path.write_text(json.dumps(payload, indent=2, sort_keys=False) + "\n")
    print(f"results: {path}")
    return path


def load_results(directory: Path) -> dict[str, dict]:
    """Every ``NAME.json`` of a results directory, by name."""
    return {p.stem: json.loads(p.read_text()) for p in sorted(Path(directory).glob("*.json"))}


def runs(package: str) -> dict[str, str]:
    """The runs of a folder: ``{name: module}``, a ``bench_`` prefix dropped from the
    name."""
    folder = Path(importlib.import_module(package).__file__).parent
    found = {}
    for info in pkgutil.iter_modules([str(folder)]):
        if info.name in NOT_RUNS or info.name.startswith("_"):
            continue
        found[info.name.removeprefix("bench_")] = f"{package}.{info.name}"
    return dict(sorted(found.items()))


def main(package: str, argv: list[str] | None = None, doc: str = "") -> int:
    """``python -m PACKAGE [--results DIR] [--quick] NAME|all|list [ARGS...]``."""
    global _RESULTS_DIR, _COMMAND
    parser = argparse.ArgumentParser(
        prog=f"python -m {package}", description=doc,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--results", type=Path, metavar="DIR",
                        help="write each run's figures to DIR/NAME.json")
    parser.add_argument("--quick", action="store_true",
                        help="small sizes (each module's QUICK_ARGS): a smoke test, or a "
                             "results set on a busy machine")
    parser.add_argument("name", help="a run's name, 'all' or 'list'")
    parser.add_argument("args", nargs=argparse.REMAINDER,
                        help="the run's own arguments (NAME --help lists them)")
    args = parser.parse_args(argv)
    table = runs(package)
    if args.name == "list":
        for name, module in table.items():
            first = (importlib.import_module(module).__doc__ or "").strip().splitlines()
            print(f"{name:<28} {first[0] if first else ''}")
        return 0
    if args.name == "all":
        if args.args:
            parser.error("'all' takes no arguments of its own; use --quick or one NAME")
        # A run that needs arguments of its own (IN_ALL = False) is left out; with --quick,
        # so is a run with no small size (no QUICK_ARGS).
        names = []
        for name, module_name in table.items():
            module = importlib.import_module(module_name)
            if not getattr(module, "IN_ALL", True):
                continue
            if args.quick and not hasattr(module, "QUICK_ARGS"):
                print(f"-- {name}: no quick size, left out")
                continue
            names.append(name)
    elif args.name in table:
        names = [args.name]
    else:
        parser.error(f"no run named {args.name!r}; 'python -m {package} list' lists them")
    _RESULTS_DIR = args.results
    status = 0
    for name in names:
        module = importlib.import_module(table[name])
        run_args = list(args.args)
        if args.quick:
            run_args = list(getattr(module, "QUICK_ARGS", [])) + run_args
        _COMMAND = shlex.join(["python", "-m", package, name, *run_args])
        print(f"== {package} {name}: {_COMMAND}", flush=True)
        # argparse names the program after argv[0]: the command, not __main__.py.
        sys.argv = [f"python -m {package} {name}", *run_args]
        code = module.main(run_args)
        status = status or (code or 0)
    return status
