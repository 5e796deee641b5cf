"""Build ``data/park_fences.csv`` from the dense outfield outline of each park.

Run:  .venv/bin/python -m validation park_fences OUTLINE_2018.csv OUTLINE_2023.csv
          [--write data/park_fences.csv] [--scale cf|own]

``OUTLINE_2018.csv`` and ``OUTLINE_2023.csv`` are ``inst/extdata/mlb_stadia_paths.csv`` of
bdilday/GeomMLBStadiums at commits ``4abd72c`` (2018-08-15, every park as traced in 2018)
and ``90b4356`` (2023-09-21, the same with Camden Yards' 2022 left-field wall); copies with
their provenance are in ``../shared/data/parks/`` (``README.md`` there). Each outline is a
polygon in Statcast's spray-chart frame (``hc_x``, ``hc_y``); every point of its
``outfield_outer`` segment in fair territory becomes one row of the fence table, with

- its spray angle ``atan2(hc_x - 125.42, 198.27 - hc_y)`` (deg; the frame and home plate of
  :func:`mcbat.statcast.kinematics.spray_angle`, the same angle as the balls' own);
- its distance ``hypot(...) * 2.495671`` ft (GeomMLBStadiums' feet per unit), times
  ``S = published CF / outline CF`` with ``--scale cf`` (the default; the tracing's scale
  differs from park to park: Yankee Stadium's outline is 4 % long) or 1 with ``--scale own``;
- its wall height: ``fence_height`` of danmorse314/dinger-machine's
  ``data/fence_heights_complete.csv`` (commit ``cf48484``), which tabulates the same outline
  points with heights; its spray angles are 0.75 times the true ones (Bill Petti's formula),
  so the height runs below are written in its angles and converted.

The published LF line (-45 deg), CF (0 deg) and RF line (+45 deg) rows of the current table
are kept as they are (with their sources); outline points within 0.5 deg of them are
dropped. Parks without an outline and their rows are copied unchanged. A park whose fences
moved gets one set of rows per configuration; how each change is applied to the outline is
in :data:`CHANGES` (and in ``data/README.md``).
"""

from __future__ import annotations

import argparse
import csv
import io
import math
from collections import defaultdict
from pathlib import Path

import numpy as np

HOME = (125.42, 198.27)
"""Home plate in the spray-chart frame (as :mod:`mcbat.statcast.kinematics`)."""
FT_PER_UNIT = 2.495671
"""GeomMLBStadiums' feet per spray-chart unit (``mlbam_xy_transformation``)."""
DINGER_ANGLE = 0.75
"""dinger-machine's ``spray_angle_stadia`` is 0.75 times the true spray angle."""

TEAMS = {
    "angels": "angel_stadium", "astros": "minute_maid_park", "athletics": "oakland_coliseum",
    "blue_jays": "rogers_centre", "braves": "truist_park", "brewers": "american_family_field",
    "cardinals": "busch_stadium", "cubs": "wrigley_field", "diamondbacks": "chase_field",
    "dodgers": "dodger_stadium", "giants": "oracle_park", "indians": "progressive_field",
    "guardians": "progressive_field", "mariners": "t_mobile_park", "marlins": "loandepot_park",
    "mets": "citi_field", "nationals": "nationals_park", "orioles": "camden_yards",
    "padres": "petco_park", "phillies": "citizens_bank_park", "pirates": "pnc_park",
    "rangers": "globe_life_park", "rays": "tropicana_field", "red_sox": "fenway_park",
    "reds": "great_american_ball_park", "rockies": "coors_field", "royals": "kauffman_stadium",
    "tigers": "comerica_park", "twins": "target_field", "white_sox": "rate_field",
    "yankees": "yankee_stadium",
}
"""GeomMLBStadiums' team names -> our ``park_id``. The 2018 Rangers outline is Globe Life
Park in Arlington (Globe Life Field opened in 2020)."""

# Wall heights (ft) of dinger-machine's fence_heights_complete.csv, as runs along the
# outline from the LF line to the RF line: (first, last spray_angle_stadia of the run, ft).
# Its spray angles are 0.75 x the true ones. Globe Life Park has none (dinger-machine's
# heights are those of Globe Life Field).
HEIGHT_RUNS = {
    "angel_stadium": [(-32.1, -28.8, 5), (-27.1, 28.2, 8), (29.9, 33.1, 5)],
    "minute_maid_park": [(-34.4, -7.1, 21), (-5.7, 17.6, 9), (19.1, 33.0, 7)],
    "oakland_coliseum": [(-35.2, -23.5, 8), (-21.7, -9.8, 15), (-8.2, 7.7, 8), (9.3, 22.9, 15),
                         (24.6, 34.6, 8)],
    "rogers_centre": [(-32.8, 33.3, 8)],
    "truist_park": [(-32.9, -26.6, 6), (-25.1, 8.7, 8), (10.2, 33.0, 16)],
    "american_family_field": [(-34.1, 33.6, 8)],
    "busch_stadium": [(-31.9, 33.6, 8)],
    "wrigley_field": [(-32.5, -23.5, 16), (-21.9, 25.2, 11), (26.5, 35.1, 16)],
    "chase_field": [(-34.5, -11.2, 8), (-9.8, 7.7, 25), (9.2, 34.1, 8)],
    "dodger_stadium": [(-33.6, -29.1, 4), (-27.4, 27.2, 8), (28.9, 33.4, 4)],
    "oracle_park": [(-34.3, 13.5, 8), (14.8, 34.9, 25)],
    "progressive_field": [(-33.0, -3.0, 19), (-1.6, 32.9, 9)],
    "t_mobile_park": [(-34.0, 33.3, 8)],
    "loandepot_park": [(-34.1, -11.0, 7), (-9.4, -4.3, 12), (-2.8, 34.9, 7)],
    "citi_field": [(-34.6, 33.5, 8)],
    "nationals_park": [(-34.3, 3.6, 8), (5.1, 23.3, 12), (25.0, 33.1, 8)],
    "camden_yards": [(-34.3, 22.2, 7), (23.8, 34.5, 21)],
    "petco_park": [(-34.5, -30.9, 4), (-29.1, 32.4, 7), (34.1, 36.1, 11)],
    "citizens_bank_park": [(-34.0, -5.6, 11), (-4.4, 7.5, 6), (8.9, 34.8, 13)],
    "pnc_park": [(-33.4, -12.4, 6), (-11.2, 16.6, 10), (18.1, 33.0, 21)],
    "tropicana_field": [(-30.8, 34.6, 11)],
    "fenway_park": [(-33.3, -6.9, 37), (-5.7, 8.0, 18), (9.1, 30.3, 5)],
    "great_american_ball_park": [(-34.0, -11.3, 12), (-9.8, 34.3, 8)],
    "coors_field": [(-34.9, 2.7, 8), (4.2, 33.2, 17)],
    "kauffman_stadium": [(-32.0, 32.5, 9)],
    "comerica_park": [(-34.5, 6.4, 8), (7.9, 17.0, 11), (18.3, 32.5, 8)],
    "target_field": [(-34.1, 2.5, 8), (4.0, 34.8, 23)],
    "rate_field": [(-34.1, 34.8, 8)],
    "yankee_stadium": [(-34.1, 34.2, 8)],
}

HEADER = """\
# Outfield fence per park configuration: distance (ft) and height (ft) at Statcast spray
# angles (deg, -45 = LF line, 0 = straightaway CF, +45 = RF line). Provenance in
# data/README.md. first_date..last_date: the span (both inclusive) in which the
# configuration stood; empty first_date = from the park's opening, empty last_date = still
# standing. An empty height_ft = no sourced height. Source keys are defined in
# data/README.md. Rows with distance_source "geom_outline xS" are the points of the
# GeomMLBStadiums outline (every point in fair territory), scaled by S; the table is
# written by `python -m validation park_fences` (validation/park_fences.py).
"""
COLUMNS = ["park_id", "first_date", "last_date", "spray_angle_deg", "distance_ft",
           "height_ft", "distance_source", "height_source"]


def read_outline(path):
    """``{park_id: (spray_angle_deg, distance_ft)}`` of an outline CSV: the fair-territory
    points (|angle| < 45.5 deg) of each park's ``outfield_outer`` path, sorted by angle, in
    GeomMLBStadiums' own scale."""
    points = defaultdict(list)
    with open(path, newline="", encoding="utf-8") as f:
        for row in csv.DictReader(f):
            if row["segment"] == "outfield_outer" and row["team"] in TEAMS:
                points[TEAMS[row["team"]]].append((float(row["x"]), float(row["y"])))
    out = {}
    for pid, xy in points.items():
        xy = np.array(xy)
        dx, dy = xy[:, 0] - HOME[0], HOME[1] - xy[:, 1]
        angle = np.degrees(np.arctan2(dx, dy))
        dist = np.hypot(dx, dy) * FT_PER_UNIT
        keep = np.abs(angle) < 45.5
        order = np.argsort(angle[keep])
        out[pid] = (angle[keep][order], dist[keep][order])
    return out


def height_at(pid, angle_deg):
    """dinger-machine's wall height (ft) at true spray angles: the run holding the point's
    dinger-machine angle, else the nearest run's (NaN for a park without heights)."""
    runs = HEIGHT_RUNS.get(pid)
    angles = np.atleast_1d(np.asarray(angle_deg, float)) * DINGER_ANGLE
    if runs is None:
        return np.full(angles.shape, np.nan)
    out = np.empty(angles.shape)
    for i, a in enumerate(angles):
        gaps = [0.0 if lo <= a <= hi else min(abs(a - lo), abs(a - hi)) for lo, hi, _ in runs]
        out[i] = runs[int(np.argmin(gaps))][2]
    return out


def _read_table(path):
    lines = [line for line in Path(path).read_text(encoding="utf-8").splitlines()
             if line.strip() and not line.startswith("#")]
    return list(csv.DictReader(lines))


def _published(rows):
    """The configuration's published points: the rows not taken from the outline."""
    return [r for r in rows if not r["distance_source"].startswith("geom_outline")]


def _triangle(angle, centre, amount, half_width):
    return amount * np.clip(1 - np.abs(angle - centre) / half_width, 0, None)


def _change(pid, first, angle, dist, height, outline_2023):
    """The configuration standing from ``first`` (or None for the first one), applied to the
    scaled outline (see data/README.md for the sources)."""
    dist, height = dist.copy(), height.copy()
    if pid == "minute_maid_park" and first == "2017-01-01":
        dist = np.minimum(dist, 409.0)            # Tal's Hill removed: CF 436 -> 409
    elif pid == "loandepot_park" and first == "2016-01-01":
        dist = np.minimum(dist, 407.0)            # CF 418 -> 407
    elif pid == "loandepot_park" and first == "2020-01-01":
        dist = np.minimum(dist, 400.0)            # CF 407 -> 400
    elif pid == "comerica_park" and first == "2023-01-01":
        dist = np.minimum(dist, 412.0)            # CF 420 (422) -> 412
        height = np.where(angle > -10, 7.0, height)   # CF and RF walls -> 7 ft
    elif pid == "rogers_centre" and first == "2023-01-01":
        dist = dist + _triangle(angle, -22.5, -7.0, 20) + _triangle(angle, 22.5, -16.0, 20)
        height = np.select([angle < -35, angle < -10, angle <= 10, angle <= 35],
                           [14.3, 11.2, 8.0, 14.3], 12.6)
    elif pid == "kauffman_stadium" and first == "2026-01-01":
        dist = dist + _triangle(angle, -22.5, -9.0, 15) + _triangle(angle, 22.5, -9.0, 15)
        height = np.full(angle.shape, 8.5)
    elif pid == "camden_yards" and first in ("2022-01-01", "2025-01-01"):
        a23, d23 = outline_2023
        moved = np.where(angle < -16, np.interp(angle, a23, d23), dist) - dist
        share = 1.0 if first == "2022-01-01" else 0.5   # 384 ft (2022), 374 ft (2025)
        dist = dist + share * moved
        if first == "2022-01-01":
            height = np.where(angle < -16, 13.0, height)
        else:  # 8 ft in the alley, 6 ft 11 in (7) towards the corner
            height = np.where(angle < -16, np.where(angle <= -35, 7.0, 8.0), height)
    return dist, height


def build(outline_2018, outline_2023, table_path, scale="cf"):
    """The rows of the new fence table (dicts of :data:`COLUMNS`)."""
    outlines = read_outline(outline_2018)
    camden_2023 = read_outline(outline_2023)["camden_yards"]
    groups: dict = {}
    for row in _read_table(table_path):
        key = (row["park_id"], row["first_date"], row["last_date"])
        groups.setdefault(key, []).append(row)
    out = []
    for (pid, first, last), rows in groups.items():
        published = _published(rows)
        if pid not in outlines:
            out.extend(rows)
            continue
        angle, raw = outlines[pid]
        if scale == "cf":
            first_config = [r for (p, f, _), rr in groups.items() if p == pid and not f
                            for r in rr]
            cf = [float(r["distance_ft"]) for r in first_config
                  if float(r["spray_angle_deg"]) == 0.0]
            factor = cf[0] / float(np.interp(0.0, angle, raw))
        else:
            factor = 1.0
        # a scale of 3 decimals, as written in the source column
        factor = round(factor, 3)
        dist = raw * factor
        height = height_at(pid, angle)
        dist, height = _change(pid, first or None, angle, dist, height,
                               (camden_2023[0], camden_2023[1] * factor))
        merged = [dict(r) for r in published
                  if float(r["spray_angle_deg"]) in (-45.0, 0.0, 45.0)]
        fixed = [float(r["spray_angle_deg"]) for r in merged]
        for a, d, h in zip(angle, dist, height):
            if any(abs(a - f) < 0.5 for f in fixed) or abs(a) >= 45.0:
                continue
            merged.append({
                "park_id": pid, "first_date": first, "last_date": last,
                "spray_angle_deg": f"{a:.2f}", "distance_ft": f"{d:.1f}",
                "height_ft": "" if math.isnan(h) else f"{h:g}",
                "distance_source": f"geom_outline x{factor:.3f}",
                "height_source": "" if math.isnan(h) else "dinger_machine"})
        merged.sort(key=lambda r: float(r["spray_angle_deg"]))
        out.extend(merged)
    return out


def write(rows, path):
    buf = io.StringIO()
    writer = csv.DictWriter(buf, COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows({c: r.get(c, "") for c in COLUMNS} for r in rows)
    Path(path).write_text(HEADER + buf.getvalue(), encoding="utf-8")


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m validation park_fences",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("outline_2018")
    parser.add_argument("outline_2023")
    parser.add_argument("--table", default="data/park_fences.csv",
                        help="the current table: its published points and outline-less parks")
    parser.add_argument("--write", default=None, help="where to write the new table")
    parser.add_argument("--scale", choices=("cf", "own"), default="cf")
    args = parser.parse_args(argv)
    rows = build(args.outline_2018, args.outline_2023, args.table, args.scale)
    if args.write:
        write(rows, args.write)
    print(f"{len(rows)} rows")
    return 0
