"""The game fit against game tables it did not simulate: coverage, pulls, limits, refusals.

Run:  NUMBA_NUM_THREADS=1 .venv/bin/python -m validation game_fit_validation --tables 200 \
          --workers 2 --out game-fit-validation
      .venv/bin/python -m validation game_fit_validation --summary game-fit-validation
      .venv/bin/python -m validation game_fit_validation --crosscheck 2

Each table comes from :func:`harness.game_tables.game_table` (its own draws,
kinematics and noise; every impact solved by the scipy reference solver, ~0.1 s a row) and
is fitted as a user would fit it: ``fit(tests/stats/data/game_fit_independent.toml, table,
("e", "e_x"))`` with profile intervals (the fit's defaults). Table ``k`` uses the seed
``2000 + k``, its fit the seed ``k``. ``--solver kernel`` makes the tables with mcbat's game
kernel instead (the same random numbers; fast, but not independent); ``--crosscheck N``
makes N tables both ways and prints their largest difference over the stated errors.
``--measured`` chooses the measured inputs a table carries (default: pitch speed, bat speed,
attack angle and an undercut known to 2 mm; ``none``: the observables alone, every input
marginalised over the study's distributions).

Each result is one JSON line in DIR/game.<worker>.jsonl, so an interrupted run keeps what it
did and a rerun goes on from there (with the same ``--rows``, ``--e`` and ``--e-x``: the
records carry them, and the summary keeps them apart). The summary gives, per parameter,
the share of two-sided 68 % intervals holding the truth (a table without an interval counts
as not covered) with its binomial error, the mean pull with its error, the pulls' spread,
one-sided 95 % limits and how often they hold the truth, refusals and the median seconds
of a table (simulation and fit).
"""

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from harness.fit_validation import (  # noqa: E402
    format_or_dash,
    interval_statistics,
    run_jobs,
)

STUDY = ROOT / "tests" / "stats" / "data" / "game_fit_independent.toml"
PARAMETERS = ("e", "e_x")
MEASURED = ("pitch_speed", "bat_speed", "attack_angle", "undercut")
"""The measured inputs of a table unless ``--measured`` says otherwise (the undercut to
2 mm, the others exact)."""

QUICK_ARGS = ["--tables", "2", "--rows", "40", "--out", "game-fit-validation-quick"]


def kernel_solver(inputs, e, e_x, bat="cylinder", handedness=1.0):
    """As :func:`harness.game_tables.reference_solver`, each row solved by mcbat's
    game kernel through its public API (:class:`mcbat.api.GameCase`,
    :func:`mcbat.api.solve_game`) with the same bodies, restitution and inputs: not
    independent, but a hundred times faster, for many tables and for comparing the two.
    ``bat`` is ``"cylinder"`` or a dict of :func:`harness.game_tables.bat_bodies`
    naming a bat preset as ``"preset"``."""
    from harness.game_tables import BODIES, OBSERVABLES, RESTITUTION
    from mcbat.api import GameCase, solve_game
    from mcbat.bodies import Ball, Bat, bat_preset
    from mcbat.bodies.restitution import Restitution

    b = BODIES
    ball = Ball(mass=b["ball_mass"], radius=b["ball_radius"],
                inertia_factor=b["ball_inertia_factor"])
    if isinstance(bat, str) and bat == "cylinder":
        body = Bat(mass=b["bat_mass"], radius=b["bat_radius"],
                   transverse_inertia=b["bat_transverse_inertia"],
                   axial_inertia=b["bat_axial_inertia"], length=b["bat_length"],
                   cm_from_barrel_end=b["bat_cm_from_barrel_end"])
    elif isinstance(bat, dict) and "preset" in bat:
        body = bat_preset(bat["preset"])
    else:
        raise ValueError(f"the kernel solver takes 'cylinder' or a bat naming its preset, "
                         f"got {bat!r}")
    restitution = Restitution(e_ref=e, e_slope=RESTITUTION["e_slope"],
                              e_speed_ref=RESTITUTION["e_speed_ref"], e_x=e_x)
    rows = len(inputs["pitch_speed"])
    out = np.empty((rows, len(OBSERVABLES)))
    for k in range(rows):
        row = {name: float(values[k]) for name, values in inputs.items()}
        case = GameCase(ball=ball, bat=body, restitution=restitution, pivot=b["pivot"],
                        handedness="R" if handedness > 0 else "L", **row)
        result = solve_game(case)
        out[k] = [getattr(result, name) for name in OBSERVABLES]
    return out


def make_table(k, rows, truth, solver="reference", measured=MEASURED):
    """Table ``k`` (seed ``2000 + k``) of ``rows`` rows at ``truth``, carrying the measured
    inputs ``measured``."""
    from harness.game_tables import game_table, reference_solver

    chosen = kernel_solver if solver == "kernel" else reference_solver
    return game_table(rows, 2000 + k, solver=chosen, measured=measured, **truth)


def fit_table(k, study, rows, truth, solver="reference", measured=MEASURED):
    """Simulate and fit table ``k``; a JSON-ready record: the setup, the fit's parameters,
    chi2, p-value and warnings, or the refusal's message, and the seconds taken."""
    from mcbat.errors import InputError
    from mcbat.stats.fit.estimate import fit

    t0 = time.perf_counter()
    table = make_table(k, rows, truth, solver, measured)
    simulated = time.perf_counter() - t0
    rec = {"table": k, "rows": rows, "solver": solver, "truth": truth,
           "measured": list(measured),
           "simulate_seconds": simulated}
    try:
        r = fit(study, table, PARAMETERS, seed=k)
    except InputError as err:
        rec.update(refused=str(err), seconds=time.perf_counter() - t0)
        return rec
    out = r.to_dict()
    rec.update(seconds=time.perf_counter() - t0, chi2=r.chi2, dof=r.dof, p_value=r.p_value,
               params=out["params"], warnings=out["warnings"])
    return rec


def read_records(out):
    """Every record in DIR's .jsonl files (the last one of a table and setup wins)."""
    recs = {}
    for path in sorted(Path(out).glob("*.jsonl")):
        for line in path.read_text().splitlines():
            rec = json.loads(line)
            recs[_setup(rec) + (rec["table"],)] = rec
    return [recs[key] for key in sorted(recs)]


def _setup(rec):
    measured = ",".join(rec.get("measured", MEASURED)) or "none"
    return (rec["rows"], rec["solver"], measured, *(rec["truth"][p] for p in PARAMETERS))


def summarize(records):
    """Per setup (rows, solver, truth) and parameter: tables, refusals, 68 % coverage and
    its binomial error, mean pull and its error, pull sd, one-sided limits and how often
    they hold, median chi2/dof and median seconds."""
    out = []
    for setup in sorted({_setup(r) for r in records}):
        these = [r for r in records if _setup(r) == setup]
        fitted = [r for r in these if "refused" not in r]
        for p in PARAMETERS:
            entries = [(r["params"][p], r["truth"][p]) for r in fitted]
            out.append({
                "rows": setup[0], "solver": setup[1], "measured": setup[2], "param": p,
                "truth": setup[3 + PARAMETERS.index(p)], "tables": len(these),
                "refused": len(these) - len(fitted),
                **interval_statistics(entries, len(fitted)),
                "chi2_per_dof": (float(np.median([r["chi2"] / r["dof"] for r in fitted]))
                                 if fitted else None),
                "median_seconds": float(np.median([r["seconds"] for r in these]))})
    return out


def summary_line(row):
    """One printed line of a :func:`summarize` row."""
    dash = format_or_dash
    return (f"{row['rows']} rows ({row['solver']}; measured: {row['measured']}) "
            f"{row['param']:3s} = {row['truth']:g}: "
            f"tables {row['tables']} refused {row['refused']}  coverage "
            f"{100 * row['coverage']:5.1f} % (+-{100 * row['coverage_se']:.1f})  mean pull "
            f"{dash(row['mean_pull'], '+.3f')} (+-{dash(row['mean_pull_se'], '.3f')})  pull sd "
            f"{dash(row['pull_sd'], '.2f')}  95 % limits {row['limits']} holding "
            f"{dash(row['limit_coverage'], '.3f')}  median chi2/dof "
            f"{dash(row['chi2_per_dof'], '.3f')}  {row['median_seconds']:.1f} s/table")


def worker(args):
    index, workers, tables, rows, truth, solver, measured, out = args
    from mcbat.study import load_study

    study = load_study(STUDY)
    done = {_setup(r) + (r["table"],) for r in read_records(out)}
    setup = _setup({"rows": rows, "solver": solver, "measured": measured, "truth": truth})
    for k in range(index, tables, workers):
        if setup + (k,) in done:
            continue
        rec = fit_table(k, study, rows, truth, solver, measured)
        with open(Path(out) / f"game.{index}.jsonl", "a") as handle:
            handle.write(json.dumps(rec) + "\n")


def crosscheck(n, rows, truth):
    """Largest difference between reference and kernel tables, over the stated errors."""
    from harness.game_tables import OBSERVABLES

    worst = dict.fromkeys(OBSERVABLES, 0.0)
    for k in range(n):
        ref, ker = make_table(k, rows, truth, "reference"), make_table(k, rows, truth, "kernel")
        for col in OBSERVABLES:
            worst[col] = max(worst[col],
                             float(np.max(np.abs(ref[col] - ker[col]) / ref[f"{col}_err"])))
    print(f"{n} tables of {rows} rows: reference and kernel differ by at most "
          + ", ".join(f"{c} {v:.2e}" for c, v in worst.items()) + " of a stated error")
    return worst


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tables", type=int, default=200)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--rows", type=int, default=100)
    parser.add_argument("--e", type=float, default=0.5, help="the true e* at 85 ft/s")
    parser.add_argument("--e-x", type=float, default=0.3, help="the true e_x")
    parser.add_argument("--solver", choices=("reference", "kernel"), default="reference")
    parser.add_argument("--measured", default=",".join(MEASURED),
                        help="the measured inputs the tables carry, comma-separated, or "
                        "none (default: %(default)s)")
    parser.add_argument("--out", default="game-fit-validation")
    parser.add_argument("--summary", metavar="DIR", help="only summarise DIR")
    parser.add_argument("--crosscheck", type=int, metavar="N",
                        help="compare N tables made by the reference and by the kernel")
    args = parser.parse_args(argv)
    truth = {"e": args.e, "e_x": args.e_x}
    measured = tuple(m for m in args.measured.split(",") if m and m != "none")
    from harness.game_tables import MEASURED as MEASURABLE

    unknown = [m for m in measured if m not in MEASURABLE]
    if unknown:
        parser.error(f"--measured: {unknown[0]!r} is not a measured input (choose from "
                     f"{', '.join(MEASURABLE)}, or none)")
    if args.crosscheck:
        crosscheck(args.crosscheck, args.rows, truth)
        return 0
    if not args.summary:
        Path(args.out).mkdir(parents=True, exist_ok=True)
        run_jobs(worker, [(i, args.workers, args.tables, args.rows, truth, args.solver,
                           measured, args.out) for i in range(args.workers)])
    for row in summarize(read_records(args.summary or args.out)):
        print(summary_line(row))
    return 0


if __name__ == "__main__":
    sys.exit(main())
