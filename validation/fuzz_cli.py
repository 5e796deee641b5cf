"""Fuzz every ``mcbat`` command with generated inputs; the contract it checks:

* the exit code is 0 or 2 (also from ``mcbat check`` on a dataset it finds damaged: bad
  input to every command that reads it), never 1 or anything else;
* no input runs longer than ``--timeout`` seconds of CPU time (a hang; a wall-clock limit
  of ten times that catches an input that blocks without computing);
* an error is one line on stderr, without a traceback;
* every exit-0 answer that promises JSON is strict JSON (no NaN or Infinity) without
  ``null`` where a number is promised (``stick_impulse`` and ``stick_criterion`` of an
  impact that never stuck are documented as null), a synthetic table has finite numbers
  only, and a finished ``mcbat run`` leaves a dataset ``mcbat check`` finds complete.

Inputs are mutations of valid ones (the shipped examples and studies, small tables and
datasets): numbers replaced by extremes (0, -1, 1e-300, 1e300, 2**64, NaN, inf, huge
integers), strings by empty, control or overlong ones, keys dropped or added, flags given
odd values, paths spelled in every form (relative, ``file:``, ``local://``, other schemes),
datasets damaged (chunks removed, truncated, flipped, foreign files, odd manifests).
Everything runs in-process (``mcbat.cli.main``), one input after the other, under
``nice`` if asked; each input gets an alarm of ``--timeout`` seconds.

    nice -n 19 .venv/bin/python -m validation fuzz_cli --n 10000 --seed 1 --report fuzz.json

Prints a table of inputs and exit codes per command, the slowest input, and every
violation (command line and the first lines of its output); exits 1 if there is any.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import os
import random
import shutil
import signal
import sys
import tempfile
import time
import tomllib
from collections import Counter, defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from mcbat.cli import main as cli_main  # noqa: E402

EXAMPLES = {name: json.loads((ROOT / "examples" / name).read_text())
            for name in ("cabo2012_sec5.json", "game_fastball.json")}
STUDIES = {name: (ROOT / "studies" / name).read_text()
           for name in ("example.toml", "game_fastball.toml", "cross_nathan_2006.toml")}
NUMBERS = [0, -0.0, -1, 1, 0.5, 1e-300, 5e-324, 1e-9, 1e20, 1e300, -1e300, 2**63, 2**64,
           -2**63, 10**400, float("nan"), float("inf"), -float("inf"), 36600.0, 2e10, 1e6]
TEXTS = ["", " ", "\x00", "\x85", "\u2028", "\u202e", "../x", "x" * 5000, "é", "\ufeff",
         "nan", "1e400", "0x10", "-", "--", "a,b", "\n"]
FLAG_VALUES = ["0", "-1", "1", "7", "abc", "1e3", "2", "18446744073709551616",
               "9223372036854775807", "", " ", "nan", "inf", "-inf", "1e-9", "1e300", "0.5",
               "1e20", "\x85", "1000", "100", "3"]
JSON_NULL_OK = {"stick_impulse", "stick_criterion"}


#: The wall-clock limit of an input, in multiples of ``--timeout`` (CPU seconds).
WALL_FACTOR = 10


class Hang(BaseException):
    """Raised by the alarm: a BaseException, so that the CLI's error handling (which maps
    every Exception to an exit code) does not swallow it."""


def _alarm(signum, frame):
    raise Hang()


# ------------------------------------------------------------------------ mutation

def _paths(tree, prefix=()):
    out = []
    items = tree.items() if isinstance(tree, dict) else enumerate(tree) \
        if isinstance(tree, list) else ()
    for key, value in items:
        out.append(prefix + (key,))
        out.extend(_paths(value, prefix + (key,)))
    return out


def _value(rng):
    kind = rng.random()
    if kind < 0.3:  # a plausible value: more inputs get past validation into the solvers
        return rng.choice([1, -1]) * 10 ** rng.uniform(-4, 3)
    if kind < 0.6:
        return rng.choice(NUMBERS)
    if kind < 0.7:
        return rng.choice(TEXTS)
    if kind < 0.8:
        return rng.choice([True, None, [], {}, [1, 2], {"value": rng.choice(NUMBERS),
                                                          "unit": rng.choice(
                                                              ["mph", "m", "rpm", "deg",
                                                               "furlong", ""])}])
    return rng.uniform(-1e3, 1e3) * 10 ** rng.randint(-12, 12)


def mutate(tree, rng, n=None):
    """A copy of a JSON/TOML tree with 1-3 random edits."""
    tree = json.loads(json.dumps(tree))
    for _ in range(n or rng.randint(1, 3)):
        paths = _paths(tree)
        if not paths:
            break
        path = rng.choice(paths)
        parent = tree
        for key in path[:-1]:
            parent = parent[key]
        action = rng.random()
        if action < 0.7:
            parent[path[-1]] = _value(rng)
        elif action < 0.85 and isinstance(parent, dict):
            del parent[path[-1]]
        elif isinstance(parent, dict):
            parent[rng.choice(["colour", "x", path[-1] + "_", ""])] = _value(rng)
    return tree


def _toml_value(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value if v is not None) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{json.dumps(k)} = {_toml_value(v)}"
                               for k, v in value.items() if v is not None) + "}"
    return '""'


def to_toml(tree):
    """TOML text of a study tree (tables of scalars and inline tables)."""
    lines = []
    for key, value in tree.items():
        if not isinstance(value, dict):
            if value is not None:
                lines.append(f"{json.dumps(key)} = {_toml_value(value)}")
    for key, value in tree.items():
        if isinstance(value, dict):
            lines.append(f"[{json.dumps(key)}]")
            for k, v in value.items():
                if v is not None:
                    lines.append(f"{json.dumps(k)} = {_toml_value(v)}")
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------ inputs

class Inputs:
    """Generates one command line (and its files) at a time in a scratch directory."""

    def __init__(self, rng, scratch: Path):
        self.rng, self.scratch = rng, scratch
        self.counter = 0
        self.studies = {name: tomllib.loads(text) for name, text in STUDIES.items()}
        self.datasets = []  # complete small datasets to damage

    def path(self, suffix):
        self.counter += 1
        return self.scratch / f"in{self.counter}{suffix}"

    def study_file(self, mutated=True, small=True):
        rng = self.rng
        name = rng.choice(list(self.studies))
        tree = json.loads(json.dumps(self.studies[name]))
        if small:
            tree.setdefault("study", {})["samples"] = rng.choice([1, 50, 300])
        if mutated and rng.random() < 0.8:
            tree = mutate(tree, rng)
        path = self.path(".toml")
        if rng.random() < 0.05:
            path.write_bytes(rng.choice([b"\xff\xfe[", b"[study\n", b"x = 1\n" * 3,
                                         "[study]\nname = \"a\u202eb\"\nsamples = 3\n".encode()]))
        else:
            path.write_text(to_toml(tree))
        return path

    def out_spelling(self):
        rng = self.rng
        base = self.scratch / f"out{self.counter}"
        if rng.random() < 0.6:
            return str(base)
        return rng.choice([str(base), f"file://{base}", f"file:{base}", f"local://{base}",
                           f"out{self.counter}", f"run:{self.counter}", "", "dir:///x",
                           "data://x", "reference://x", "nosuch://x/y", "memory://x/y",
                           f"file://elsewhere{base}", f"{base}?x=1", "s3://"])

    def flags(self, names, p=0.3):
        rng = self.rng
        out = []
        for name in names:
            if rng.random() < p:
                out += [name, rng.choice(FLAG_VALUES)]
        return out

    # one generator per command
    def impact(self):
        rng = self.rng
        case = mutate(EXAMPLES[rng.choice(list(EXAMPLES))], rng)
        path = self.path(".json")
        text = json.dumps([case, case] if rng.random() < 0.1 else case)
        path.write_text(text)
        return ["impact", str(path), *self.flags(["--tolerance"])]

    def flight(self):
        rng = self.rng
        case = {"launch_speed": {"value": rng.uniform(40, 120), "unit": "mph"},
                "launch_angle": {"value": rng.uniform(-10, 60), "unit": "deg"},
                "backspin": {"value": rng.uniform(0, 3000), "unit": "rpm"}}
        if rng.random() < 0.5:
            case["ball"] = {"mass": 0.145, "radius": 0.0366}
        case = mutate(case, rng) if rng.random() < 0.85 else case
        path = self.path(".json")
        path.write_text(json.dumps(case))
        extra = []
        if rng.random() < 0.4:
            extra = ["--trajectory", rng.choice(["0.1", "1e-6", "0", "-1", "nan", "1e300",
                                                 "0.01", "inf", "1e-3"])]
        if rng.random() < 0.2:
            extra += ["--scheme", rng.choice(["adaptive", "sheet", "x"])]
        return ["flight", str(path), *extra]

    def run(self):
        rng = self.rng
        study = self.study_file(mutated=rng.random() < 0.35)
        argv = ["run", str(study), "--quiet", "--out", self.out_spelling()]
        argv += self.flags(["--seed", "--threads", "--chunk-size", "--tolerance"], p=0.12)
        if rng.random() < 0.4:
            argv += ["--samples", rng.choice(["0", "-1", "1", "200", "abc", "10000000000000",
                                             "18446744073709551616", "1e3"])]
        if rng.random() < 0.1:
            argv += ["--columns", rng.choice(["status", "exit_speed,status", "nope", ",",
                                              ""])]
        if rng.random() < 0.1:
            argv.append(rng.choice(["--overwrite", "--summary-only"]))
        return argv

    def dataset(self):
        """A small complete dataset (made once in a while), copied for damage."""
        rng = self.rng
        if len(self.datasets) < 3 or rng.random() < 0.02:
            out = self.scratch / f"ds{len(self.datasets)}"
            with contextlib.redirect_stdout(io.StringIO()):
                code = cli_main(["run", str(ROOT / "studies" / "example.toml"), "--out",
                             str(out), "--samples", "900", "--chunk-size", "300", "--quiet",
                             "--seed", str(len(self.datasets))])
            if code == 0:
                self.datasets.append(out)
        source = rng.choice(self.datasets)
        copy = self.path("")
        shutil.copytree(source, copy)
        return copy

    def check(self):
        rng = self.rng
        where = self.dataset() if rng.random() < 0.8 else Path(rng.choice(
            ["/nonexistent/x", str(self.scratch), "dir:///x", "", "file:/nonexistent"]))
        if isinstance(where, Path) and where.is_dir() and (where / "_mcbat.json").exists():
            damage = rng.choice(["none", "remove", "truncate", "flip", "foreign", "dir",
                                 "manifest", "files", "deep", "summary_only"])
            chunk = where / "chunk-000001.parquet"
            manifest = where / "_mcbat.json"
            if damage == "remove":
                chunk.unlink()
            elif damage == "truncate":
                chunk.write_bytes(chunk.read_bytes()[:rng.randint(0, 2000)])
            elif damage == "flip":
                data = bytearray(chunk.read_bytes())
                i = rng.randrange(len(data))
                data[i] ^= 0xFF
                chunk.write_bytes(bytes(data))
            elif damage == "foreign":
                shutil.copy(chunk, where / "chunk-000001 (copy).parquet")
            elif damage == "dir":
                (where / "chunk-000009.parquet").mkdir()
            elif damage in ("manifest", "files", "summary_only"):
                tree = json.loads(manifest.read_text())
                if damage == "manifest":
                    tree = mutate(tree, rng)
                elif damage == "files":
                    tree["files"] = rng.choice([[], None, "x", 3, {"a": 1}])
                else:
                    tree["summary_only"] = True
                manifest.write_text(json.dumps(tree))
            elif damage == "deep":
                manifest.write_text("[" * 100_000 + "]" * 100_000)
        argv = ["check", str(where)]
        if rng.random() < 0.3:
            argv.append("--quick")
        return argv

    def table(self, game):
        rng = self.rng
        n = rng.randint(3, 8)
        if game:
            cols = {"launch_speed": [rng.uniform(80, 110) for _ in range(n)],
                    "launch_angle": [rng.uniform(-10, 40) for _ in range(n)],
                    "spray_angle": [rng.uniform(-30, 30) for _ in range(n)]}
        else:
            cols = {"impact_parameter": [rng.uniform(-0.02, 0.02) for _ in range(n)],
                    "spin_in": [79.0] * n,
                    "exit_speed": [rng.uniform(1.3, 1.7) for _ in range(n)],
                    "scattering_angle": [rng.uniform(-20, 20) for _ in range(n)],
                    "spin_out": [rng.uniform(20, 40) for _ in range(n)]}
        if rng.random() < 0.8:
            name = rng.choice(list(cols))
            cols[name][rng.randrange(n)] = rng.choice(NUMBERS + ["x", ""])
        path = self.path(".csv")
        header = list(cols)
        rows = [",".join(str(cols[c][i]) for c in header) for i in range(n)]
        path.write_text(",".join(header) + "\n" + "\n".join(rows) + "\n")
        return path

    def synth(self):
        rng = self.rng
        study = rng.choice(["cross_nathan_2006.toml", "game_fastball.toml"])
        argv = ["synth", "--study", str(ROOT / "studies" / study), "--rows",
                rng.choice(["3", "5", "0", "-2", "x", "100000000000"])]
        argv += self.flags(["--seed", "--e", "--mu", "--e-x", "--speed-noise",
                            "--angle-noise", "--spin-noise", "--impact-parameter-noise",
                            "--spin-in-noise"], p=0.1)
        if rng.random() < 0.1:
            argv += ["--input-noise", rng.choice(["undercut=0.002", "undercut=inf",
                                                  "x=1", "undercut", "bat_speed=1e300"])]
        if rng.random() < 0.3:
            argv += ["--out", str(self.path(rng.choice([".csv", ".parquet", ".txt"])))]
        return argv

    def fit(self):
        rng = self.rng
        game = rng.random() < 0.3
        study = ROOT / "studies" / ("game_fastball.toml" if game else
                                    "cross_nathan_2006.toml")
        argv = ["fit", "--study", str(study), "--data", str(self.table(game)),
                "--free", rng.choice(["e", "mu", "e,mu", "e_x", "x", ""] if not game
                                     else ["e", "e_x", "x"]),
                "--intervals", "curvature", "--no-compare", "--draws",
                rng.choice(["4", "8", "3", "0"])]
        argv += self.flags(["--seed", "--bootstrap"])
        if rng.random() < 0.5:
            argv.append("--json")
        return argv

    def calibrate(self):
        rng = self.rng
        if rng.random() < 0.5:
            return ["calibrate", *self.flags(["--target"])]
        study = rng.choice(["cross_nathan_2006.toml", "game_fastball.toml"])
        return ["calibrate", "--study", str(ROOT / "studies" / study), "--samples",
                rng.choice(["50", "0", "-1", "x", "100"]), "--target",
                rng.choice(["1.4", "95", "nan", "inf", "-1", "1e300", "0"]),
                *(["--parameter", rng.choice(["e", "mu", "e_x", "x"])]
                  if rng.random() < 0.3 else [])]

    def argv_noise(self):
        rng = self.rng
        command = rng.choice(["run", "check", "impact", "flight", "synth", "fit",
                              "calibrate", "reproduce", "nope", "--version", "-h"])
        tail = [rng.choice(FLAG_VALUES + ["--out", "--seed", "--samples"])
                for _ in range(rng.randint(0, 3))]
        if command == "reproduce":  # only refusals: a valid reproduction is minutes of work
            tail = [rng.choice(["--samples", "--threads"]),
                    rng.choice(["0", "-1", "abc", "18446744073709551616", ""])]
        return [command, *tail]


#: Inputs per command, relative (fit and calibrate cost seconds each).
WEIGHTS = {"impact": 28, "flight": 18, "run": 20, "check": 14, "synth": 8, "fit": 2,
           "calibrate": 1, "argv_noise": 8}


# ------------------------------------------------------------------------ checking

def _strict(text):
    def refuse(name):
        raise ValueError(f"non-finite number {name}")
    return json.loads(text, parse_constant=refuse)


def _nulls(value, key=None):
    if value is None:
        return [] if key in JSON_NULL_OK else [key]
    if isinstance(value, dict):
        return [n for k, v in value.items() for n in _nulls(v, k)]
    if isinstance(value, list):
        return [n for v in value for n in _nulls(v, key)]
    return []


def judge(command, argv, code, stdout, stderr):
    """The violations of one input (empty when it keeps the contract)."""
    bad = []
    if code not in (0, 2):
        bad.append(f"exit {code}")
    if "Traceback" in stderr:
        bad.append("traceback")
    if code == 2 and len(stderr.strip().splitlines()) != 1:
        bad.append(f"{len(stderr.strip().splitlines())} lines on stderr")
    if code == 0 and command in ("impact", "flight", "calibrate") or (
            code == 0 and command == "fit" and "--json" in argv):
        try:
            nulls = _nulls(_strict(stdout))
            if nulls:
                bad.append(f"null for {sorted(set(map(str, nulls)))[:4]}")
        except ValueError as err:
            bad.append(f"not strict JSON: {err}")
    if code == 0 and command == "synth" and "--out" not in argv:
        import pandas as pd

        table = pd.read_csv(io.StringIO(stdout))
        if not len(table) or not all(pd.api.types.is_numeric_dtype(t)
                                     for t in table.dtypes) or not table.map(
                                         math.isfinite).all().all():
            bad.append("synthetic table with non-finite values or no rows")
    if code == 0 and command == "run":
        out = argv[argv.index("--out") + 1]
        import mcbat

        try:
            result = mcbat.check(out)
            if not result.ok:
                bad.append("run exit 0 but check: " + "; ".join(result.problems())[:200])
        except Exception as err:  # noqa: BLE001
            bad.append(f"run exit 0 but check raised {type(err).__name__}: {err}"[:200])
    return bad


def run_one(argv, timeout):
    stdout, stderr = io.StringIO(), io.StringIO()
    stdin = io.TextIOWrapper(io.BytesIO(b""))
    # A hang is counted in this process's CPU time (every thread's): on a machine shared
    # with other jobs, under nice -n 19, wall time says more about the neighbours than
    # about mcbat. Input that blocks without computing (a network wait) is caught by the
    # wall clock, at WALL_FACTOR times the limit.
    signal.signal(signal.SIGPROF, _alarm)
    signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_PROF, timeout)
    signal.alarm(timeout * WALL_FACTOR)
    t0 = time.perf_counter()
    old_stdin = sys.stdin
    try:
        sys.stdin = stdin
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
            code = cli_main(argv)
    except Hang:
        code = "hang"
    except SystemExit as err:
        code = err.code if isinstance(err.code, int) else 1
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.alarm(0)
        sys.stdin = old_stdin
    return code, stdout.getvalue(), stderr.getvalue(), time.perf_counter() - t0


def warm_up(scratch: Path):
    """One valid input of each command, untimed: the first call of a command loads its
    compiled kernels (seconds; minutes on a loaded machine), which is not a hang."""
    flight = scratch / "warm_flight.json"
    flight.write_text(json.dumps({"launch_speed": 45, "launch_angle": 0.5}))
    drop, game = ROOT / "studies" / "cross_nathan_2006.toml", ROOT / "studies" / \
        "game_fastball.toml"
    table = scratch / "warm_table.csv"
    for argv in (["impact", str(ROOT / "examples" / "cabo2012_sec5.json")],
                 ["impact", str(ROOT / "examples" / "game_fastball.json")],
                 ["flight", str(flight)],
                 ["run", str(ROOT / "studies" / "example.toml"), "--samples", "50",
                  "--quiet", "--out", str(scratch / "warm_run")],
                 ["run", str(game), "--samples", "50", "--quiet", "--out",
                  str(scratch / "warm_game")],
                 ["synth", "--study", str(drop), "--rows", "5", "--out", str(table)],
                 ["fit", "--study", str(drop), "--data", str(table), "--free", "e",
                  "--intervals", "curvature", "--no-compare", "--draws", "4"]):
        with contextlib.redirect_stdout(io.StringIO()), \
                contextlib.redirect_stderr(io.StringIO()):
            cli_main(argv)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=10_000, help="inputs (default 10,000)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=int, default=60,
                        help="CPU seconds per input (wall clock: 10x)")
    parser.add_argument("--report", type=Path, help="write the results as JSON")
    args = parser.parse_args(argv)
    rng = random.Random(args.seed)
    commands = list(WEIGHTS)
    weights = [WEIGHTS[c] for c in commands]
    codes = defaultdict(Counter)
    violations = []
    slowest = (0.0, None)
    seconds = Counter()
    t_start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="mcbat-fuzz-") as scratch:
        cwd = os.getcwd()
        os.chdir(scratch)  # relative --out spellings land in the scratch directory
        try:
            inputs = Inputs(rng, Path(scratch))
            warm_up(Path(scratch))
            for i in range(args.n):
                command = rng.choices(commands, weights)[0]
                try:
                    argv_i = getattr(inputs, command)()
                except Exception as err:  # noqa: BLE001 - the generator's own failure
                    violations.append({"i": i, "command": command, "argv": None,
                                       "problems": [f"generator: {err!r}"]})
                    continue
                code, out, err, dt = run_one(argv_i, args.timeout)
                name = command if command != "argv_noise" else "(any)"
                codes[name][str(code)] += 1
                seconds[name] += dt
                if dt > slowest[0]:
                    slowest = (dt, argv_i)
                problems = judge(argv_i[0] if command == "argv_noise" else command, argv_i,
                                 code, out, err)
                if code == "hang":
                    problems = [f"hang over {args.timeout} s"]
                if problems:
                    violations.append({"i": i, "command": command, "argv": argv_i,
                                       "problems": problems,
                                       "stderr": err.strip().splitlines()[-3:],
                                       "stdout": out[:300]})
                    print(f"violation #{i} {command}: {problems}: {argv_i}: "
                          f"{err.strip().splitlines()[-1:]}", flush=True)
                if (i + 1) % 100 == 0:
                    if args.report:  # a run stopped early still leaves its numbers
                        _write_report(args, i + 1, time.perf_counter() - t_start, codes,
                                      slowest, violations)
                    print(f"{i + 1:,} inputs, {len(violations)} violations, "
                          f"{time.perf_counter() - t_start:.0f} s, exit codes "
                          f"{dict(sum(codes.values(), Counter()))}, slowest "
                          f"{slowest[0]:.1f} s", flush=True)
                # keep the scratch directory small
                for path in Path(scratch).glob("in*"):
                    if path.is_dir() and path.name != "in" and rng.random() < 0.5:
                        shutil.rmtree(path, ignore_errors=True)
        finally:
            os.chdir(cwd)
    total = time.perf_counter() - t_start
    print(f"\n{args.n:,} inputs in {total:.0f} s (seed {args.seed}, timeout {args.timeout} s)")
    print(f"{'command':<12}{'inputs':>8}  exit codes{'':<20}seconds")
    for name in sorted(codes):
        n = sum(codes[name].values())
        spread = ", ".join(f"{k}: {v}" for k, v in sorted(codes[name].items()))
        print(f"{name:<12}{n:>8}  {spread:<30}{seconds[name]:.0f}")
    all_codes = Counter()
    for counter in codes.values():
        all_codes.update(counter)
    print(f"all exit codes: {dict(sorted(all_codes.items()))}")
    print(f"slowest input: {slowest[0]:.1f} s: {slowest[1]}")
    print(f"violations: {len(violations)}")
    for v in violations[:40]:
        print(f"  #{v['i']} {v['command']}: {v['problems']}: {v['argv']}\n"
              f"      {v.get('stderr')}")
    if args.report:
        _write_report(args, args.n, total, codes, slowest, violations)
    return 1 if violations else 0


def _write_report(args, done, seconds, codes, slowest, violations):
    args.report.write_text(json.dumps({
        "n": args.n, "done": done, "seed": args.seed, "timeout": args.timeout,
        "seconds": seconds, "codes": {k: dict(v) for k, v in codes.items()},
        "slowest": [slowest[0], slowest[1]], "violations": violations}, indent=1,
        default=str))


if __name__ == "__main__":
    sys.exit(main())
