"""Fuzz mcbat's Statcast surfaces with generated files; the contract it checks:

* the exit code is 0 or 2, never 1 or anything else;
* no input runs longer than ``--timeout`` seconds of CPU time (ten times that of wall
  clock catches an input that blocks without computing: a FIFO, a device);
* an error is one line on stderr, without a traceback;
* a success prints no ``nan`` or ``inf`` (text or JSON), its JSON is strict, and its
  stderr holds no Python warning.

The surfaces: ``mcbat statcast`` (text, ``--json``, ``--out``, ``--strict``), ``mcbat
infer``, ``mcbat compare`` (with ``--units``, ``--columns``, ``--permutations``), ``mcbat
fit --flight``, ``mcbat fit`` of a game study and ``--population`` on a Savant export, a
game study's ``[pitches]`` file (``mcbat run``), ``mcbat reproduce statcast``, and
``mcbat impact`` game cases with extreme balls. Their files are mutations of real exports
(``data/statcast_2020-09-03.csv``, ``data/statcast_2024_ohtani.csv`` when present): cells
replaced by extremes (1e20, -1, 2**64, 1.5 in an identifier, NaN, inf, text), columns
dropped, rows repeated (with and without their header), files cut short, CRLF and BOM,
UTF-16, binary noise, gzip (and a gzip bomb), Parquet (also named ``.csv``), units off by
a factor (m/s for mph), constant distances, and paths that are no regular file (a FIFO,
``/dev/zero``, a directory, a symbolic link to a device).

Input ``i`` is generated from ``random.Random(f"{seed}-{i}")`` alone, so any violation
reproduces with ``--only I`` whatever the number of workers. ``--workers N`` runs N
processes (each input in-process through ``mcbat.cli.main``, with an alarm).

    nice -n 19 .venv/bin/python -m validation fuzz_statcast --n 10000 --workers 2 --seed 1

Prints the inputs and exit codes per surface, the slowest input and every violation;
exits 1 if there is any.
"""

from __future__ import annotations

import argparse
import contextlib
import gzip
import io
import json
import math
import multiprocessing
import os
import random
import re
import shutil
import sys
import tempfile
import time
from collections import Counter, defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from validation.fuzz_cli import _nulls, _strict, run_one  # noqa: E402

BASE = ROOT / "data" / "statcast_2020-09-03.csv"
TRACKED = ROOT.parent / "shared" / "data" / "statcast" / "statcast_2024_ohtani.csv"
NUMBERS = ["0", "-1", "1e20", "-1e20", "1e308", "1e-300", "nan", "inf", "-inf",
           "18446744073709551616", "9223372036854775808", "1.5", "2e9", "abc", "", "null",
           "True", " 7 ", "0x10", "1e400", "-0", "\x00", "é"]
IDENTIFIERS = ("game_pk", "at_bat_number", "pitch_number", "batter", "pitcher")
NUMERIC = ("release_speed", "launch_speed", "launch_angle", "hit_distance_sc", "hc_x",
           "hc_y", "vx0", "vy0", "vz0", "ax", "ay", "az", "release_spin_rate", "plate_x",
           "plate_z", "game_year", "spin_axis", "bat_speed", "attack_angle", "hit_location")
#: A printed non-finite number as Python writes it (nan, inf, -inf; not inside a word like
#: "infer"; prose says "NaN", and JSON's NaN/Infinity fail the strict-JSON check).
NON_FINITE = re.compile(r"(?<![\w.])[-+]?(nan|inf)(?![\w])")
#: Quoted text (an echo of the user's cell, "-inf"), not a number mcbat computed.
QUOTED = re.compile(r"'[^'\n]*'|\"[^\"\n]*\"")
#: Inputs per surface, relative (fit, infer and reproduce cost seconds each).
WEIGHTS = {"statcast": 45, "compare": 14, "infer": 8, "pitches": 12, "fit_flight": 6,
           "fit_game": 2, "population": 1, "reproduce": 1, "impact": 11}


# ------------------------------------------------------------------------ base tables

def _base_rows(path, rows, seed=0):
    """The header and ``rows`` rows of an export (every ball in play among the first
    lines kept, so that the small files still have balls to infer and fly)."""
    import csv

    with open(path, newline="", encoding="utf-8-sig") as handle:
        table = list(csv.reader(handle))
    header, body = table[0], table[1:]
    description = header.index("description")
    in_play = [r for r in body if r[description].startswith("hit_into_play")]
    other = [r for r in body if not r[description].startswith("hit_into_play")]
    rng = random.Random(seed)
    chosen = in_play[: rows * 2 // 3] + rng.sample(other, min(len(other), rows // 3))
    return header, chosen


class Files:
    """Generates the files of one input in a scratch directory."""

    def __init__(self, rng, scratch: Path, bases):
        self.rng, self.scratch, self.bases = rng, scratch, bases
        self.counter = 0

    def path(self, suffix):
        self.counter += 1
        return self.scratch / f"in{self.counter}{suffix}"

    def rows(self):
        header, body = self.rng.choice(self.bases)
        return list(header), [list(r) for r in body]

    def export(self):
        """A mutated export, as CSV text, or a special path."""
        rng = self.rng
        header, body = self.rows()
        kind = rng.random()
        if kind < 0.06:
            return self.special()
        if kind < 0.14:
            return self.binary()
        for _ in range(rng.randint(0, 3)):
            self.mutate(header, body)
        text = _csv_text(header, body)
        extra = rng.random()
        if extra < 0.08:  # two overlapping downloads
            cut = rng.randint(0, len(body))
            text = text + _csv_text(header if rng.random() < 0.5 else None, body[cut:])
        elif extra < 0.12:
            text = text[: rng.randint(0, len(text))]
        elif extra < 0.15:
            text = text.replace("\n", "\r\n")
        elif extra < 0.17:
            text = "\ufeff" + text
        elif extra < 0.19:
            text = text.replace("\n", "\n\n", rng.randint(1, 5))
        form = rng.random()
        if form < 0.07:
            path = self.path(".csv.gz")
            path.write_bytes(gzip.compress(text.encode()))
        elif form < 0.12:
            path = self.path(rng.choice([".parquet", ".csv"]))
            try:
                self.parquet(text, path)
            except Exception:  # noqa: BLE001 - a text pandas cannot read: write it as text
                path.write_text(text)
        elif form < 0.14:
            path = self.path(".csv")
            path.write_bytes(text.encode("utf-16"))
        else:
            path = self.path(".csv")
            path.write_text(text, newline="")
        return path

    def mutate(self, header, body):
        if not body:
            return
        if self.rng.random() < 0.72:
            self.mutate_values(header, body)
        else:
            self.mutate_shape(header, body)

    def mutate_values(self, header, body):
        rng = self.rng
        what = rng.random() * 0.72
        if what < 0.45:  # a cell
            column = rng.choice([c for c in (*NUMERIC, *IDENTIFIERS) if c in header]
                                if rng.random() < 0.85 else header)
            j = header.index(column)
            for row in rng.sample(body, min(len(body), rng.choice([1, 1, 2, len(body)]))):
                if j < len(row):
                    row[j] = rng.choice(NUMBERS)
        elif what < 0.55:  # a column dropped
            j = rng.randrange(len(header))
            del header[j]
            for row in body:
                if j < len(row):
                    del row[j]
        elif what < 0.65:  # a column scaled (another unit)
            column = rng.choice(["launch_speed", "hit_distance_sc", "launch_angle",
                                 "release_speed", "bat_speed"])
            if column in header:
                j = header.index(column)
                factor = rng.choice([0.44704, 1.609, 0.3048, 0.01745, 1000.0, -1.0])
                for row in body:
                    if j < len(row):
                        row[j] = _scaled(row[j], factor)
        else:  # one value for every row
            column = rng.choice(["hit_distance_sc", "launch_speed", "launch_angle"])
            if column in header:
                j = header.index(column)
                for row in body:
                    if j < len(row) and row[j] not in ("", "null"):
                        row[j] = rng.choice(["350", "0", "90"])

    def mutate_shape(self, header, body):
        rng = self.rng
        what = 0.72 + rng.random() * 0.28
        if what < 0.8:  # rows repeated
            body.extend(rng.sample(body, rng.randint(1, len(body))))
        elif what < 0.86:  # a row too short or too long
            row = rng.choice(body)
            if rng.random() < 0.5:
                del row[rng.randrange(len(row)):]
            else:
                row.append("x")
        elif what < 0.9:  # the header repeated inside
            body.insert(rng.randrange(len(body) + 1), list(header))
        elif what < 0.95:  # no rows
            del body[rng.randint(0, min(len(body), 3)):]
        else:  # a cell with a quote, a comma or a line break
            row = rng.choice(body)
            row[rng.randrange(len(row))] = rng.choice(['"', "a,b", "a\nb", "\x85", "\u2028"])

    def parquet(self, text, path):
        import pandas as pd

        frame = pd.read_csv(io.StringIO(text), low_memory=False)
        if self.rng.random() < 0.5:
            from mcbat.statcast import read, write

            write(read(frame), path)  # a tidy table
        else:
            frame.to_parquet(path)

    def special(self):
        rng = self.rng
        kind = rng.choice(["fifo", "zero", "null", "dir", "link", "missing", "empty",
                           "header"])
        if kind == "fifo":
            path = self.path(".csv")
            os.mkfifo(path)
            return path
        if kind == "zero":
            return Path("/dev/zero")
        if kind == "null":
            return Path("/dev/null")
        if kind == "dir":
            path = self.path(".csv")
            path.mkdir()
            return path
        if kind == "link":
            path = self.path(".csv")
            path.symlink_to("/dev/zero")
            return path
        if kind == "missing":
            return self.path(".csv")
        path = self.path(".csv")
        header, _ = self.rows()
        path.write_text("" if kind == "empty" else ",".join(header) + "\n")
        return path

    def binary(self):
        rng = self.rng
        path = self.path(rng.choice([".csv", ".csv.gz", ".parquet"]))
        kind = rng.random()
        if kind < 0.3:
            path.write_bytes(bytes(rng.randrange(256) for _ in range(rng.randint(1, 4000))))
        elif kind < 0.5:  # a gzip bomb: a few hundred kB of zeros that expand to 100 MB
            path.write_bytes(_bomb())
        elif kind < 0.7:
            path.write_bytes(b"PAR1" + bytes(rng.randrange(256) for _ in range(200)))
        elif kind < 0.85:
            path.write_bytes(b"\x1f\x8b" + bytes(rng.randrange(256) for _ in range(300)))
        else:
            path.write_bytes(b"x" * rng.choice([10, 70_000, 17 << 20]))
        return path


_BOMB = None


def _bomb():
    global _BOMB
    if _BOMB is None:
        _BOMB = gzip.compress(b"0" * (100 << 20), 9)
    return _BOMB


def _scaled(cell, factor):
    try:
        value = float(cell)
    except ValueError:
        return cell
    return f"{value * factor:.6g}" if math.isfinite(value) else cell


def _csv_text(header, body):
    import csv

    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    if header is not None:
        writer.writerow(header)
    writer.writerows(body)
    return out.getvalue()


# ------------------------------------------------------------------------ inputs

class Inputs:
    """One command line per call of a surface, with its files."""

    def __init__(self, rng, scratch, bases, dataset):
        self.rng, self.scratch, self.dataset = rng, scratch, dataset
        self.files = Files(rng, scratch, bases)

    def statcast(self):
        rng = self.rng
        argv = ["statcast", str(self.files.export())]
        if rng.random() < 0.4:
            argv.append("--json")
        if rng.random() < 0.2:
            argv.append("--strict")
        if rng.random() < 0.15:
            argv += ["--out", str(self.files.path(rng.choice([".parquet", ".csv"])))]
        return argv

    def compare(self):
        rng = self.rng
        argv = ["compare", str(self.dataset), str(self.files.export()),
                "--permutations", rng.choice(["0", "10", "30"]), "--plane-rows",
                rng.choice(["50", "200"])]
        if rng.random() < 0.3:
            argv += ["--units", rng.choice(["launch_speed=m/s", "launch_speed=mph",
                                            "launch_angle=rad", "hit_distance=m",
                                            "launch_speed=km/h", "launch_speed=deg"])]
        if rng.random() < 0.2:
            argv += ["--columns", rng.choice(["launch_speed", "launch_angle,launch_speed",
                                              "hit_distance", "pitch_speed"])]
        if rng.random() < 0.3:
            argv.append("--json")
        if rng.random() < 0.1:
            argv.append("--strict")
        return argv

    def infer(self):
        argv = ["infer", str(self.files.export())]
        if self.rng.random() < 0.1:
            argv.append("--strict")
        return argv

    def fit_flight(self):
        rng = self.rng
        argv = ["fit", "--flight", "--data", str(self.files.export()), "--intervals",
                "curvature"]
        if rng.random() < 0.3:
            argv.append("--json")
        if rng.random() < 0.1:
            argv += ["--free", rng.choice(["drag_scale", "lift_scale"])]
        return argv

    def fit_game(self):
        argv = ["fit", "--study", str(ROOT / "studies" / "game_fastball.toml"), "--data",
                str(self.files.export()), "--free", "e", "--intervals", "curvature",
                "--no-compare", "--draws", "4"]
        if self.rng.random() < 0.3:
            argv.append("--json")
        return argv

    def population(self):
        return ["fit", "--population", "--study",
                str(ROOT / "studies" / "mlb_population.toml"), "--data",
                str(self.files.export()), "--free", "swing.bat_speed.mean", "--draws", "10",
                "--bins", "5"]

    def reproduce(self):
        return ["reproduce", "statcast", "--data", str(self.files.export()), "--out",
                str(self.files.path(""))]

    def pitches(self):
        rng = self.rng
        path = self.files.export()
        if rng.random() < 0.3 and path.suffix == ".csv" and path.is_file() and \
                rng.random() < 0.5:
            # a tidy CSV: the reader's table written as CSV, a cell mutated
            try:
                from mcbat.statcast import read

                tidy = read(BASE).head(60)
                column = rng.choice(["pitch_speed", "spin_rate", "game_pk", "batter",
                                     "at_bat_number", "vertical_approach_angle"])
                tidy[column] = tidy[column].astype(object)
                tidy.loc[rng.randrange(len(tidy)), column] = rng.choice(NUMBERS)
                if rng.random() < 0.3:
                    tidy = tidy.iloc[list(range(len(tidy))) * 2]
                tidy.to_csv(path, index=False)
            except Exception:  # noqa: BLE001 - the file stays the export
                pass
        study = self.files.path(".toml")
        swing = rng.random() < 0.3
        study.write_text(
            f'[study]\nname = "fuzz"\nsamples = 40\n[ball]\npreset = "baseball"\n'
            f'[bat]\npreset = "r161"\n[pitches]\nfile = {json.dumps(str(path))}\n'
            f'swing = {"true" if swing else "false"}\n'
            '[pitches.fallback]\nspin_axis = { value = 200, unit = "deg" }\n'
            + ('bat_speed = { value = 70, unit = "mph" }\n'
               'attack_angle = { value = 10, unit = "deg" }\n'
               'attack_direction = { value = 0, unit = "deg" }\n' if swing else "")
            + '[pitch]\nspin_efficiency = 0.9\n[swing]\n'
            + ('' if swing else 'bat_speed = { value = 70, unit = "mph" }\n')
            + 'vertical_bat_angle = { value = -30, unit = "deg" }\n'
            '[contact]\nundercut = { dist = "uniform", low = -1, high = 1, unit = "in" }\n'
            '[friction]\nmu = 0.5\n')
        return ["run", str(study), "--quiet", "--out", str(self.files.path(""))]

    def impact(self):
        rng = self.rng
        case = json.loads((ROOT / "examples" / "game_fastball.json").read_text())
        value = rng.choice([1e300, 1e308, 10**300, -1.0, 0.0, 1e-300, 0.0366, 1e20, 10.0,
                            {"value": 1e300, "unit": "in"}, "x", None])
        case["ball"] = {"mass": rng.choice([0.145, 1e300, 1e-300, 10**400 // 10**100]),
                        "radius": value}
        if rng.random() < 0.3:
            case = json.loads((ROOT / "examples" / "cabo2012_sec5.json").read_text())
            case["ball"]["radius"] = value
        path = self.files.path(".json")
        path.write_text(json.dumps(case))
        return ["impact", str(path)]


# ------------------------------------------------------------------------ checking

def judge(argv, code, stdout, stderr):
    """The violations of one input (empty when it keeps the contract)."""
    bad = []
    if code not in (0, 2):
        bad.append(f"exit {code}")
    if "Traceback" in stderr:
        bad.append("traceback")
    if code == 2 and len(stderr.strip().splitlines()) != 1:
        bad.append(f"{len(stderr.strip().splitlines())} lines on stderr")
    if code == 0:
        shown = QUOTED.sub("''", stdout.replace(str(Path(tempfile.gettempdir())), ""))
        found = NON_FINITE.search(shown)
        if found:
            start = max(found.start() - 60, 0)
            bad.append(f"non-finite number printed: {shown[start:found.end() + 20]!r}")
        if "Warning" in stderr:
            bad.append(f"a warning on stderr: {stderr.strip()[:200]}")
        if "--json" in argv or argv[0] == "impact":
            try:
                nulls = _nulls(_strict(stdout))
                if nulls and argv[0] == "impact":
                    bad.append(f"null for {sorted(set(map(str, nulls)))[:4]}")
            except ValueError as err:
                bad.append(f"not strict JSON: {err}")
    return bad


def warm_up(scratch, dataset):
    """One valid input of each surface, untimed and unjudged: the first call of a command
    loads (or, after a change to a kernel's source, compiles) its numba kernels, which
    prints one line on stderr and is no hang."""
    from mcbat.cli import main as cli_main

    flight = ["fit", "--flight", "--data", str(BASE), "--intervals", "curvature"]
    game = ["fit", "--study", str(ROOT / "studies" / "game_fastball.toml"), "--data",
            str(BASE), "--free", "e", "--intervals", "curvature", "--no-compare", "--draws",
            "4"]
    for argv in (["statcast", str(BASE)], ["infer", str(BASE)],
                 ["compare", str(dataset), str(BASE), "--permutations", "10"], flight, game,
                 ["impact", str(ROOT / "examples" / "game_fastball.json")],
                 ["impact", str(ROOT / "examples" / "cabo2012_sec5.json")]):
        with contextlib.redirect_stdout(io.StringIO()), \
                contextlib.redirect_stderr(io.StringIO()):
            cli_main(argv)


def _dataset(scratch):
    """A small game dataset to compare the files with."""
    from mcbat.cli import main as cli_main

    out = scratch / "ds"
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        cli_main(["run", str(ROOT / "studies" / "game_fastball.toml"), "--samples", "300",
                  "--quiet", "--out", str(out)])
    return out


def work(task):
    """Run the inputs ``indices`` (one worker); returns their results."""
    seed, indices, timeout = task
    import warnings

    warnings.simplefilter("default")
    results = []
    scratch = Path(tempfile.mkdtemp(prefix="mcbat-fuzz-statcast-"))
    cwd = os.getcwd()
    os.chdir(scratch)
    try:
        bases = [_base_rows(BASE, 90)]
        if TRACKED.exists():
            bases.append(_base_rows(TRACKED, 90))
        dataset = _dataset(scratch)
        warm_up(scratch, dataset)
        surfaces = list(WEIGHTS)
        for i in indices:
            rng = random.Random(f"{seed}-{i}")
            surface = rng.choices(surfaces, [WEIGHTS[s] for s in surfaces])[0]
            workdir = scratch / f"w{i}"
            workdir.mkdir()
            inputs = Inputs(rng, workdir, bases, dataset)
            try:
                argv = getattr(inputs, surface)()
            except Exception as err:  # noqa: BLE001 - the generator's own failure
                results.append({"i": i, "surface": surface, "argv": None, "code": "gen",
                                "seconds": 0.0, "problems": [f"generator: {err!r}"]})
                continue
            code, out, err, dt = run_one(argv, timeout)
            problems = [f"hang over {timeout} s"] if code == "hang" else \
                judge(argv, code, out, err)
            results.append({"i": i, "surface": surface, "argv": argv, "code": str(code),
                            "seconds": dt, "problems": problems,
                            "stderr": err.strip().splitlines()[-3:] if problems else None,
                            "stdout": out[:300] if problems else None})
            shutil.rmtree(workdir, ignore_errors=True)
    finally:
        os.chdir(cwd)
        shutil.rmtree(scratch, ignore_errors=True)
    return results


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=10_000, help="inputs (default 10,000)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--timeout", type=int, default=60,
                        help="CPU seconds per input (wall clock: 10x)")
    parser.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    parser.add_argument("--only", type=int, nargs="*", help="run only these inputs")
    parser.add_argument("--report", type=Path, help="write the results as JSON")
    args = parser.parse_args(argv)
    indices = args.only if args.only else list(range(args.n))
    t0 = time.perf_counter()
    workers = max(1, min(args.workers, len(indices)))
    parts = [(args.seed, indices[k::workers], args.timeout) for k in range(workers)]
    if workers == 1:
        results = work(parts[0])
    else:
        # (in pieces, so that progress shows and a worker's memory is given back)
        results = []
        pieces = [(args.seed, indices[k:k + 250], args.timeout)
                  for k in range(0, len(indices), 250)]
        with multiprocessing.get_context("fork").Pool(workers, maxtasksperchild=1) as pool:
            for done in pool.imap_unordered(work, pieces):
                results.extend(done)
                for r in done:
                    if r["problems"]:
                        print(f"violation #{r['i']} {r['surface']}: {r['problems']}: "
                              f"{r['argv']}: {r.get('stderr')}", flush=True)
                bad = sum(1 for r in results if r["problems"])
                print(f"{len(results):,} inputs, {bad} violations, "
                      f"{time.perf_counter() - t0:.0f} s", flush=True)
    total = time.perf_counter() - t0
    codes, seconds = defaultdict(Counter), Counter()
    for r in results:
        codes[r["surface"]][r["code"]] += 1
        seconds[r["surface"]] += r["seconds"]
    slowest = max(results, key=lambda r: r["seconds"])
    violations = [r for r in results if r["problems"]]
    print(f"\n{len(results):,} inputs in {total:.0f} s with {workers} worker(s) "
          f"(seed {args.seed}, timeout {args.timeout} s)")
    print(f"{'surface':<12}{'inputs':>8}  exit codes{'':<20}seconds")
    for name in WEIGHTS:
        if name in codes:
            n = sum(codes[name].values())
            spread = ", ".join(f"{k}: {v}" for k, v in sorted(codes[name].items()))
            print(f"{name:<12}{n:>8}  {spread:<30}{seconds[name]:.0f}")
    every = Counter()
    for counter in codes.values():
        every.update(counter)
    print(f"all exit codes: {dict(sorted(every.items()))}")
    print(f"slowest input: #{slowest['i']} {slowest['seconds']:.1f} s: {slowest['argv']}")
    print(f"violations: {len(violations)}")
    for v in sorted(violations, key=lambda r: r["i"])[:40]:
        print(f"  #{v['i']} {v['surface']}: {v['problems']}: {v['argv']}\n"
              f"      {v.get('stderr')}")
    if args.report:
        args.report.write_text(json.dumps({
            "n": len(results), "seed": args.seed, "workers": workers, "seconds": total,
            "codes": {k: dict(v) for k, v in codes.items()}, "violations": violations},
            indent=1, default=str))
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main())
