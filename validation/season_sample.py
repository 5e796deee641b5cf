"""The study against a season-wide sample of tracked balls in play whose pitches are not
given: launch speed and angle by bat speed, pitch height and location, model and data.

A day's export holds a few hundred tracked balls in play, so a bin of 100 of them has a
mean launch speed uncertain by 1.5 mph: the trends of the collision with the swing are
hidden in its noise. Public samples of a season's tracked balls in play hold tens of
thousands of rows, but often only the swing and the batted ball (``bat_speed``,
``attack_angle``, ``swing_path_tilt``, ``launch_speed``, ``launch_angle``, ``plate_x``,
``plate_z``, the batter's and pitcher's hands), not the pitch. Here each of their rows is
given the pitch of a random tracked ball in play of a real export thrown by a pitcher of
the same hand (:func:`pair`): the launch speed moves by about 0.2 mph per mph of pitch
speed, so a bin's mean carries the pitch file's mix (a few tenths of a mph, the same in
every bin), while its dependence on the bat speed is the season's. The pitch's plate
location is the sample's own (the contact's location trends read it).

    NUMBA_NUM_THREADS=1 .venv/bin/python -m validation season_sample \\
        --fit season_2025.csv --sample season_2025.csv --sample season_2024.csv \\
        --judge statcast_2025-05-01.csv,statcast_2024_skubal.csv,statcast_2024_ohtani.csv \\
        --figure docs/figures/bat_tracking/season.png

``--fit`` fits the study's contact to a sample first (:func:`fit_contact`; every other
setting the study's, ``--study`` for a variant), leaving out the balls in play of the
exports judged (``--judge``: judged like ``validation bat_tracking``'s, out of sample) and
of ``--exclude``; without it the study's contact is used as written. Files are names in
``../shared/data/statcast/`` or ``data/``, or paths. ``docs/bat_tracking.md`` names the
samples used and their provenance.
"""

import argparse
import tempfile
import tomllib
from pathlib import Path

import numpy as np
import pandas as pd

import validation.bat_tracking as bt
from validation.bat_tracking import PLATE_X_BINS, PLATE_Z_BINS, STUDY, resolve, simulate, tracked

IN_ALL = False
#: Swing columns taken from the sample (the rest of a row is its pitch's).
SWING_COLUMNS = ("launch_speed", "launch_angle", "bat_speed", "swing_length",
                 "attack_angle", "swing_path_tilt", "plate_x", "plate_z")
BAT_SPEED_EDGES = tuple(np.arange(50.0, 90.1, 2.5))
ACCEPTANCE_EDGES = (0.0, 65.0, 70.0, 75.0, 80.0, 200.0)
MIN_ROWS = 30
UNREACHED = (60.0, 90.0)
"""Launch angle (deg) and speed (mph) above both of which a fit leaves a row out."""


def pair(sample: pd.DataFrame, pitches: pd.DataFrame, seed=1) -> pd.DataFrame:
    """Savant rows: each row of ``sample`` (a swing and its batted ball, the hands as
    ``is_stand_left`` and ``is_throw_left`` 0/1 or as ``stand`` and ``p_throws``) with the
    pitch of a random row of ``pitches`` (a raw Savant export's balls in play with bat
    tracking) of a pitcher of the same hand. The swing columns missing from the sample
    are left empty (the study's fallbacks draw them); every row gets its own pitch
    identifiers (the pitches repeat), batter and pitcher."""
    sample = sample.copy()
    if "stand" not in sample:
        sample["stand"] = np.where(sample["is_stand_left"] == 1, "L", "R")
    if "p_throws" not in sample:
        sample["p_throws"] = np.where(sample["is_throw_left"] == 1, "L", "R")
    pool = pitches[pitches["bb_type"].notna() & pitches["bat_speed"].notna()]
    rng = np.random.default_rng(seed)
    frames = []
    for hand, rows in sample.groupby("p_throws", sort=True):
        same = pool[pool["p_throws"] == hand]
        if same.empty:
            raise ValueError(f"the pitch file has no ball in play off a pitcher throwing {hand}")
        out = same.iloc[rng.integers(0, len(same), len(rows))].copy()
        for column in SWING_COLUMNS:
            out[column] = rows[column].to_numpy() if column in rows else np.nan
        out["stand"] = rows["stand"].to_numpy()
        out["attack_direction"] = (rows["attack_direction"].to_numpy()
                                   if "attack_direction" in rows else np.nan)
        frames.append(out)
    out = pd.concat(frames, ignore_index=True)
    out["game_pk"] = 1 + np.arange(len(out)) // 1000
    out["at_bat_number"] = 1 + np.arange(len(out)) % 1000
    out["pitch_number"] = 1
    # the sample names no player: each ball its own batter and pitcher (the pitches'
    # ids would tie unrelated balls into one player's level)
    out["batter"] = 1 + np.arange(len(out))
    out["pitcher"] = 1_000_000 + np.arange(len(out))
    return out


def without(sample: pd.DataFrame, others) -> pd.DataFrame:
    """``sample`` less its rows that are balls in play of the raw Savant exports
    ``others`` (the same launch speed to 0.1 mph, launch angle to 1 deg and bat speed to
    0.1 mph: a public season sample may hold a day's file whole)."""
    def key(t):
        return (t["launch_speed"].round(1).astype(str) + "|"
                + t["launch_angle"].round(0).astype("Int64").astype(str) + "|"
                + t["bat_speed"].round(1).astype(str))

    seen = set()
    for other in others:
        raw = pd.read_csv(resolve(other), low_memory=False)
        raw = raw[raw["bb_type"].notna() & raw["bat_speed"].notna()
                  & raw["launch_speed"].notna()]
        seen |= set(key(raw))
    return sample[~key(sample).isin(seen)]


def binned(key, edges, measured, row, draws) -> list[dict]:
    """Per bin of ``key`` (one value per row) with at least ``MIN_ROWS`` rows: the rows,
    the measured mean and its standard error, the model's mean over the draws of those
    rows (``row``: the row each draw meets)."""
    out = []
    k_row, k_draw = np.digitize(key, edges), np.digitize(key[row], edges)
    for k in range(1, len(edges)):
        rows = k_row == k
        if rows.sum() < MIN_ROWS:
            continue
        out.append({"low": float(edges[k - 1]), "high": float(edges[k]),
                    "rows": int(rows.sum()), "measured": float(measured[rows].mean()),
                    "se": float(measured[rows].std() / np.sqrt(rows.sum())),
                    "model": float(draws[k_draw == k].mean())})
    return out


def chi2(bins) -> float:
    """Sum of ((model - measured) / se)^2 over the bins."""
    return float(sum(((b["model"] - b["measured"]) / b["se"]) ** 2 for b in bins))


def paired_table(path, pitches, seed, exclude=()) -> tuple:
    """The tidy table of the sample at ``path`` less the balls in play of the exports
    ``exclude`` (:func:`without`), each row paired with a pitch of ``pitches``
    (:func:`pair`), and the sample's row count after the exclusions."""
    sample = without(pd.read_csv(resolve(path)), exclude)
    raw = pd.read_csv(resolve(pitches), low_memory=False)
    with tempfile.TemporaryDirectory() as tmp:
        paired = Path(tmp) / "paired.csv"
        pair(sample, raw, seed).to_csv(paired, index=False)
        return tracked([str(paired)]), len(sample)


def fit_contact(path, pitches, seed, exclude=()):
    """The study's contact (``FREE`` of ``validation bat_tracking``) fitted with
    ``fit_population`` to the sample at ``path`` (:func:`paired_table`), every other
    setting the study's. The rows no draw of the study reaches (pop-ups above 60 deg
    leaving faster than 90 mph: ``UNREACHED``) are left out and counted. Returns the fit
    and the rows left out."""
    table, _ = paired_table(path, pitches, seed, exclude)
    unreached = ((table["launch_angle"] > UNREACHED[0])
                 & (table["launch_speed"] > UNREACHED[1])).to_numpy()
    table = table[~unreached]
    errors = {k: v for k, v in study_errors(bt.BASE_STUDY[0]).items()
              if k != "attack_direction"}
    return bt.fit(table, errors, trend=None), int(unreached.sum())


def study_errors(study) -> dict:
    """The study's ``[pitches.swing_error]`` sds (deg, mph; no outlier table)."""
    table = tomllib.loads(Path(study).read_text())["pitches"].get("swing_error", {})
    return {k: v["value"] for k, v in table.items() if isinstance(v, dict) and "value" in v}


def swing_length_slopes(table, speed, angle, rows=None) -> dict:
    """Least-squares coefficients of launch speed (mph per ft) and angle (deg per ft) on
    the measured ``swing_length`` with the bat speed, the pitch's height, its distance
    off the plate's middle (``plate_x`` away from the batter, beyond 4 in about 2 in away)
    and, where every row has one, the attack angle held: ``{"speed": (coefficient, se),
    "angle": ...}``. ``rows``: the table's row of each of ``speed`` and ``angle`` (the
    model's draws); None: the rows themselves (the data)."""
    plate_x = table["plate_x"].to_numpy()
    away = np.where(table["handedness"].to_numpy() == "L", -plate_x, plate_x)
    held = [table["bat_speed"].to_numpy() - 72.0, table["swing_length"].to_numpy() - 7.2,
            table["plate_z"].to_numpy() - 2.5, np.maximum(np.abs(away - 1 / 6) - 1 / 3, 0.0)]
    attack = table["attack_angle"].to_numpy() if "attack_angle" in table else None
    if attack is not None and np.isfinite(attack).all():
        held.append(attack)
    x = np.column_stack([np.ones(len(table)), *held])
    x = x if rows is None else x[rows]
    out = {}
    for name, y in (("speed", speed), ("angle", angle)):
        ok = np.isfinite(x).all(axis=1) & np.isfinite(y)
        beta, *_ = np.linalg.lstsq(x[ok], y[ok], rcond=None)
        resid = y[ok] - x[ok] @ beta
        cov = np.linalg.inv(x[ok].T @ x[ok]) * resid.var()
        out[name] = (float(beta[2]), float(np.sqrt(cov[2, 2])))
    return out


def judge(path, pitches, samples, seed, data, exclude=()) -> dict:
    """The study ``data`` (a study definition) on the sample at ``path``
    (:func:`paired_table`)."""
    table, kept = paired_table(path, pitches, seed, exclude)
    with tempfile.TemporaryDirectory() as tmp:
        sim = simulate(data, table, samples, seed, tmp)
    bat = table["bat_speed"].to_numpy()
    speed, angle = table["launch_speed"].to_numpy(), table["launch_angle"].to_numpy()
    plate_z = table["plate_z"].to_numpy()  # (ft, as Statcast gives it)
    plate_x = table["plate_x"].to_numpy()
    away = np.where(table["handedness"].to_numpy() == "L", -plate_x, plate_x)
    row = sim["row"]
    result = {"sample": Path(path).name, "rows": len(table), "sample_rows": kept,
              "speed": binned(bat, BAT_SPEED_EDGES, speed, row, sim["launch_speed"]),
              "angle": binned(bat, BAT_SPEED_EDGES, angle, row, sim["launch_angle"]),
              "acceptance": binned(bat, ACCEPTANCE_EDGES, speed, row, sim["launch_speed"]),
              "height": binned(plate_z, PLATE_Z_BINS, angle, row, sim["launch_angle"]),
              "away": binned(away, PLATE_X_BINS, speed, row, sim["launch_speed"])}
    for key in ("speed", "angle", "height", "away"):
        result[f"{key}_chi2"] = chi2(result[key])
    result["swing_length"] = {
        "data": swing_length_slopes(table, speed, angle),
        "model": swing_length_slopes(table, sim["launch_speed"], sim["launch_angle"], row)}
    return result


def report(r) -> list[str]:
    """The printed lines of one sample's judgement."""
    lines = [f"{r['sample']}, {r.get('role', 'judged')}: {r['rows']} of {r['sample_rows']} "
             f"rows (after the exclusions)"]
    for key, title, unit in (("speed", "launch speed by bat speed", "mph"),
                             ("angle", "launch angle by bat speed", "deg"),
                             ("height", "launch angle by plate_z (ft)", "deg"),
                             ("away", "launch speed by plate_x away from the batter (ft)",
                              "mph"),
                             ("acceptance", "launch speed, the bat-speed bins held to 2 mph",
                              "mph")):
        lines.append(f"  {title}" + (f": sum of ((model - measured)/se)^2 "
                                     f"{r[key + '_chi2']:.1f} ({len(r[key])} bins)"
                                     if key != "acceptance" else ""))
        for b in r[key]:
            gap = b["model"] - b["measured"]
            lines.append(f"    {b['low']:5.1f} to {b['high']:5.1f}: {b['rows']:5d} rows, "
                         f"measured {b['measured']:6.1f} +- {b['se']:.1f}, model "
                         f"{b['model']:6.1f} {unit} (model - measured {gap:+.1f})")
    sl = r.get("swing_length")
    if sl:
        lines.append("  per ft of swing_length, the bat speed, pitch height, distance off the "
                     "plate (and attack angle, where measured) held: " + ", ".join(
                         f"launch {name} {unit}: data {sl['data'][name][0]:+.2f} +- "
                         f"{sl['data'][name][1]:.2f}, model {sl['model'][name][0]:+.2f}"
                         for name, unit in (("speed", "mph"), ("angle", "deg"))))
    return lines


def figure(results, path):
    """Launch speed and angle against bat speed, data and model, one column a sample."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(results), figsize=(5.2 * len(results), 7.5),
                             squeeze=False, sharex=True)
    for j, r in enumerate(results):
        for i, (key, label) in enumerate((("speed", "launch speed (mph)"),
                                          ("angle", "launch angle (deg)"))):
            ax = axes[i, j]
            x = [0.5 * (b["low"] + b["high"]) for b in r[key]]
            ax.errorbar(x, [b["measured"] for b in r[key]], [b["se"] for b in r[key]],
                        fmt="o", color="k", ms=4, label="measured (mean +- se)")
            ax.plot(x, [b["model"] for b in r[key]], "-", color="C3", label="model")
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
            if i == 0:
                ax.set_title(f"{r['sample']}, {r.get('role', 'judged')} ({r['rows']} rows)",
                             fontsize=10)
                ax.legend(fontsize=8)
        axes[1, j].set_xlabel("measured bat speed (mph)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m validation season_sample",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--sample", action="append", default=[],
                        help="a season sample of tracked balls in play to judge (repeatable)")
    parser.add_argument("--fit", help="a season sample to fit the study's contact to first "
                        "(else the study's contact as written)")
    parser.add_argument("--judge", default="", help="comma-separated Savant exports to "
                        "judge with the contact (validation bat_tracking's numbers)")
    parser.add_argument("--pitches", default="statcast_2025-05-01.csv",
                        help="the Savant export whose balls in play give the pitches")
    parser.add_argument("--samples", type=int, default=200000)
    parser.add_argument("--seed", type=int, default=2025)
    parser.add_argument("--study", type=Path, default=STUDY)
    parser.add_argument("--figure", help="write the figure to this PNG")
    parser.add_argument("--league-contact", action="store_true",
                        help="judge without [pitches.player_levels]: the league's contact "
                             "for every row")
    parser.add_argument("--exclude", default="", help="comma-separated Savant exports "
                        "whose balls in play to drop from the samples (those judged on their "
                        "own, or fitted)")
    parser.add_argument("--swing-length", help="SHIFT[,REFERENCE]: add a "
                        "[contact.swing_length_trend] to the study, the undercut moving "
                        "SHIFT in per ft of swing_length above REFERENCE ft (default 7.2); "
                        "with --fit the contact is refitted with it")
    parser.add_argument("--vertical-bat-angle", type=float, help="MEAN (deg): the study's "
                        "assumed vertical bat angle moved to MEAN, its sd and width kept")
    args = parser.parse_args(argv)
    bt.BASE_STUDY[0] = args.study
    if args.vertical_bat_angle is not None:
        swing = tomllib.loads(Path(args.study).read_text())["swing"]["vertical_bat_angle"]
        shift = args.vertical_bat_angle - swing["mean"]
        bt.OVERRIDES["swing.vertical_bat_angle"] = {
            **swing, "mean": args.vertical_bat_angle, "low": swing["low"] + shift,
            "high": min(swing["high"] + shift, 0.0)}
    if args.swing_length:
        shift, reference = (*(float(x) for x in args.swing_length.split(",")), 7.2)[:2]
        bt.OVERRIDES["contact.swing_length_trend"] = bt._plate_z_table(f"{shift},{reference}")
    judged = [j for j in args.judge.split(",") if j]
    # (a judged export's balls in play never enter the fit, whatever --exclude says)
    exclude = list(dict.fromkeys([*(x for x in args.exclude.split(",") if x), *judged]))
    values = None
    if args.fit:
        result, unreached = fit_contact(args.fit, args.pitches, args.seed, exclude)
        values = bt._values(result)
        print(f"fit on {Path(args.fit).name} ({result.rows} rows; {unreached} left out, "
              f"launch angle above {UNREACHED[0]:g} deg at over {UNREACHED[1]:g} mph): chi2 "
              f"{result.chi2:.1f}/{result.dof}")
        for p in result.parameters:
            low, high = (f"{e:.2f}" if e is not None else "?"
                         for e in (p["lower_error"], p["upper_error"]))
            print(f"  {p['name']} = {p['value']:.3f} -{low} +{high} {p['unit']}")
    data = bt.study_definition(values)
    if args.league_contact:
        data["pitches"].pop("player_levels", None)
    with tempfile.TemporaryDirectory() as tmp:
        summary = []
        for name in judged:
            table = tracked([name])
            summary.append((Path(name).name, bt.judge(data, table, 100000, args.seed, tmp)))
            print("\n".join(bt.report(f"{summary[-1][0]} (no ball of it in the contact's fit)",
                                       summary[-1][1])))
        if summary:
            print("\n".join(["", *bt.summary_table(summary)]))
    results = [judge(s, args.pitches, args.samples, args.seed, data, exclude)
               for s in args.sample]
    for s, r in zip(args.sample, results):
        # without --fit the contact is the study's as written, fitted on whatever its
        # comments say: this run cannot tell in sample from out
        r["role"] = (("in sample (fitted)" if s == args.fit else "out of sample") if args.fit
                     else "the study's contact as written")
    for r in results:
        print("\n".join(report(r)))
    if args.figure and results:
        figure(results, args.figure)


if __name__ == "__main__":
    main()
