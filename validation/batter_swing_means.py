"""Launch speed on bat speed, within a batter and between batters, with each batter's mean
bat speed taken over all his tracked swings in the file (whiffs and fouls too), the row
itself left out.

``validation bat_tracking`` splits the slope with each batter's mean over his balls in
play, which in a day's file is two or three rows and includes the row itself: the mean
then carries part of the row's own bat speed. Here the mean is over his other tracked
swings (batters with at least ``--min-swings`` of them), and the two slopes are found by
moments (:func:`slopes`) with the variances of the bat speed between and within batters
(one-way analysis of variance of the tracked swings), so that the left-out mean's noise
flattens neither. Errors: bootstrap over the batters (the variances held). Last, per bat-speed
bin of the balls in play, the mean of the batter's (left-out) mean less the file's: how
far a batter term could move that bin.

    .venv/bin/python -m validation batter_swing_means \\
        statcast_2025-05-01.csv statcast_2024_skubal.csv

Files are names in ``../shared/data/statcast/`` or ``data/``, or paths.
``--swing-length`` prints instead the launch angle's and speed's dependence on the swing
length within a batter (:func:`within_swing_length`). ``--leaderboard FILE`` gives the
between-player slope of a season's Savant search grouped by batter, or by pitcher
(``docs/bat_tracking.md`` (e) and *Results* name the ones used and their provenance).
"""

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from mcbat import statcast as sc
from validation.bat_tracking import BINS, resolve

IN_ALL = False
QUICK_ARGS = ["statcast_2024_skubal.csv"]


def swing_means(table: pd.DataFrame, min_swings: int) -> pd.DataFrame:
    """The tracked balls in play of ``table`` (tidy) with ``batter_mean`` (mph: the mean
    bat speed of the batter's other tracked swings) and ``swings`` (his tracked swings),
    for batters with at least ``min_swings``."""
    swings = table[np.isfinite(table["bat_speed"])]
    total = swings.groupby("batter")["bat_speed"].agg(["sum", "size"])
    balls = swings[sc.balls_in_play(swings) & np.isfinite(swings["launch_speed"])
                   & np.isfinite(swings["pitch_speed"])].copy()
    balls["swings"] = balls["batter"].map(total["size"])
    balls = balls[balls["swings"] >= min_swings]
    balls["batter_mean"] = ((balls["batter"].map(total["sum"]) - balls["bat_speed"])
                            / (balls["swings"] - 1))
    return balls


def variances(table: pd.DataFrame, min_swings: int) -> tuple[float, float, float]:
    """``(between, within, typical swings per batter)``: the variances (mph^2) of the
    batters' true mean bat speeds and of a swing about its batter's mean (one-way
    analysis of variance, batters with at least ``min_swings`` tracked swings)."""
    swings = table[np.isfinite(table["bat_speed"])]
    count = swings.groupby("batter")["bat_speed"].transform("size")
    swings = swings[count >= min_swings]
    grouped = swings.groupby("batter")["bat_speed"]
    n = grouped.size().to_numpy(float)
    within = float(grouped.var(ddof=1).mul(n - 1).sum() / (n - 1).sum())
    n0 = (n.sum() - (n ** 2).sum() / n.sum()) / (n.size - 1)
    between = max(float(grouped.mean().var(ddof=1)) - within * float(np.mean(1 / n)), 0.0)
    return between, within, float(n0)


def slopes(balls: pd.DataFrame, between_var: float, within_var: float) -> np.ndarray:
    """``(within, between)``, mph per mph, by moments: with ``B`` the left-out mean, the
    between-batter slope is ``cov(launch speed, B) / var_b`` (``B``'s noise does not
    follow the row) and the within one ``cov(launch speed, V - B) / (var(V - B) - e)``,
    ``e`` the mean variance of ``B``'s noise, ``var_w / (swings - 1)``."""
    launch = balls["launch_speed"].to_numpy(float)
    mean = balls["batter_mean"].to_numpy(float)
    offset = balls["bat_speed"].to_numpy(float) - mean
    noise = within_var * float(np.mean(1.0 / (balls["swings"].to_numpy(float) - 1.0)))
    between = np.cov(launch, mean)[0, 1] / between_var
    within = np.cov(launch, offset)[0, 1] / (np.var(offset, ddof=1) - noise)
    return np.array([within, between])


def report(name: str, min_swings: int, boots: int, seed: int) -> list[str]:
    """The lines of one file."""
    table = sc.read(resolve(name))
    balls = swing_means(table, min_swings)
    if balls["batter"].nunique() < 2:
        return [f"{name}: fewer than two batters with {min_swings} tracked swings"]
    between_var, within_var, n0 = variances(table, min_swings)
    fitted = slopes(balls, between_var, within_var)
    rng = np.random.default_rng(seed)
    groups = [g for _, g in balls.groupby("batter")]
    reps = np.array([slopes(pd.concat([groups[i] for i in rng.integers(0, len(groups),
                                                                       len(groups))]),
                            between_var, within_var)
                     for _ in range(boots)])
    err = reps.std(axis=0)
    lines = [f"{name}: {len(balls)} balls in play of {len(groups)} batters with >= "
             f"{min_swings} tracked swings ({n0:.1f} swings per batter)",
             f"  bat speed sd between batters {np.sqrt(between_var):.2f} mph, within "
             f"{np.sqrt(within_var):.2f} mph",
             f"  launch speed on bat speed: within a batter {fitted[0]:.2f} +- {err[0]:.2f}, "
             f"between batters {fitted[1]:.2f} +- {err[1]:.2f} mph/mph"]
    offset = balls["batter_mean"] - balls["batter_mean"].mean()
    bat = balls["bat_speed"].to_numpy(float)
    for lo, hi in zip(BINS[:-1], BINS[1:]):
        rows = (bat >= lo) & (bat < hi)
        label = f"{lo:.0f}-{hi:.0f}" if hi < 200 else f"{lo:.0f}+"
        if rows.any():
            lines.append(f"  bat speed {label:>6} mph: {rows.sum():4d} balls, batter's mean "
                         f"{offset[rows].mean():+.2f} mph from the file's")
    return lines


def within_swing_length(name: str, min_balls: int = 3) -> list[str]:
    """Launch angle and speed on ``swing_length`` within a batter (each column less its
    batter's mean over his tracked balls in play: fixed effects; batters with at least
    ``min_balls``), the bat speed and the pitch's height held, and with the attack angle
    held too where every ball has one: coefficient and its standard error per ft."""
    table = sc.read(resolve(name))
    balls = table[sc.balls_in_play(table) & np.isfinite(table["launch_speed"])
                  & np.isfinite(table["bat_speed"]) & np.isfinite(table["swing_length"])
                  & np.isfinite(table["plate_z"]) & (table["bat_speed"] > 50.0)]
    balls = balls[balls.groupby("batter")["launch_speed"].transform("size") >= min_balls]
    held = ["bat_speed", "swing_length", "plate_z"]
    sets = [held]
    if np.isfinite(balls["attack_angle"]).all():
        sets.append([*held, "attack_angle"])
    lines = [f"{name}: {len(balls)} balls in play of {balls['batter'].nunique()} batters "
             f"with >= {min_balls}, per ft of swing length within a batter"]
    for columns in sets:
        centred = balls[[*columns, "launch_speed", "launch_angle"]] - balls.groupby(
            "batter")[[*columns, "launch_speed", "launch_angle"]].transform("mean")
        x = centred[columns].to_numpy(float)
        parts = []
        for y_name in ("launch_angle", "launch_speed"):
            y = centred[y_name].to_numpy(float)
            beta = np.linalg.lstsq(x, y, rcond=None)[0]
            resid = y - x @ beta
            se = np.sqrt(np.diag(np.linalg.inv(x.T @ x)) * resid.var())
            parts.append(f"{y_name} {beta[1]:+.2f} +- {se[1]:.2f}")
        lines.append(f"  holding {', '.join(c for c in columns if c != 'swing_length')}: "
                     + ", ".join(parts))
    return lines


def _board_fit(path, min_balls: int):
    """A leaderboard's players with ``min_balls`` balls in play, and its least squares of
    mean launch speed on mean bat speed and pitch speed."""
    board = pd.read_csv(path, encoding="utf-8-sig")
    for column in ("bat_speed", "launch_speed", "velocity", "bip"):
        board[column] = pd.to_numeric(board[column], errors="coerce")
    board = board.dropna(subset=["bat_speed", "launch_speed", "velocity"])
    board = board[board["bip"] >= min_balls]
    x = np.column_stack([np.ones(len(board)), board["bat_speed"], board["velocity"]])
    y = board["launch_speed"].to_numpy(float)
    return board, x, y, np.linalg.lstsq(x, y, rcond=None)[0]


def season_levels(first, second, min_balls: int) -> tuple[int, float, float, float]:
    """Is a player's level (his mean launch speed less what his bat speed and pitch speed
    predict, ``leaderboard``) a lasting trait? The same players' levels in two seasons'
    leaderboards (joined on ``player_id``): how many, their covariance between the seasons
    and each season's variance less the noise of a mean over the player's balls (14.5 mph
    per ball), mph^2."""
    levels = []
    for path in (first, second):
        board, x, y, fitted = _board_fit(path, min_balls)
        levels.append(pd.DataFrame({"level": y - x @ fitted,
                                    "noise": 14.5 ** 2 / board["bip"].to_numpy(float)},
                                   index=board["player_id"].to_numpy()))
    both = levels[0].merge(levels[1], how="inner", left_index=True, right_index=True,
                           suffixes=("_1", "_2"))
    cov = float(np.cov(both["level_1"], both["level_2"])[0, 1])
    true = [float(both[f"level_{k}"].var() - both[f"noise_{k}"].mean()) for k in (1, 2)]
    return len(both), cov, true[0], true[1]


#: A grouped search's mean pitch characteristics that could carry a pitcher's level (its pitch
#: speed is already in the level's regression).
PITCH_FEATURES = ("spin_rate", "release_extension", "api_break_z_induced",
                  "api_break_x_arm", "arm_angle", "release_pos_z", "plate_x", "plate_z")


def season_to_season(first, second, min_balls: int) -> list[str]:
    """``season_levels`` in words, and each season's correlation of the level with the
    players' mean pitch characteristics (:data:`PITCH_FEATURES`, where both have them)."""
    n, cov, one, two = season_levels(first, second, min_balls)
    lines = [f"{n} players with >= {min_balls} balls in play in both "
             f"({Path(first).name}, {Path(second).name})",
             f"  levels' covariance between the seasons {cov:.2f} mph^2; each season's "
             f"variance less the noise of the means {one:.2f}, {two:.2f} mph^2 "
             f"(correlation of the true levels {cov / np.sqrt(max(one * two, 1e-12)):.2f})"]
    fits = [_board_fit(path, min_balls) for path in (first, second)]
    for feature in PITCH_FEATURES:
        if all(feature in board for board, *_ in fits):
            r = [np.corrcoef(pd.to_numeric(board[feature], errors="coerce").fillna(
                     pd.to_numeric(board[feature], errors="coerce").mean()),
                 y - x @ fitted)[0, 1] for board, x, y, fitted in fits]
            lines.append(f"  level against the mean {feature}: r {r[0]:+.2f}, {r[1]:+.2f}")
    return lines


def leaderboard(path, min_balls: int, boots: int, seed: int) -> list[str]:
    """The between-player slope of a Savant search grouped by batter (one row per batter:
    ``bat_speed``, the mean over his tracked swings; ``launch_speed``, over his batted
    balls; ``velocity``, the pitches' mean release speed; ``bip``) or by pitcher (the same
    over his opponents' swings and balls and his own pitches): mean launch speed on mean
    bat speed and pitch speed, over players with at least ``min_balls`` balls in play.
    Each mean is over hundreds of swings, so its noise flattens nothing."""
    board, x, y, fitted = _board_fit(path, min_balls)
    rng = np.random.default_rng(seed)
    reps = [np.linalg.lstsq(x[i], y[i], rcond=None)[0][1]
            for i in (rng.integers(0, len(board), len(board)) for _ in range(boots))]
    # how far a batter's mean launch speed lies from what his swings and pitches predict,
    # less the noise of a mean over his balls (launch speed sd ~14.5 mph per ball)
    resid = y - x @ fitted
    noise = float(np.mean(14.5 ** 2 / board["bip"].to_numpy(float)))
    true_sd = float(np.sqrt(max(resid.var() - noise, 0.0)))
    # the same for the launch angle about the players' mean (one player's launch angles
    # spread 25-29 deg per ball in the development exports: 27)
    angle_lines = []
    if "launch_angle" in board:
        angle = pd.to_numeric(board["launch_angle"], errors="coerce").to_numpy(float)
        noise_angle = float(np.mean(27.0 ** 2 / board["bip"].to_numpy(float)))
        angle_lines.append(
            f"  a player's mean launch angle about the players' mean: sd "
            f"{np.nanstd(angle):.2f} deg, "
            f"{np.sqrt(max(np.nanvar(angle) - noise_angle, 0.0)):.2f} less the noise of his "
            "mean")
    return [f"{path}: {len(board)} players with >= {min_balls} balls in play "
            f"({int(board['bip'].sum())} balls), bat speed sd between players "
            f"{board['bat_speed'].std():.2f} mph",
            f"  mean launch speed on mean bat speed: {fitted[1]:.2f} +- {np.std(reps):.2f} "
            f"mph/mph between players",
            f"  a player's mean launch speed about the fit: sd {resid.std():.2f} mph, "
            f"{true_sd:.2f} less the noise of his mean; within 1 mph for "
            f"{np.mean(np.abs(resid) < 1.0):.0%} of the players, within 2 for "
            f"{np.mean(np.abs(resid) < 2.0):.0%}",
            *angle_lines,
            *[f"  {name}: {r:+.1f} mph" for name, r in
              zip(board["player_name"], resid) if "player_name" in board
              and any(k in str(name) for k in ("Skubal", "Ohtani"))]]


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m validation batter_swing_means",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*", help="Savant exports with bat tracking")
    parser.add_argument("--leaderboard", action="append", default=[],
                        help="a Savant search grouped by batter (CSV): its between-batter "
                             "slope")
    parser.add_argument("--min-balls", type=int, default=150,
                        help="balls in play a leaderboard's batter needs (default 150)")
    parser.add_argument("--min-swings", type=int, default=6,
                        help="tracked swings a batter needs (default 6)")
    parser.add_argument("--swing-length", action="store_true",
                        help="instead: launch angle and speed on the swing length within "
                             "a batter")
    parser.add_argument("--seasons", nargs=2, metavar=("FIRST", "SECOND"),
                        help="two seasons' leaderboards of the same kind: is a player's "
                             "level a lasting trait")
    parser.add_argument("--boots", type=int, default=300)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    for name in args.files:
        print("\n".join(within_swing_length(name) if args.swing_length
                        else report(name, args.min_swings, args.boots, args.seed)))
    for path in args.leaderboard:
        print("\n".join(leaderboard(path, args.min_balls, args.boots, args.seed)))
    if args.seasons:
        print("\n".join(season_to_season(*args.seasons, args.min_balls)))


if __name__ == "__main__":
    main()
