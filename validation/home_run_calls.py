"""Home-run calls against real home runs, and the fences against the measured distances.

Run:  .venv/bin/python -m validation home_run_calls FILES_OR_FOLDERS... [--compare OLD.csv]
          [--min-distance 300] [--by-park]

Each Savant export (a folder stands for its ``statcast_*.csv``) is replayed as it was
(:func:`mcbat.statcast.replay.replay`: its own park, air and season) and each ball's call
(:func:`mcbat.statcast.home_runs.home_run_call`) is set against what happened
(``events == "home_run"``). A file holding only home runs (more than 90 % of its balls in
play) counts for the missed calls and the geometry of home runs, not for false calls.

Two checks:

- **Geometry** (no flight): ``hit_distance_sc`` against our fence
  (:func:`mcbat.statcast.parks.fence` at the ball's spray angle and date). A home run's
  (projected) distance must lie beyond the fence, a ball caught in the air
  (``field_out``, ``sac_fly``, ``double_play``, ... of a fly ball, line drive or popup)
  short of it; judged on the home runs and the caught balls of at least
  ``--min-distance`` ft. A hit whose distance lies beyond the fence is not counted: Statcast
  projects the distance of a ball stopped by the wall (doubles off Fenway's 37 ft wall have
  distances up to 60 ft beyond it), so only its height at the wall says whether it cleared.
- **Calls**: the confusion of called and measured home runs, per file and (``--by-park``)
  per park, each error split into **geometry** (the measured distance contradicts our fence:
  a false call whose ball was caught *beyond* it, a missed call whose home run landed
  *short* of it) and **flight** (the fence agrees with the measured distance; the flown
  ball's carry or height at the wall is what was wrong).

``--compare OLD.csv`` runs the same against another fence table (e.g. the earlier sparse
one: ``git show 5f16540:data/park_fences.csv > /tmp/old.csv``).
"""

from __future__ import annotations

import argparse
import contextlib
from pathlib import Path

import numpy as np
import pandas as pd

from mcbat.statcast import parks, reader
from mcbat.statcast.replay import replay

CAUGHT_EVENTS = ("field_out", "sac_fly", "double_play", "sac_fly_double_play", "triple_play")
AIR_TYPES = ("fly_ball", "line_drive", "popup")
HOME_RUN_ONLY_SHARE = 0.9


def files_of(paths):
    """The CSV files of ``paths`` (a folder gives its ``statcast_*.csv``), sorted."""
    out = []
    for p in map(Path, paths):
        out.extend(sorted(p.glob("statcast_*.csv")) if p.is_dir() else [p])
    return out


@contextlib.contextmanager
def fence_table(path):
    """Within the block, :func:`mcbat.statcast.parks.fence` reads the fence table ``path``
    (same format as ``data/park_fences.csv``); None leaves the shipped one."""
    if path is None:
        yield
        return
    text = Path(path).read_text(encoding="utf-8")
    original_read = parks._read

    def read(name):
        if name != parks.FENCES_FILE:
            return original_read(name)
        import csv
        return list(csv.DictReader(line for line in text.splitlines()
                                   if line.strip() and not line.startswith("#")))

    parks._read = read
    parks.fence_configurations.cache_clear()
    parks.fences.cache_clear()
    try:
        yield
    finally:
        parks._read = original_read
        parks.fence_configurations.cache_clear()
        parks.fences.cache_clear()


def classify(out: pd.DataFrame, min_distance: float = 300.0) -> pd.DataFrame:
    """Per ball of a replay table: ``measured`` (a home run), ``called``, ``fence_at_spray``
    (ft, our fence at its measured spray angle and date), ``caught`` (in the air),
    ``judged`` (a home run, or a caught ball of at least ``min_distance`` ft, with a fence),
    ``geometry_ok`` (home run beyond the fence, caught ball short of it)."""
    events = out["events"].astype("string").fillna("").to_numpy(str)
    kind = out["bb_type"].astype("string").fillna("").to_numpy(str)
    dist = out["hit_distance_sc"].to_numpy(float)
    fence, _ = parks.fence(out["actual_park"].to_numpy(object),
                           out["spray_angle"].to_numpy(float),
                           pd.to_datetime(out["game_date"]).to_numpy())
    measured = events == "home_run"
    caught = np.isin(events, CAUGHT_EVENTS) & np.isin(kind, AIR_TYPES)
    has = np.isfinite(dist) & np.isfinite(fence)
    judged = has & (measured | (caught & (dist >= min_distance)))
    ok = np.where(measured, dist >= fence, dist <= fence)
    called = out["actual_home_run"].astype("boolean")
    return pd.DataFrame({
        "park": out["actual_park"].to_numpy(object), "measured": measured,
        "called": called.fillna(False).to_numpy(bool),
        "probability": out["actual_home_run_probability"].to_numpy(float),
        "call_known": (~called.isna()).to_numpy(bool),
        "caught": caught, "judged": judged, "geometry_ok": ok & has,
        "hit_distance_sc": dist, "fence_at_spray": fence})


def summarize(c: pd.DataFrame, home_runs_only: bool) -> dict:
    """The figures of one file (or park): calls and geometry (module docstring)."""
    known = c["call_known"]
    m, k = c["measured"] & known, c["called"] & known
    false_call = k & ~m
    missed = m & ~k
    beyond = c["hit_distance_sc"] > c["fence_at_spray"]
    judged = c["judged"]
    return {
        "balls": int(len(c)), "measured": int(c["measured"].sum()),
        "called": None if home_runs_only else int(k.sum()),
        "expected": None if home_runs_only else float(c.loc[known, "probability"].sum()),
        "both": int((k & m).sum()),
        "false_calls": None if home_runs_only else int(false_call.sum()),
        "false_geometry": None if home_runs_only else int((false_call & c["caught"] & beyond
                                                          ).sum()),
        "missed": int(missed.sum()),
        "missed_geometry": int((missed & ~beyond & np.isfinite(c["fence_at_spray"])).sum()),
        "no_call": int((~known).sum()),
        "judged": int(judged.sum()),
        "home_runs_short": int((judged & c["measured"] & ~c["geometry_ok"]).sum()),
        "caught_beyond": int((judged & c["caught"] & ~c["geometry_ok"]).sum()),
    }


def evaluate(paths, min_distance=300.0):
    """``(per_file, per_park, balls)``: DataFrames of :func:`summarize` over the files (per
    park, the calls count the files with all balls in play and the geometry every file),
    and the balls of the files with all balls in play (:func:`classify`)."""
    files, frames = [], []
    for path in files_of(paths):
        table = reader.read(path)
        c = classify(replay(table), min_distance)
        only = float(c["measured"].mean()) > HOME_RUN_ONLY_SHARE
        files.append({"file": path.name, "home_runs_only": only, **summarize(c, only)})
        frames.append(c.assign(home_runs_only=only))
    balls = pd.concat(frames, ignore_index=True)
    mixed = balls[~balls["home_runs_only"]]
    rows = []
    for park, g in balls.groupby("park"):
        calls = summarize(g[~g["home_runs_only"]], False)
        geometry = summarize(g, True)
        for key in ("measured", "judged", "home_runs_short", "caught_beyond"):
            calls[key] = geometry[key]
        calls["measured_mixed"] = int(g.loc[~g["home_runs_only"], "measured"].sum())
        rows.append({"park": park, **calls})
    return pd.DataFrame(files), pd.DataFrame(rows), mixed


def _table(df):
    cols = list(df.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for row in df.itertuples(index=False):
        lines.append("| " + " | ".join("" if v is None or (isinstance(v, float) and np.isnan(v))
                                       else (str(int(v)) if float(v).is_integer()
                                             else f"{v:.1f}")
                                       if isinstance(v, (float, np.floating))
                                       else str(v) for v in row) + " |")
    return "\n".join(lines)


#: Bins of the home-run probability for ``reliability``.
PROBABILITY_BINS = (0.0, 0.02, 0.1, 0.3, 0.7, 0.9, 1.0)


def reliability(balls: pd.DataFrame) -> str:
    """A Markdown table: per bin of the called probability, the balls, the home runs
    expected (the sum of their probabilities) and measured."""
    known = balls[balls["call_known"]]
    bins = pd.cut(known["probability"], PROBABILITY_BINS, include_lowest=True)
    g = known.groupby(bins, observed=True).agg(balls=("probability", "size"),
                                               expected=("probability", "sum"),
                                               measured=("measured", "sum"))
    lines = ["| probability | balls | expected | measured |", "|---|---|---|---|"]
    for interval, row in g.iterrows():
        lines.append(f"| {max(interval.left, 0.0):.2f}-{interval.right:.2f} | {int(row.balls)} | "
                     f"{row.expected:.1f} | {int(row.measured)} |")
    return "\n".join(lines)


def report(per_file, per_park, balls_of_mixed, by_park, label):
    print(f"\n### {label}\n")
    shown = ["file", "measured", "expected", "called", "both", "false_calls", "false_geometry",
             "missed", "missed_geometry", "no_call", "judged", "home_runs_short",
             "caught_beyond"]
    print(_table(per_file[shown]))
    judged = per_file["judged"].sum()
    bad = per_file["home_runs_short"].sum() + per_file["caught_beyond"].sum()
    mixed = per_file[~per_file["home_runs_only"]]
    print(f"\nGeometry: {judged - bad} of {judged} judged balls consistent with the fence "
          f"({100 * (1 - bad / judged):.2f} %): {per_file['home_runs_short'].sum()} home runs "
          f"short of it, {per_file['caught_beyond'].sum()} caught balls beyond it.")
    print(f"Calls (files with all balls in play): {int(mixed['called'].sum())} called, "
          f"{float(mixed['expected'].sum()):.1f} expected (the sum of the balls' "
          f"probabilities), {int(mixed['measured'].sum())} measured; false calls "
          f"{int(mixed['false_calls'].sum())} ({int(mixed['false_geometry'].sum())} geometry), "
          f"missed {int(mixed['missed'].sum())} ({int(mixed['missed_geometry'].sum())} "
          f"geometry); the rest are the flight's.")
    print("\nThe probabilities against what happened (files with all balls in play):\n")
    print(reliability(balls_of_mixed))
    if by_park:
        print("\nPer park: calls over the files with all balls in play (`measured_mixed`), "
              "geometry over every file (`measured` counts the home-run-only files too).\n")
        print(_table(per_park[["park", "measured_mixed"] + shown[2:] + ["measured"]]))


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m validation home_run_calls",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", nargs="+", help="Savant CSV files or folders")
    parser.add_argument("--compare", default=None, help="another fence table to run too")
    parser.add_argument("--min-distance", type=float, default=300.0,
                        help="caught balls judged from this distance (ft)")
    parser.add_argument("--by-park", action="store_true", help="also the table per park")
    args = parser.parse_args(argv)
    runs = [(None, "fences of data/park_fences.csv")]
    if args.compare:
        runs.append((args.compare, f"fences of {args.compare}"))
    for table, label in runs:
        with fence_table(table):
            per_file, per_park, balls = evaluate(args.paths, args.min_distance)
        report(per_file, per_park, balls, args.by_park, label)
    return 0
