"""mcbat's fit against the exact marginal likelihood and the textbook fit, table by table.

Run:  NUMBA_NUM_THREADS=1 .venv/bin/python -m validation marginal_fit --setting large \
          --tables 10 --fits DIR --out marginal.jsonl
      .venv/bin/python -m validation marginal_fit --setting large --summary marginal.jsonl \
          --fits DIR

Each table of :mod:`harness.fit_validation` (the same seeds and noise as the fit's
check) is fitted twice without mcbat's fit machinery: by the textbook fit (every impact
parameter at its true value, :func:`harness.textbook_fit.textbook_fit`) and by the
exact marginal likelihood (each row's impact parameter and contact point integrated over
their true uniform distributions by quadrature, :func:`harness.textbook_fit.
marginal_fit`; ``--contact-nodes 0`` keeps the contact points at their true values, which
mcbat's fit does not know). With
``--fits DIR`` (a ``fit_validation`` run of the same setting) the summary sets mcbat's
best fits beside them: the mean differences over the tables, with their standard errors,
say how much of a shift in mcbat's fit belongs to marginalising the measured inputs at all
and how much to the way mcbat does it. About 5 minutes a 3000-row table; one JSON line a
table, so a rerun goes on.
"""

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from harness.fit_validation import SETTINGS, TRUTH, make_table  # noqa: E402
from harness.textbook_fit import marginal_fit, textbook_fit  # noqa: E402

QUICK_ARGS = ["--setting", "inside", "--tables", "1", "--out", "marginal-fit-quick.jsonl"]


def record(setting, k, nodes, contact_nodes):
    """Table ``k`` of ``setting``: the truth, the textbook fit and the marginal fit."""
    table = make_table(setting, k)
    textbook = textbook_fit(table)
    marginal = marginal_fit(table, nodes=nodes, start=(textbook["e"], textbook["mu"]),
                            contact_nodes=contact_nodes)
    return {"setting": setting, "table": k, "nodes": nodes, "contact_nodes": contact_nodes,
            "truth": {p: float(table.attrs["truth"][p]) for p in TRUTH},
            "textbook": {p: textbook[p] for p in TRUTH},
            "marginal": {p: marginal[p] for p in TRUTH}}


def read_lines(path):
    """The JSON lines of ``path`` (none if it does not exist)."""
    path = Path(path)
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def mcbat_fits(directory, setting):
    """Table -> mcbat's best values, from a ``fit_validation`` output directory."""
    fits = {}
    for path in sorted(Path(directory).glob("*.jsonl")):
        for rec in read_lines(path):
            if rec.get("setting") == setting and "params" in rec:
                fits[rec["table"]] = {p: rec["params"][p]["value"] for p in TRUTH}
    return fits


def _mean(values):
    values = np.asarray(values, float)
    se = values.std(ddof=1) / np.sqrt(len(values)) if len(values) > 1 else float("nan")
    return f"{values.mean():+.6f} +- {se:.6f} ({int((values < 0).sum())} of {len(values)} below 0)"


def summary(records, fits=None):
    """Printed lines: per parameter, the marginal fit against the textbook fit and the
    truth, and mcbat's fit against the marginal fit where ``fits`` has the table."""
    lines = []
    for p in TRUTH:
        marginal = [r["marginal"][p] for r in records]
        textbook = [r["textbook"][p] for r in records]
        truth = [r["truth"][p] for r in records]
        lines.append(f"{p:3s} tables {len(records):3d}  marginal - textbook "
                     f"{_mean(np.subtract(marginal, textbook))}  marginal - truth "
                     f"{_mean(np.subtract(marginal, truth))}")
        if fits:
            both = [r for r in records if r["table"] in fits]
            if both:
                lines.append(f"{p:3s} tables {len(both):3d}  mcbat - marginal "
                             f"{_mean([fits[r['table']][p] - r['marginal'][p] for r in both])}"
                             f"  mcbat - textbook "
                             f"{_mean([fits[r['table']][p] - r['textbook'][p] for r in both])}")
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m validation marginal_fit",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--setting", default="large", choices=list(SETTINGS))
    parser.add_argument("--tables", type=int, default=10)
    parser.add_argument("--nodes", type=int, default=64,
                        help="quadrature nodes of a row's impact parameter")
    parser.add_argument("--contact-nodes", type=int, default=8,
                        help="quadrature nodes of a row's contact point (0: its true value)")
    parser.add_argument("--out", default="marginal-fit.jsonl")
    parser.add_argument("--fits", metavar="DIR",
                        help="a fit_validation output directory of the same setting")
    parser.add_argument("--summary", metavar="FILE", help="summarise FILE and stop")
    args = parser.parse_args(argv)
    key = (args.setting, args.nodes, args.contact_nodes)
    if args.summary:
        records = [r for r in read_lines(args.summary)
                   if (r["setting"], r["nodes"], r.get("contact_nodes", 0)) == key]
    else:
        done = {(r["setting"], r["nodes"], r.get("contact_nodes", 0), r["table"])
                for r in read_lines(args.out)}
        with open(args.out, "a") as out:
            for k in range(args.tables):
                if (*key, k) in done:
                    continue
                rec = record(args.setting, k, args.nodes, args.contact_nodes)
                out.write(json.dumps(rec) + "\n")
                out.flush()
                print(f"table {k}: textbook e* {rec['textbook']['e']:.6f}, marginal "
                      f"{rec['marginal']['e']:.6f}", flush=True)
        records = [r for r in read_lines(args.out)
                   if (r["setting"], r["nodes"], r.get("contact_nodes", 0)) == key]
    if not records:
        print("no records")
        return 1
    setting = records[0]["setting"]
    fits = mcbat_fits(args.fits, setting) if args.fits else None
    for line in summary(records, fits):
        print(line)
    return 0


if __name__ == "__main__":
    sys.exit(main())
