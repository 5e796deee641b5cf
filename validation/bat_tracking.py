"""Real pitches and measured swings against tracked balls in play, in and out of sample.

Fits what the measured swing does not fix (the contact's place along the bat and its
undercut, how the contact moves with the bat speed, the measurement errors of the attack
angle, the bat speed and the attack direction) to the tracked balls in play of the
``--fit`` files, each row conditioned on its measured pitch and swing, and judges
``studies/bat_tracking.toml`` with the fitted values on the ``--judge`` files, the fit
files beside them (docs/bat_tracking.md)::

    NUMBA_NUM_THREADS=1 .venv/bin/python -m validation bat_tracking \\
        --fit statcast_2024_skubal.csv,statcast_2024_ohtani.csv \\
        --cross statcast_2025-05-01.csv

Files are names in ``../shared/data/statcast/`` (its ``more/``, ``data/``, or paths);
``name#k/n`` is the k-th of n parts of the file's games. ``--cross FILE`` judges each part
of FILE by a fit to ``--fit`` and the other parts, and pools the parts. Steps:

1. the errors and the trend (:func:`choose`): for each node of a grid, the contact fitted
   with ``fit_population`` (``swing = true``), then the draws for the fit files' rows
   compared with them (:func:`distance`: every file's rows in bat-speed bin x launch-speed
   bin, and the slope of launch angle on attack angle); the nearest node is kept (a file
   without attack angles says nothing about their error); the attack direction's error by
   the slope of the spray angle on it;
2. the contact fitted again there (the reported values and errors);
3. per file: KS distances of launch speed and angle (``samples`` draws), each row's
   calibration (the share of rows whose measured value lies above the row's simulated
   90th percentile, below its 10th, read from its rank among the row's draws:
   ``mcbat.stats.compare.per_row``), the mean launch speed per bat-speed bin (rows >= 100
   are held to 2 mph), the slopes, ``q`` and its upper edge, the backspin.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd

import mcbat.statcast as sc
from mcbat.runner.pitches import load_pitches
from mcbat.stats.compare.per_row import MIN_DRAWS, ranks
from mcbat.stats.models.simulate import solve_game_inputs
from mcbat.stats.population.fit import fit_population
from mcbat.stats.population.table import write_pitches
from mcbat.study.spec import Study

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data" / "statcast"
STUDY = ROOT / "studies" / "bat_tracking.toml"
#: The study whose fixed settings the fits and judgements use (``--study``; everything but
#: the contact, the swing errors and the bat-speed trend, which are fitted or given).
BASE_STUDY = [STUDY]
#: Keys of the base study replaced (``"contact.plate_x_trend"`` -> its table, None: removed;
#: ``"restitution.location"`` -> a table's name), from ``--plate-x`` and ``--location``.
OVERRIDES: dict = {}
#: The undercut's bat-speed trend (in per 10 mph) instead of the study's (``--undercut-trend``).
UNDERCUT_TREND: list = []
#: The bat-speed outliers' table instead of the study's (``--bat-speed-outliers``; None:
#: without).
OUTLIERS: list = []
FREE = ("contact.from_barrel_end.mean", "contact.from_barrel_end.std",
        "contact.undercut.mean", "contact.undercut.std")
BINS = (0.0, 65.0, 70.0, 75.0, 80.0, 200.0)
ERROR_GRID = {"attack_angle": (0.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0),
              "bat_speed": (0.0, 1.0, 2.0, 3.0, 4.0, 5.0)}
TREND_GRID = (-2.0, -1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5)
"""The contact's bat-speed trend (in per 10 mph) scanned."""
ATTACK_START = 5.0
"""The attack angle's error (deg) the first scan of the bat-speed error and trend uses."""
DIRECTION_GRID = (0.0, 3.0, 6.0, 9.0, 12.0)
"""The attack direction's error (deg) scanned."""
LS_BINS = 6
"""Launch-speed bins (equal counts of each file's rows) of :func:`distance`."""
TREND_REFERENCE = 70.0
"""The bat speed (mph) at which the fitted contact distribution's mean applies."""
IN_ALL = False
QUICK_ARGS = ["--fit", "statcast_2024_skubal.csv", "--judge", "statcast_2025-05-01.csv",
              "--samples", "20000"]


def resolve(name) -> Path:
    """A file name in the shared Statcast folder (or its ``more/``), in ``data/``, or a
    path."""
    path = Path(name)
    for candidate in (path, DATA / name, DATA / "more" / name, ROOT / "data" / name):
        if candidate.exists():
            return candidate
    return DATA / name


def split_name(name):
    """``"file.csv#k/n"`` -> ``("file.csv", k, n)``: the k-th of n parts of the file's
    games (game_pk in increasing order, game ``i`` in part ``i % n + 1``); a day's games
    share no batter, so the parts are independent samples. ``"file.csv"`` -> ``(name,
    None, None)``."""
    if "#" not in name:
        return name, None, None
    base, part = name.rsplit("#", 1)
    k, n = (int(x) for x in part.split("/"))
    if not 1 <= k <= n:
        raise ValueError(f"{name}: need 1 <= k <= n in '#k/n'")
    return base, k, n


def tracked(names) -> pd.DataFrame:
    """The tracked balls in play (a batted-ball type, bat speed, launch speed and angle, the
    pitch at the plate) of the files, as one tidy table (``file``: which file). A name
    ``file#k/n`` takes the k-th of n parts of the file's games (:func:`split_name`)."""
    frames = []
    for name in names:
        base, k, n = split_name(name)
        t = sc.read(resolve(base))
        if k is not None:
            games = np.sort(t["game_pk"].dropna().unique())
            part = {g: i % n + 1 for i, g in enumerate(games)}
            t = t[t["game_pk"].map(part) == k]
        keep = (t["bb_type"].notna() & t["bat_speed"].notna() & t["launch_speed"].notna()
                & t["launch_angle"].notna() & t["pitch_speed"].notna()
                & t["vertical_approach_angle"].notna()
                & t["handedness"].isin(["R", "L"]))
        t = t[keep].copy()
        if "attack_angle" in t:
            t = t[~(t["attack_angle"].abs() > 45.0)]  # (the study's range check)
        t["file"] = Path(name).name
        frames.append(t)
    out = pd.concat(frames, ignore_index=True)
    out.attrs = frames[0].attrs
    return out


def study_definition(values=None, errors=None, trend=None) -> dict:
    """``studies/bat_tracking.toml`` with fitted contact ``values`` (``{"contact.undercut.
    mean": in, ...}``), swing errors (``{"attack_angle": deg, "bat_speed": mph,
    "attack_direction": deg}``) and the contact's bat-speed trend (in per 10 mph; None:
    the study's)."""
    data = tomllib.loads(BASE_STUDY[0].read_text())
    for key, table in OVERRIDES.items():
        section, name = key.split(".")
        if table is None:
            data[section].pop(name, None)
        else:
            data[section][name] = table
    for name, value in (values or {}).items():
        section, key, field = name.split(".")
        data[section][key][field] = float(value)
    for key, value in (errors or {}).items():
        unit = "deg" if key != "bat_speed" else "mph"
        data["pitches"].setdefault("swing_error", {})[key] = {"value": float(value),
                                                              "unit": unit}
    if OUTLIERS:
        swing_error = data["pitches"].setdefault("swing_error", {})
        if OUTLIERS[0] is None:
            swing_error.pop("bat_speed_outliers", None)
        else:
            swing_error["bat_speed_outliers"] = OUTLIERS[0]
    if trend is not None or UNDERCUT_TREND:
        # (the undercut's shift of the study's table, or of --undercut-trend, is kept)
        table = data["contact"].setdefault("bat_speed_trend", {
            "reference": {"value": TREND_REFERENCE, "unit": "mph"},
            "per": {"value": 10, "unit": "mph"}})
        table["per"] = {"value": 10, "unit": "mph"}
        table["reference"] = {"value": TREND_REFERENCE, "unit": "mph"}
        if trend is not None:
            table["from_barrel_end"] = {"value": float(trend), "unit": "in"}
        if UNDERCUT_TREND:
            table["undercut"] = {"value": float(UNDERCUT_TREND[0]), "unit": "in"}
    return data


def _study(data, table, workdir, player_levels=True):
    """The study drawing its pitches and swings from ``table``'s rows (in order);
    ``player_levels=False``: the league's contact on every row, as a fit of it needs."""
    data = json.loads(json.dumps(data))
    path = Path(workdir) / f"rows{len(table)}_{id(table)}.csv"
    write_pitches(table.reset_index(drop=True), path)
    data["pitches"] = {k: v for k, v in data["pitches"].items() if k != "bb_type"}
    data["pitches"]["file"] = str(path)
    return load_pitches(Study.from_dict(data, source=STUDY), player_levels=player_levels)


def simulate(data, table, samples, seed, workdir) -> dict:
    """Draws of the study for ``table``'s rows: ``row`` (the table's row each draw meets)
    and the draws' ``launch_speed`` (mph), ``launch_angle``, ``spray_angle`` (deg) and
    ``backspin`` (rpm)."""
    return draws(_study(data, table, workdir), samples, seed)


def draws(study, samples, seed) -> dict:
    """:func:`simulate`'s draws of a loaded study."""
    inputs = study.sample_inputs(0, samples, seed)
    row = study.pitch_identifiers(0, samples, seed)["source_row"]
    out, ok = solve_game_inputs(study, inputs)
    sim = {k: np.asarray(out[k], float)[ok]
           for k in ("launch_speed", "launch_angle", "spray_angle", "backspin")}
    sim["row"] = row[ok]
    return sim


def slopes(bat, ls, attack, la):
    """Least-squares slopes of launch speed on bat speed and launch angle on attack angle
    (NaN without attack angles)."""
    s_ls = float(np.polyfit(bat, ls, 1)[0])
    ok = np.isfinite(attack)
    s_la = float(np.polyfit(attack[ok], la[ok], 1)[0]) if ok.sum() > 10 else float("nan")
    return s_ls, s_la


def _column(table, name):
    return (table[name].to_numpy(float) if name in table
            else np.full(len(table), np.nan))


def data_slopes(table, boots=300, seed=0):
    """The measured slopes and their bootstrap errors."""
    bat, ls = table["bat_speed"].to_numpy(float), table["launch_speed"].to_numpy(float)
    attack, la = _column(table, "attack_angle"), table["launch_angle"].to_numpy(float)
    rng = np.random.default_rng(seed)
    reps = [slopes(bat[i], ls[i], attack[i], la[i])
            for i in (rng.integers(0, len(table), len(table)) for _ in range(boots))]
    return slopes(bat, ls, attack, la), tuple(np.nanstd(np.array(reps), axis=0))


def spray_slope(table, row=None, spray=None):
    """Slope of the spray angle (mirrored for left-handed batters: > 0 towards the
    batter's opposite field) on the measured attack direction (NaN without one)."""
    direction = _column(table, "attack_direction")
    hand = np.where(table["handedness"].to_numpy() == "R", 1.0, -1.0)
    if row is None:
        row, spray = np.arange(len(table)), table["spray_angle"].to_numpy(float)
    x, y = direction[row], hand[row] * spray
    ok = np.isfinite(x) & np.isfinite(y)
    return float(np.polyfit(x[ok], y[ok], 1)[0]) if ok.sum() > 10 else float("nan")


def fit(table, errors, trend=None, seed=1):
    """The contact fitted with ``fit_population`` at the swing ``errors`` and the
    contact's bat-speed ``trend`` (in per 10 mph)."""
    study = _study_obj(study_definition(errors=errors, trend=trend))
    t = table.copy()
    t.attrs = table.attrs
    return fit_population(study, t, FREE, seed=seed)


def _study_obj(data):
    """The study itself (its own [pitches] file is replaced by the fit's rows)."""
    with tempfile.TemporaryDirectory() as tmp:
        return _study(data, _placeholder(), tmp, player_levels=False)


def _placeholder():
    t = pd.DataFrame({"pitch_speed": [40.0], "vertical_approach_angle": [-6.0],
                      "horizontal_approach_angle": [0.0], "spin_rate": [2200.0],
                      "spin_axis": [180.0], "bat_speed": [70.0], "attack_angle": [10.0],
                      "attack_direction": [0.0], "handedness": ["R"], "plate_x": [0.0],
                      "plate_z": [2.5], "swing_length": [7.2]})
    return t


def bin_means(table, row=None, ls=None):
    """Per bat-speed bin (:data:`BINS`, by the measured bat speed): rows, the mean launch
    speed (of the rows, or of the draws ``ls`` meeting rows ``row``) and its standard
    error."""
    bat = table["bat_speed"].to_numpy(float)
    if row is None:
        row, ls = np.arange(len(table)), table["launch_speed"].to_numpy(float)
    out = []
    for lo, hi in zip(BINS[:-1], BINS[1:]):
        rows = int(np.sum((bat >= lo) & (bat < hi)))
        sel = (bat[row] >= lo) & (bat[row] < hi)
        mean = float(ls[sel].mean()) if sel.any() else float("nan")
        se = float(ls[sel].std() / np.sqrt(max(rows, 1))) if sel.any() else float("nan")
        out.append((rows, mean, se))
    return out


def _cells(bat, ls, edges):
    """Counts of rows in (bat-speed bin of :data:`BINS`) x (launch-speed bin of ``edges``)."""
    i = np.clip(np.searchsorted(BINS, bat, side="right") - 1, 0, len(BINS) - 2)
    j = np.searchsorted(edges, ls, side="right")
    return np.bincount(i * (len(edges) + 1) + j,
                       minlength=(len(BINS) - 1) * (len(edges) + 1)).astype(float)


def measured_targets(table):
    """What :func:`distance` compares with: per file, its launch-speed bin edges (equal
    counts, :data:`LS_BINS` bins) and its counts in (bat-speed bin) x (launch-speed bin);
    and the slopes."""
    files = table["file"].to_numpy()
    per_file = {}
    for f in dict.fromkeys(files):
        t = table[files == f]
        ls = t["launch_speed"].to_numpy(float)
        edges = np.unique(np.quantile(ls, np.arange(1, LS_BINS) / LS_BINS))
        per_file[f] = (edges, _cells(t["bat_speed"].to_numpy(float), ls, edges))
    return per_file, data_slopes(table)


def distance(table, sim, measured=None) -> float:
    """How far the draws lie from the rows: Pearson's chi2 of every file's rows in (bat-speed
    bin) x (launch-speed bin) against the draws meeting that file's rows (scaled to its row
    count; cells the draws give less than one row are merged into one), which weighs the
    launch speeds' level, spread and upper edge in every bat-speed bin; plus the squared
    difference of the slope of launch angle on attack angle in units of its bootstrap error
    (where the rows have attack angles)."""
    measured = measured or measured_targets(table)
    per_file, ((_, s_la), (_, e_la)) = measured
    files = table["file"].to_numpy()
    bat = table["bat_speed"].to_numpy(float)
    d = 0.0
    for name, (edges, observed) in per_file.items():
        sel = files[sim["row"]] == name
        expected = _cells(bat[sim["row"][sel]], sim["launch_speed"][sel], edges)
        expected *= observed.sum() / max(expected.sum(), 1.0)
        small = expected < 1.0
        o = np.append(observed[~small], observed[small].sum())
        e = np.append(expected[~small], expected[small].sum())
        keep = e > 0
        d += float(np.sum((o[keep] - e[keep]) ** 2 / e[keep]))
    if np.isfinite(s_la):
        attack = _column(table, "attack_angle")
        m_la = slopes(np.zeros(2) + [0, 1], np.zeros(2), attack[sim["row"]],
                      sim["launch_angle"])[1]
        d += ((m_la - s_la) / e_la) ** 2
    return float(d)


def _values(result):
    return {p["name"]: p["value"] for p in result.parameters}


def choose(table, samples, workdir, seed=7) -> dict:
    """The swing errors and the contact's bat-speed trend whose draws lie nearest the
    rows (:func:`distance`), the contact refitted at every node: bat-speed error x trend
    on a grid (at the attack angle's error :data:`ATTACK_START` where the rows have attack
    angles), then the attack angle's error, then bat-speed error x trend again at it, on
    the neighbouring nodes; the attack direction's error last, by the slope of the spray
    angle on it. Returns ``{"errors", "trend", "trend_interval", "scan"}``."""
    measured = measured_targets(table)
    has_attack = np.isfinite(_column(table, "attack_angle")).sum() > 10
    scan = []

    def node(ea, eb, tr):
        done = [x["distance"] for x in scan if (x["attack_angle"], x["bat_speed"],
                                                x["trend"]) == (ea, eb, tr)]
        if done:
            return done[0]
        errors = {"attack_angle": ea, "bat_speed": eb}
        result = fit(table, errors, tr)
        data = study_definition(_values(result), errors, tr)
        d = distance(table, simulate(data, table, samples, seed, workdir), measured)
        scan.append({"attack_angle": ea, "bat_speed": eb, "trend": tr, "distance": d,
                     "chi2": result.chi2, "dof": result.dof})
        print(f"  errors aa {ea:g} deg, bat {eb:g} mph, trend {tr:+g} in/10 mph: distance "
              f"{d:.2f}; chi2 of the contact fit {result.chi2:.1f}/{result.dof}", flush=True)
        return d

    def grid(ea, bats, trends):
        best = min((node(ea, eb, tr), eb, tr) for eb in bats for tr in trends)
        return best[1], best[2]

    ea = ATTACK_START if has_attack else 0.0
    eb, tr = grid(ea, ERROR_GRID["bat_speed"], TREND_GRID)
    if has_attack:
        ea = min((node(a, eb, tr), a) for a in ERROR_GRID["attack_angle"])[1]
        eb, tr = grid(ea, _near(ERROR_GRID["bat_speed"], eb), _near(TREND_GRID, tr))
    errors = {"attack_angle": ea, "bat_speed": eb}
    if has_attack:
        errors["attack_direction"] = _choose_direction(table, errors, tr, samples, seed,
                                                       workdir)
    last = [s for s in scan if s["attack_angle"] == ea]
    return {"errors": errors, "trend": tr, "trend_interval": _interval(last), "scan": scan}


def _near(grid, value):
    """``value`` and its neighbours on ``grid``."""
    i = grid.index(value)
    return grid[max(0, i - 1):i + 2]


def _interval(scan):
    """The trends whose distance (the smallest over the bat-speed errors) lies within 1 of
    the least: ``(low, high)`` in in/10 mph, linearly interpolated between nodes (an end of
    the grid when the rise stays under 1 there)."""
    trends = sorted({s["trend"] for s in scan})
    prof = np.array([min(s["distance"] for s in scan if s["trend"] == t) for t in trends])
    i = int(np.argmin(prof))
    level = prof[i] + 1.0

    def walk(step):
        j = i
        while 0 <= j + step < len(trends):
            if prof[j + step] > level:
                t0, t1, d0, d1 = trends[j], trends[j + step], prof[j], prof[j + step]
                return t0 + (level - d0) / (d1 - d0) * (t1 - t0)
            j += step
        return trends[j]

    return walk(-1), walk(+1)


def _choose_direction(table, errors, trend, samples, seed, workdir):
    """The attack direction's error whose simulated spray slope lies nearest the rows'."""
    target = spray_slope(table)
    result = fit(table, errors, trend)
    best = None
    for ed in DIRECTION_GRID:
        data = study_definition(_values(result), {**errors, "attack_direction": ed}, trend)
        sim = simulate(data, table, samples, seed, workdir)
        slope = spray_slope(table, sim["row"], sim["spray_angle"])
        print(f"  attack direction error {ed:g} deg: spray slope {slope:.3f} (data "
              f"{target:.3f})", flush=True)
        if best is None or abs(slope - target) < best[0]:
            best = (abs(slope - target), ed)
    return best[1]


BATTER_ROWS = 4
"""Rows a batter needs in a file for :func:`batter_slopes` to use them."""


def batter_slopes(table, row=None, ls=None, boots=0, seed=0):
    """The launch speed's slope on the bat speed split in two (least squares of launch
    speed on ``bat speed - the batter's mean`` and ``the batter's mean``, over the rows of
    batters with at least :data:`BATTER_ROWS` rows; the batter's mean is over his rows of
    ``table``): ``(within a batter, between batters)`` in mph per mph, of the rows or of
    the draws ``ls`` meeting rows ``row``; with ``boots``, also their bootstrap standard
    errors (batters resampled). NaN without two such batters."""
    batter = table["batter"].to_numpy()
    bat = table["bat_speed"].to_numpy(float)
    grouped = table.groupby("batter")["bat_speed"]
    count = grouped.transform("size").to_numpy()
    mean = grouped.transform("mean").to_numpy(float)
    if row is None:
        row, ls = np.arange(len(table)), table["launch_speed"].to_numpy(float)
    keep = count[row] >= BATTER_ROWS
    if len(np.unique(batter[row][keep])) < 2:
        return (float("nan"),) * (4 if boots else 2)

    def fit_rows(sel):
        r = row[sel]
        x = np.column_stack([np.ones(r.size), bat[r] - mean[r], mean[r]])
        return np.linalg.lstsq(x, ls[sel], rcond=None)[0][1:]

    within, between = (float(v) for v in fit_rows(keep))
    if not boots:
        return within, between
    rng = np.random.default_rng(seed)
    kept = np.flatnonzero(keep)
    by_batter = {b: kept[batter[row][kept] == b] for b in np.unique(batter[row][kept])}
    names = list(by_batter)
    reps = [fit_rows(np.concatenate([by_batter[names[i]]
                                     for i in rng.integers(0, len(names), len(names))]))
            for _ in range(boots)]
    err = np.std(np.array(reps), axis=0)
    return within, between, float(err[0]), float(err[1])


def collision_efficiency(table, row, ls):
    """Statcast's ``q`` of the rows (``row``: which row each launch speed ``ls`` belongs
    to): ``(launch speed - bat speed)/(pitch speed + bat speed)`` with the row's measured
    bat speed and plate speed, as the data's is computed."""
    bat = table["bat_speed"].to_numpy(float)[row]
    pitch = table["pitch_speed"].to_numpy(float)[row]
    return (ls - bat) / (pitch + bat)


PLATE_X_BINS = (-10.0, -0.6, -0.3, 0.0, 0.3, 0.6, 10.0)
"""Where the pitch crossed the plate, ft from its centre away from the batter (Statcast's
``plate_x`` for a right-handed batter, its negative for a left-handed one)."""
PLATE_Z_BINS = (-10.0, 1.8, 2.3, 2.8, 3.3, 10.0)
"""How high the pitch crossed the plate, ft (Statcast's ``plate_z``)."""


def location_bins(table, row, draws, observable, edges) -> list[dict]:
    """Per bin of ``edges`` of the pitch's location (:data:`PLATE_X_BINS`: ``plate_x``
    away from the batter; :data:`PLATE_Z_BINS`: ``plate_z``): rows, the measured mean of
    ``observable`` (``"launch_speed"`` or ``"launch_angle"``) and its standard error, the
    model's mean (of ``draws``, meeting rows ``row``), and the shares of rows above their
    own simulated 90th and below their 10th percentile (ranked among their draws:
    ``mcbat.stats.compare.per_row``)."""
    if edges is PLATE_X_BINS:
        plate_x = _column(table, "plate_x")
        where = np.where(table["handedness"].to_numpy() == "L", -plate_x, plate_x)
    else:
        where = _column(table, "plate_z")
    measured = table[observable].to_numpy(float)
    u = np.full(len(table), np.nan)
    judged, u_judged = ranks(row, draws, measured, MIN_DRAWS)
    u[judged] = u_judged
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        rows = np.flatnonzero((where >= lo) & (where < hi))
        if rows.size < 10:
            continue
        mine = u[rows][np.isfinite(u[rows])]
        out.append({"bin": f"{lo:+.1f} to {hi:+.1f}", "rows": int(rows.size),
                    "measured": float(measured[rows].mean()),
                    "se": float(measured[rows].std() / np.sqrt(rows.size)),
                    "model": float(draws[np.isin(row, rows)].mean()),
                    "above_p90": float(np.mean(mine > 0.9)) if mine.size else 0.0,
                    "below_p10": float(np.mean(mine < 0.1)) if mine.size else 0.0})
    return out


def _median(values) -> float:
    """The median, NaN for no values."""
    return float(np.median(values)) if values.size else float("nan")


def judge(data, table, samples, seed, workdir) -> dict:
    """The acceptance numbers of the study ``data`` on ``table``'s rows, and what the
    figures draw."""
    return evaluate(table, simulate(data, table, samples, seed, workdir))


def exact_model_share(draws):
    """The share of rows an exact model puts above their 90th percentile (or below their
    10th) when each percentile is numpy's (linear rule) of ``draws`` draws of the row's own
    distribution: the measured value is then one more draw, and ranks above the draws'
    position ``0.9 (n - 1)`` with probability ``(0.1 n + 0.9) / (n + 1)`` (13.8 % at 20
    draws, 10.5 % at 175)."""
    n = np.asarray(draws, np.float64)
    return (0.1 * n + 0.9) / (n + 1.0)


def evaluate(table, sim) -> dict:
    """The acceptance numbers of draws ``sim`` (:func:`simulate`) of ``table``'s rows."""
    from scipy import stats

    row, ls, la = sim["row"], sim["launch_speed"], sim["launch_angle"]
    out = {"rows": len(table)}
    m_ls, m_la = table["launch_speed"].to_numpy(float), table["launch_angle"].to_numpy(float)
    for name, draws, meas in (("launch_speed", ls, m_ls), ("launch_angle", la, m_la)):
        test = stats.ks_2samp(draws, meas)
        out[f"ks_{name}"], out[f"ks_{name}_p"] = float(test.statistic), float(test.pvalue)
    # the distance an exact model's rows exceed half the time (so many rows: sampling)
    out["ks_exact_median"] = float(stats.kstwo.ppf(0.5, len(table)))
    judged = np.bincount(row, minlength=len(table))
    judged = judged[judged >= MIN_DRAWS]
    out["draws_per_row"] = float(np.median(judged)) if judged.size else 0.0
    out["exact_share"] = float(np.mean(exact_model_share(judged)))
    for name, draws_all, meas in (("launch_speed", ls, m_ls), ("launch_angle", la, m_la)):
        _, u = ranks(row, draws_all, meas, MIN_DRAWS)
        out[f"{name}_above_p90"] = float(np.mean(u > 0.9))
        out[f"{name}_below_p10"] = float(np.mean(u < 0.1))
    model_bins = bin_means(table, row, ls)
    bat = table["bat_speed"].to_numpy(float)
    q_data = collision_efficiency(table, np.arange(len(table)), m_ls)
    q_model = collision_efficiency(table, row, ls)
    out["bat_speed_bins"] = [
        {"bin": f"{lo:.0f}-{hi:.0f}" if hi < 200 else f"{lo:.0f}+", "rows": b[0],
         "measured": b[1], "se": b[2], "model": m[1],
         "q_median": _median(q_data[(bat >= lo) & (bat < hi)]),
         "q_median_model": _median(q_model[(bat[row] >= lo) & (bat[row] < hi)])}
        for lo, hi, b, m in zip(BINS[:-1], BINS[1:], bin_means(table), model_bins)]
    out["plate_x_bins"] = location_bins(table, row, ls, "launch_speed", PLATE_X_BINS)
    out["plate_x_chi2"] = float(sum(((b["model"] - b["measured"]) / b["se"]) ** 2
                                    for b in out["plate_x_bins"]))
    out["plate_z_bins"] = location_bins(table, row, la, "launch_angle", PLATE_Z_BINS)
    out["plate_z_chi2"] = float(sum(((b["model"] - b["measured"]) / b["se"]) ** 2
                                    for b in out["plate_z_bins"]))
    attack = _column(table, "attack_angle")
    out["attack_bins"] = []
    if np.isfinite(attack).sum() > 10:
        for lo in range(-15, 35, 5):
            rows = (attack >= lo) & (attack < lo + 5)
            sims = (attack[row] >= lo) & (attack[row] < lo + 5)
            if rows.sum() >= 10:
                out["attack_bins"].append({"bin": lo + 2.5, "rows": int(rows.sum()),
                                           "measured": float(m_la[rows].mean()),
                                           "se": float(m_la[rows].std()
                                                       / np.sqrt(rows.sum())),
                                           "model": float(la[sims].mean())})
    out["slopes_model"] = slopes(bat[row], ls, attack[row], la)
    if "batter" in table:
        out["batter_slopes_data"] = batter_slopes(table, boots=300)
        out["batter_slopes_model"] = batter_slopes(table, row, ls)
    out["slopes_data"] = slopes(bat, m_ls, attack, m_la)
    out["spray_slope_model"] = spray_slope(table, row, sim["spray_angle"])
    out["spray_slope_data"] = spray_slope(table)
    out["above_50_model"] = float(np.mean(la > 50.0))
    out["means"] = {"launch_speed": (float(m_ls.mean()), float(ls.mean())),
                    "launch_angle": (float(m_la.mean()), float(la.mean()))}
    out["speed_percentiles"] = {"data": np.percentile(m_ls, (10, 25, 50, 75, 90)).tolist(),
                                "model": np.percentile(ls, (10, 25, 50, 75, 90)).tolist()}
    out["above_50_data"] = float(np.mean(m_la > 50.0))
    # the launch speed of the highest balls: where the launch angles above their row's
    # 90th percentile come from
    out["high_angles"] = [
        {"bin": f"{lo:g}-{hi:g}", "share_model": float(np.mean((la >= lo) & (la < hi))),
         "share_data": float(np.mean((m_la >= lo) & (m_la < hi))),
         "speed_model": float(np.median(ls[(la >= lo) & (la < hi)]))
         if np.any((la >= lo) & (la < hi)) else float("nan"),
         "speed_data": float(np.median(m_ls[(m_la >= lo) & (m_la < hi)]))
         if np.any((m_la >= lo) & (m_la < hi)) else float("nan")}
        for lo, hi in ((40.0, 50.0), (50.0, 60.0), (60.0, 90.0))]
    out["q"] = {"data": q_data, "model": q_model,
                "p90_by_bin": [
                    (float(np.quantile(q_data[(bat >= lo) & (bat < hi)], 0.9))
                     if np.sum((bat >= lo) & (bat < hi)) >= 10 else float("nan"),
                     float(np.quantile(q_model[(bat[row] >= lo) & (bat[row] < hi)], 0.9))
                     if np.any((bat[row] >= lo) & (bat[row] < hi)) else float("nan"))
                    for lo, hi in zip(BINS[:-1], BINS[1:])]}
    out["spin"] = {"launch_angle": la, "spray_angle": sim["spray_angle"],
                   "backspin": sim["backspin"],
                   "handedness": table["handedness"].to_numpy()[row]}
    out["backspin_slopes"] = backspin_slopes(out["spin"])
    return out


def backspin_slopes(spin) -> tuple:
    """``(model, Nathan's, mean ratio)``: the least-squares slope (rpm per deg) of the
    drawn balls' backspin on their launch angle over 10-40 deg, the same of Nathan's
    average spin model at the same balls (launch and spray angles, the batter's side),
    and the ratio of their means there."""
    from mcbat.statcast.spin import nathan_average_spin

    la = spin["launch_angle"]
    used = (la >= 10.0) & (la <= 40.0) & np.isfinite(spin["backspin"])
    if used.sum() < 100:
        return float("nan"), float("nan"), float("nan")
    nathan, _ = nathan_average_spin(la[used], spin["spray_angle"][used],
                                    spin["handedness"][used])
    backspin = spin["backspin"][used]
    return (float(np.polyfit(la[used], backspin, 1)[0]),
            float(np.polyfit(la[used], nathan, 1)[0]), float(backspin.mean() / nathan.mean()))


def verdict(r) -> list[str]:
    """Which acceptance numbers hold."""
    ok = []
    ok.append(("KS launch speed <= 0.05", r["ks_launch_speed"] <= 0.05))
    ok.append(("KS launch angle <= 0.05", r["ks_launch_angle"] <= 0.05))
    for name in ("launch_speed", "launch_angle"):
        for tail in ("above_p90", "below_p10"):
            ok.append((f"{name} {tail} in 7-13 %", 0.07 <= r[f"{name}_{tail}"] <= 0.13))
    for b in r["bat_speed_bins"]:
        if b["rows"] >= 100:
            ok.append((f"bin {b['bin']} within 2 mph", abs(b["model"] - b["measured"]) <= 2))
    return [f"{'PASS' if good else 'FAIL'} {what}" for what, good in ok]


def summary_table(judged) -> list[str]:
    """One markdown row per judged export (``(label, result)`` pairs): the numbers the
    model is held to, and how many of them hold."""
    lines = ["| export | tracked balls in play | KS launch speed / angle (p-value) | KS an "
             "exact model's rows exceed half the time | launch speed above p90 / below p10 | "
             "launch angle above p90 / below p10 | bat-speed bins of 100 rows or more: model "
             "- measured (mph) | held |",
             "|---|---|---|---|---|---|---|---|"]
    for label, r in judged:
        bins = ", ".join(f"{b['bin']}: {b['model'] - b['measured']:+.1f}"
                         for b in r["bat_speed_bins"] if b["rows"] >= 100) or "none"
        held = verdict(r)
        lines.append(
            f"| {label} | {r['rows']} | {r['ks_launch_speed']:.3f} "
            f"({r['ks_launch_speed_p']:.2f}) / {r['ks_launch_angle']:.3f} "
            f"({r['ks_launch_angle_p']:.2f}) | {r['ks_exact_median']:.3f} | "
            f"{r['launch_speed_above_p90']:.1%} / "
            f"{r['launch_speed_below_p10']:.1%} | {r['launch_angle_above_p90']:.1%} / "
            f"{r['launch_angle_below_p10']:.1%} | {bins} | "
            f"{sum(v.startswith('PASS') for v in held)} of {len(held)} |")
    return lines


def report(label, r) -> list[str]:
    """Lines of one judged file."""
    lines = [f"{label}: {r['rows']} rows",
             f"  KS launch speed {r['ks_launch_speed']:.3f}, launch angle "
             f"{r['ks_launch_angle']:.3f}",
             f"  launch speed: above row's p90 {r['launch_speed_above_p90']:.1%}, below p10 "
             f"{r['launch_speed_below_p10']:.1%}",
             f"  launch angle: above row's p90 {r['launch_angle_above_p90']:.1%}, below p10 "
             f"{r['launch_angle_below_p10']:.1%}",
             f"  (each row's measured value ranked among its {r['draws_per_row']:.0f} draws, "
             f"median, ties spread: an exact model reads 10 %; numpy's linear percentile of "
             f"that many would read {r['exact_share']:.1%})",
             f"  slopes model {r['slopes_model'][0]:.2f} mph/mph, {r['slopes_model'][1]:.2f} "
             f"deg/deg; data {r['slopes_data'][0]:.2f}, {r['slopes_data'][1]:.2f}",
             f"  spray on attack direction: model {r['spray_slope_model']:.2f}, data "
             f"{r['spray_slope_data']:.2f}",
             f"  launch angle > 50 deg: model {r['above_50_model']:.1%}, data "
             f"{r['above_50_data']:.1%}",
             "  launch speed's 10/25/50/75/90th percentiles: data " + "/".join(
                 f"{v:.1f}" for v in r["speed_percentiles"]["data"]) + ", model " + "/".join(
                 f"{v:.1f}" for v in r["speed_percentiles"]["model"]) + " mph"]
    if "backspin_slopes" in r:
        model, nathan, ratio = r["backspin_slopes"]
        lines.append(f"  backspin on launch angle, 10-40 deg: model {model:.0f} rpm/deg, Nathan's "
                     f"model on the same balls {nathan:.0f}; mean backspin / Nathan's "
                     f"{ratio:.2f}")
    for h in r.get("high_angles", []):
        lines.append(f"  launch angle {h['bin']} deg: share model {h['share_model']:.1%}, data "
                     f"{h['share_data']:.1%}; median launch speed model "
                     f"{h['speed_model']:.1f}, data {h['speed_data']:.1f} mph")
    if "batter_slopes_data" in r:
        w, b, ew, eb = r["batter_slopes_data"]
        mw, mb = r["batter_slopes_model"]
        lines.append(f"  launch speed on bat speed, within a batter: model {mw:.2f}, data "
                     f"{w:.2f} +- {ew:.2f}; between batters: model {mb:.2f}, data {b:.2f} "
                     f"+- {eb:.2f} mph/mph (batters with >= {BATTER_ROWS} rows)")
    for b in r["bat_speed_bins"]:
        lines.append(f"  bat speed {b['bin']:>6} mph: {b['rows']:4d} rows, measured "
                     f"{b['measured']:6.1f} +- {b['se']:.1f}, model {b['model']:6.1f} mph; "
                     f"median q {b['q_median']:.3f}, model {b['q_median_model']:.3f}")
    if r.get("plate_x_bins"):
        lines.append(f"  launch speed by where the pitch crossed the plate: sum of "
                     f"((model - measured)/se)^2 over the bins {r['plate_x_chi2']:.1f} "
                     f"({len(r['plate_x_bins'])} bins)")
    for b in r.get("plate_x_bins", []):
        lines.append(f"  plate_x {b['bin']:>12} ft away: {b['rows']:4d} rows, measured "
                     f"{b['measured']:6.1f} +- {b['se']:.1f}, model {b['model']:6.1f} mph; "
                     f"above p90 {b['above_p90']:.0%}, below p10 {b['below_p10']:.0%}")
    if r.get("plate_z_bins"):
        lines.append(f"  launch angle by the pitch's height: sum of ((model - measured)/se)^2 "
                     f"over the bins {r['plate_z_chi2']:.1f} ({len(r['plate_z_bins'])} bins)")
    for b in r.get("plate_z_bins", []):
        lines.append(f"  plate_z {b['bin']:>12} ft: {b['rows']:4d} rows, measured "
                     f"{b['measured']:6.1f} +- {b['se']:.1f}, model {b['model']:6.1f} deg; "
                     f"above p90 {b['above_p90']:.0%}, below p10 {b['below_p10']:.0%}")
    lines += ["  " + v for v in verdict(r)]
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m validation bat_tracking",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--fit", required=True, help="comma-separated files to fit "
                        "(name, name#k/n for the k-th of n parts of its games, or a path)")
    parser.add_argument("--judge", default="", help="comma-separated files to judge")
    parser.add_argument("--samples", type=int, default=100000)
    parser.add_argument("--seed", type=int, default=2025)
    parser.add_argument("--figure", help="write the figures to this PNG (and its _spin.png)")
    parser.add_argument("--errors", help="attack_angle,bat_speed[,attack_direction] error "
                                         "sds (deg,mph,deg): skip the scan")
    parser.add_argument("--trend", type=float, help="the contact's bat-speed trend (in per "
                                                    "10 mph; with --errors)")
    parser.add_argument("--json", help="write the fitted values and acceptance numbers here")
    parser.add_argument("--cross", help="a file whose games are cut into --folds parts, "
                        "each judged by a fit to --fit and the other parts")
    parser.add_argument("--folds", type=int, default=2)
    parser.add_argument("--study", type=Path, help="a variant of studies/bat_tracking.toml "
                        "whose fixed settings to use (e.g. another [contact.plate_x_trend] "
                        "or restitution location table)")
    parser.add_argument("--plate-x", help="the contact's pitch-location trend instead of "
                        "the study's: SHIFT,DEAD_ZONE[,REFERENCE] (in per ft, in, in; "
                        "'none': without one)")
    parser.add_argument("--plate-z", help="the undercut's pitch-height trend instead of "
                        "the study's: SHIFT[,REFERENCE] (in per ft, ft; 'none': without one)")
    parser.add_argument("--location", help="the restitution's location table instead of "
                        "the study's (a name of mcbat.bodies.restitution.LOCATION_TABLES)")
    parser.add_argument("--undercut-trend", type=float, help="the undercut's bat-speed "
                        "trend instead of the study's (in per 10 mph)")
    parser.add_argument("--bat-speed-outliers", help="the bat speeds measured far too "
                        "fast instead of the study's: FRACTION,EXCESS[,SPREAD] (mph; "
                        "'none': without)")
    args = parser.parse_args(argv)
    if args.bat_speed_outliers:
        OUTLIERS[:] = [_outliers_table(args.bat_speed_outliers)]
    if args.undercut_trend is not None:
        UNDERCUT_TREND[:] = [args.undercut_trend]
    if args.study:
        BASE_STUDY[0] = args.study
    if args.plate_x:
        OVERRIDES["contact.plate_x_trend"] = _plate_x_table(args.plate_x)
    if args.plate_z:
        OVERRIDES["contact.plate_z_trend"] = _plate_z_table(args.plate_z)
    if args.location:
        OVERRIDES["restitution.location"] = args.location
    errors = None
    if args.errors:
        parts = [float(x) for x in args.errors.split(",")]
        errors = dict(zip(("attack_angle", "bat_speed", "attack_direction"), parts))
    outcome = run(args.fit.split(","), [j for j in args.judge.split(",") if j], args.samples,
                  args.seed, errors, args.trend, args.cross, args.folds)
    if args.figure:
        figure(outcome, args.figure)
    if args.json:
        Path(args.json).write_text(json.dumps(summary(outcome), indent=1))
    return 0


def _plate_x_table(text):
    """``"SHIFT,DEAD_ZONE[,REFERENCE]"`` (in per ft, in, in; default reference 2 in) ->
    a ``[contact.plate_x_trend]`` table; ``"none"`` -> None (no trend)."""
    if text == "none":
        return None
    parts = [float(x) for x in text.split(",")]
    shift, zone, reference = (*parts, 2.0)[:3]
    return {"reference": {"value": reference, "unit": "in"},
            "dead_zone": {"value": zone, "unit": "in"}, "per": {"value": 1, "unit": "ft"},
            "from_barrel_end": {"value": shift, "unit": "in"}}


def _outliers_table(text):
    """``"FRACTION,EXCESS[,SPREAD]"`` (mph) -> a ``[pitches.swing_error.bat_speed_outliers]``
    table; ``"none"`` -> None."""
    if text.strip().lower() == "none":
        return None
    parts = [float(x) for x in text.split(",")]
    table = {"fraction": parts[0], "excess": {"value": parts[1], "unit": "mph"}}
    if len(parts) > 2:
        table["spread"] = {"value": parts[2], "unit": "mph"}
    return table


def _plate_z_table(text):
    """``"SHIFT[,REFERENCE]"`` (in per ft, ft; default reference 2.5 ft) -> a
    ``[contact.plate_z_trend]`` table; ``"none"`` -> None (no trend)."""
    if text == "none":
        return None
    parts = [float(x) for x in text.split(",")]
    shift, reference = (*parts, 2.5)[:2]
    return {"reference": {"value": reference, "unit": "ft"}, "per": {"value": 1, "unit": "ft"},
            "undercut": {"value": shift, "unit": "in"}}


def summary(outcome) -> dict:
    """The JSON-ready part of :func:`run`'s outcome (no draws)."""
    skip = ("q", "spin")
    return {"errors": outcome["errors"], "trend": outcome["trend"],
            "trend_interval": outcome.get("trend_interval"),
            "values": outcome["values"], "fit": outcome["fit"].to_dict(),
            "fit_files": outcome["fit_files"], "folds": outcome.get("folds"),
            "results": [{"label": label, "file": name,
                         **{k: v for k, v in r.items() if k not in skip}}
                        for (label, name), r in outcome["results"].items()]}


def _shown(outcome, label):
    """The results a figure's row draws: in sample, the first fold's fit files; out of
    sample, the cross-fitted file and the other judged files of the first fold (or the
    judged files without folds)."""
    keep = {"in sample": ("in sample", "in sample (fold 1)"),
            "out of sample": ("out of sample", "out of sample (fold 1)")}[label]
    items = [(k, r) for k, r in outcome["results"].items() if k[0] in keep]
    if label == "out of sample" and any(k[0] == "out of sample" for k, _ in items):
        items = [(k, r) for k, r in items if k[0] == "out of sample" or "#" not in k[1]]
    return items


def _centre(label) -> float:
    """Where a bat-speed bin is drawn (mph): the open end bins 2.5 mph past their edge."""
    lo = float(label.rstrip("+").split("-")[0])
    return BINS[1] - 2.5 if lo == BINS[0] else lo + 2.5


def figure(outcome, path):
    """Per row (in sample, out of sample): the mean launch speed per bat-speed bin, the
    mean launch angle per attack-angle bin, the distribution of ``q``, its 90th
    percentile per bat-speed bin and the mean launch speed per bin of where the pitch
    crossed the plate, data (points) and model (lines). Beside it
    (``<path>_spin.png``): the model's backspin against launch angle with Nathan's."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 5, figsize=(22, 8.5))
    for line_no, label in enumerate(("in sample", "out of sample")):
        ax = axes[line_no]
        for (_, name), r in _shown(outcome, label):
            b = [x for x in r["bat_speed_bins"] if x["rows"] >= 10]
            centres = [_centre(x["bin"]) for x in b]
            line = ax[0].errorbar(centres, [x["measured"] for x in b],
                                  yerr=[x["se"] for x in b], fmt="o", capsize=2,
                                  label=f"{name} (data)")
            colour = line[0].get_color()
            ax[0].plot(centres, [x["model"] for x in b], "-", color=colour,
                       label=f"{name} (model)")
            if r["attack_bins"]:
                a = r["attack_bins"]
                ax[1].errorbar([x["bin"] for x in a], [x["measured"] for x in a],
                               yerr=[x["se"] for x in a], fmt="o", capsize=2, color=colour,
                               label=f"{name} (data)")
                ax[1].plot([x["bin"] for x in a], [x["model"] for x in a], "-",
                           color=colour, label=f"{name} (model)")
            edges = np.linspace(-0.3, 0.4, 36)
            ax[2].hist(r["q"]["data"], edges, density=True, histtype="step", color=colour,
                       lw=1.5, label=f"{name} (data)")
            ax[2].hist(r["q"]["model"], edges, density=True, histtype="step", color=colour,
                       ls="--", label=f"{name} (model)")
            p90 = np.array(r["q"]["p90_by_bin"])
            centres_all = [_centre(x["bin"]) for x in r["bat_speed_bins"]]
            ax[3].plot(centres_all, p90[:, 0], "o", color=colour, label=f"{name} (data)")
            ax[3].plot(centres_all, p90[:, 1], "-", color=colour, label=f"{name} (model)")
            px = r.get("plate_x_bins", [])
            middle = [np.clip(np.mean([float(v) for v in x["bin"].split(" to ")]), -0.9, 0.9)
                      for x in px]
            ax[4].errorbar(middle, [x["measured"] for x in px], yerr=[x["se"] for x in px],
                           fmt="o", capsize=2, color=colour, label=f"{name} (data)")
            ax[4].plot(middle, [x["model"] for x in px], "-", color=colour,
                       label=f"{name} (model)")
        ax[0].set_title(f"{label}: launch speed vs bat speed")
        ax[0].set_xlabel("measured bat speed (mph; bins of 5, < 65 and 80+ at the ends)")
        ax[0].set_ylabel("mean launch speed (mph)")
        ax[1].set_title(f"{label}: launch angle vs attack angle")
        ax[1].set_xlabel("measured attack angle (deg; bins of 5)")
        ax[1].set_ylabel("mean launch angle (deg)")
        ax[2].set_title(f"{label}: q = (EV - bat speed)/(pitch + bat speed)")
        ax[2].set_xlabel("q (measured bat and plate speed of the row)")
        ax[2].set_ylabel("density")
        ax[3].set_title(f"{label}: upper edge of q (90th percentile)")
        ax[3].set_xlabel("measured bat speed (mph)")
        ax[3].set_ylabel("q, 90th percentile per bin")
        ax[4].set_title(f"{label}: launch speed vs plate_x")
        ax[4].set_xlabel("plate_x away from the batter (ft; bins of 0.3)")
        ax[4].set_ylabel("mean launch speed (mph)")
        for a in ax:
            a.legend(fontsize=6)
            a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    _spin_figure(outcome, str(path).replace(".png", "_spin.png"))


def _spin_figure(outcome, path):
    """The model's backspin per launch-angle bin (median, 10-90 %) of every judged file,
    with Nathan's average model evaluated at the same draws."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mcbat.statcast.spin import nathan_average_spin

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), sharey=True)
    for ax, label in zip(axes, ("in sample", "out of sample")):
        for (_, name), r in _shown(outcome, label):
            s = r["spin"]
            edges = np.arange(-30, 71, 5)
            mid = 0.5 * (edges[1:] + edges[:-1])
            idx = np.digitize(s["launch_angle"], edges) - 1
            q = np.array([np.quantile(s["backspin"][idx == i], [0.1, 0.5, 0.9])
                          if np.sum(idx == i) > 50 else [np.nan] * 3
                          for i in range(len(mid))])
            nathan, _ = nathan_average_spin(s["launch_angle"], s["spray_angle"],
                                            s["handedness"])
            nq = np.array([np.median(nathan[idx == i]) if np.sum(idx == i) > 50 else np.nan
                           for i in range(len(mid))])
            line = ax.plot(mid, q[:, 1], "-", label=f"{name}: model, median")
            ax.fill_between(mid, q[:, 0], q[:, 2], color=line[0].get_color(), alpha=0.15,
                            label=f"{name}: model, 10-90 %")
            ax.plot(mid, nq, "--", color=line[0].get_color(),
                    label=f"{name}: Nathan's average model")
        ax.set_title(f"{label}: backspin of the drawn balls")
        ax.set_xlabel("launch angle (deg)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("backspin (rpm)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def fit_and_choose(fit_files, samples, workdir, errors=None, trend=None) -> dict:
    """The swing errors, the contact's trend (scanned unless given) and the contact fitted
    at them on ``fit_files``; prints them."""
    table = tracked(fit_files)
    interval = None
    if errors is None:
        print(f"scanning the swing errors and the contact's bat-speed trend on "
              f"{', '.join(fit_files)} ({len(table)} rows)")
        chosen = choose(table, min(samples, 40000), workdir)
        errors, trend, interval = chosen["errors"], chosen["trend"], chosen["trend_interval"]
    trend = 0.0 if trend is None else trend
    result = fit(table, {k: v for k, v in errors.items() if k != "attack_direction"}, trend)
    shown = ", ".join(f"{k} {v:g}" for k, v in errors.items())
    print(f"fit on {', '.join(fit_files)} ({result.rows} rows): chi2 {result.chi2:.1f}/"
          f"{result.dof}; swing errors: {shown} (deg, mph); contact trend {trend:+g} in "
          f"per 10 mph above {TREND_REFERENCE:g} mph"
          + (f" (distance within 1: {interval[0]:+.2f} to {interval[1]:+.2f})"
             if interval else ""))
    for p in result.parameters:
        # (an interval that reaches a parameter's limit has no error on that side)
        low, high = (f"{e:.2f}" if e is not None else "?"
                     for e in (p["lower_error"], p["upper_error"]))
        print(f"  {p['name']} = {p['value']:.2f} -{low} +{high} {p['unit']}")
    return {"errors": errors, "trend": trend, "trend_interval": interval,
            "values": _values(result), "fit": result, "fit_files": list(fit_files)}


def _print(results):
    blocks = [report(f"{label}: {name}", r) for (label, name), r in results.items()]
    width = max(len(line) for block in blocks for line in block) + 2
    ins = [b for (label, _), b in zip(results, blocks) if label.startswith("in sample")]
    outs = [b for (label, _), b in zip(results, blocks) if not label.startswith("in sample")]
    for k in range(max(len(ins), len(outs))):
        left = ins[k] if k < len(ins) else []
        right = outs[k] if k < len(outs) else []
        for i in range(max(len(left), len(right))):
            a = left[i] if i < len(left) else ""
            b = right[i] if i < len(right) else ""
            print(f"{a:<{width}}{b}")
        print()


def run(fit_files, judge_files, samples=100000, seed=2025, errors=None, trend=None,
        cross=None, folds=2) -> dict:
    """Fit on ``fit_files``, judge on both; prints the report and returns
    ``{"errors", "trend", "values", "fit", "results": {(label, file): judge(...)}}``.

    With ``cross`` (a file name), the file's games are cut into ``folds`` parts
    (:func:`split_name`); each part is judged by a fit to ``fit_files`` and the other
    parts, and the parts' draws are pooled into one cross-fitted judgement of the whole
    file (every row judged by a fit that never saw its game; draws in proportion to the
    rows). The returned values are the first fold's."""
    results = {}
    with tempfile.TemporaryDirectory() as workdir:
        if cross is None:
            chosen = fit_and_choose(fit_files, samples, workdir, errors, trend)
            data = study_definition(chosen["values"], chosen["errors"], chosen["trend"])
            for label, names in (("in sample", fit_files), ("out of sample", judge_files)):
                for name in names:
                    results[(label, name)] = judge(data, tracked([name]), samples, seed,
                                                   workdir)
            _print(results)
            return {**chosen, "results": results}
        parts = [f"{cross}#{k}/{folds}" for k in range(1, folds + 1)]
        whole = tracked([cross])
        pooled, tables, offset, first, each = [], [], 0, None, []
        for k, part in enumerate(parts, 1):
            files = [*fit_files, *(q for q in parts if q != part)]
            chosen = fit_and_choose(files, samples, workdir, errors, trend)
            each.append({key: chosen[key] for key in ("errors", "trend", "trend_interval",
                                                      "values", "fit_files")}
                        | {"chi2": chosen["fit"].chi2, "dof": chosen["fit"].dof,
                           "parameters": chosen["fit"].parameters})
            first = first or chosen
            data = study_definition(chosen["values"], chosen["errors"], chosen["trend"])
            if k == 1:
                for name in files:
                    results[("in sample (fold 1)", name)] = judge(
                        data, tracked([name]), samples, seed, workdir)
            for name in judge_files:
                results[(f"out of sample (fold {k})", name)] = judge(
                    data, tracked([name]), samples, seed, workdir)
            table = tracked([part])
            sim = simulate(data, table, max(1000, round(samples * len(table) / len(whole))),
                           seed + k, workdir)
            results[(f"out of sample (fold {k})", part)] = evaluate(table, sim)
            sim["row"] = sim["row"] + offset
            offset += len(table)
            pooled.append(sim)
            tables.append(table)
        table = pd.concat(tables, ignore_index=True)
        sim = {key: np.concatenate([p[key] for p in pooled]) for key in pooled[0]}
        results[("out of sample", f"{cross} (cross-fitted, {folds} folds)")] = evaluate(
            table, sim)
    _print(results)
    return {**first, "results": results, "folds": each}


if __name__ == "__main__":
    main()


EXCERPT_SOURCE = "statcast_2025-05-01.csv#2/2"
"""The games of ``data/statcast_2025-05-01_bat_tracking.csv``: the part of the day the
shipped study's contact was not fitted to."""


def write_excerpt(path, source=EXCERPT_SOURCE):
    """Write the tracked balls in play (a ``bb_type`` and a ``bat_speed``) of ``source``'s
    games (``file#k/n``: :func:`split_name`) to ``path``: the Savant columns
    :mod:`mcbat.statcast` reads, in the export's order, each cell as it is in the export
    (Python's ``csv`` module). Returns the number of rows written."""
    import csv

    base, k, n = split_name(source)
    with open(resolve(base), newline="", encoding="utf-8") as handle:
        reader = csv.reader(handle)
        header = next(reader)
        keep = [i for i, c in enumerate(header) if c in (*sc.REQUIRED, *sc.OPTIONAL)]
        at = {c: i for i, c in enumerate(header)}
        rows = list(reader)
    games = sorted({int(r[at["game_pk"]]) for r in rows if r[at["game_pk"]]})
    part = {g: i % n + 1 for i, g in enumerate(games)} if k else None
    out = [r for r in rows if r[at["bb_type"]] and r[at["bat_speed"]]
           and (part is None or part.get(int(r[at["game_pk"]])) == k)]
    with open(path, "w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow([header[i] for i in keep])
        writer.writerows([r[i] for i in keep] for r in out)
    return len(out)
