"""What the pitch's movement does to the batted ball beyond what the study models: each
tracked ball's launch speed and angle less the mean of the study's draws for its own pitch
and swing (the residual), regressed on the pitch's induced vertical break (``pfx_z``),
its horizontal break towards the batter (``pfx_x`` signed by the batter's side) and its
release spin rate (per 1,000 rpm), per export and combined (inverse-variance weights).

The study's contact follows where the pitch crossed the plate and how the bat met it,
but not how the pitch moved on its way: a batter who misjudges a pitch's rise swings under
or over it. The season samples carry no pitch, so only the exports can show it.

    NUMBA_NUM_THREADS=1 .venv/bin/python -m validation pitch_movement \\
        statcast_2025-05-01.csv statcast_2024_skubal.csv statcast_2024_ohtani.csv

Files are names in ``../shared/data/statcast/`` or ``data/``, or paths (raw Savant
exports: ``pfx_x``, ``pfx_z`` and ``release_spin_rate`` are read from them).
"""

import argparse
import tempfile

import numpy as np
import pandas as pd

import validation.bat_tracking as bt

IN_ALL = False
QUICK_ARGS = ["statcast_2024_skubal.csv"]
KEY = ["game_pk", "at_bat_number", "pitch_number"]
TERMS = ("pfx_z (ft)", "towards the batter (ft)", "spin (1000 rpm)")


def residuals(name: str, samples: int, seed: int) -> pd.DataFrame:
    """The export's tracked balls in play (``validation bat_tracking``'s table) with the
    residuals ``launch_speed_residual`` (mph) and ``launch_angle_residual`` (deg) of the
    shipped study and the pitch's movement columns."""
    table = bt.tracked([name]).reset_index(drop=True)
    with tempfile.TemporaryDirectory() as tmp:
        sim = bt.simulate(bt.study_definition(None), table, samples, seed, tmp)
    draws = pd.DataFrame({"row": sim["row"], "speed": sim["launch_speed"],
                          "angle": sim["launch_angle"]}).groupby("row").mean()
    draws = draws.reindex(range(len(table)))
    table["launch_speed_residual"] = table["launch_speed"].to_numpy() - draws["speed"]
    table["launch_angle_residual"] = table["launch_angle"].to_numpy() - draws["angle"]
    raw = pd.read_csv(bt.resolve(name), encoding="utf-8-sig", low_memory=False)
    moves = raw[KEY + ["pfx_x", "pfx_z", "release_spin_rate"]].drop_duplicates(KEY)
    table = table.drop(columns=[c for c in moves.columns if c not in KEY and c in table])
    return table.merge(moves, on=KEY, how="left")


def coefficients(table: pd.DataFrame, column: str) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares coefficients of ``column`` on ``TERMS`` and their standard errors."""
    side = np.where(table["handedness"].to_numpy() == "L", -1.0, 1.0)
    # pfx_x is in the catcher's view, positive towards first base; a right-handed batter
    # stands on the third-base side, so movement towards him is negative pfx_x
    x = np.column_stack([np.ones(len(table)), table["pfx_z"], -table["pfx_x"] * side,
                         table["release_spin_rate"] / 1000.0])
    y = table[column].to_numpy(float)
    ok = np.isfinite(x).all(axis=1) & np.isfinite(y)
    beta, *_ = np.linalg.lstsq(x[ok], y[ok], rcond=None)
    resid = y[ok] - x[ok] @ beta
    cov = np.linalg.inv(x[ok].T @ x[ok]) * resid.var()
    return beta[1:], np.sqrt(np.diag(cov))[1:]


def combined(estimates) -> tuple[np.ndarray, np.ndarray]:
    """Inverse-variance weighted means of ``(coefficients, errors)`` pairs."""
    beta = np.array([b for b, _ in estimates])
    weight = 1.0 / np.array([e for _, e in estimates]) ** 2
    return (beta * weight).sum(axis=0) / weight.sum(axis=0), 1.0 / np.sqrt(weight.sum(axis=0))


def _line(label, beta, err) -> str:
    return f"  {label}: " + ", ".join(f"{t} {b:+.2f} +- {e:.2f}"
                                      for t, b, e in zip(TERMS, beta, err))


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m validation pitch_movement",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", help="Savant exports with bat tracking")
    parser.add_argument("--samples", type=int, default=100000)
    parser.add_argument("--seed", type=int, default=2025)
    args = parser.parse_args(argv)
    found = {"launch_angle_residual": [], "launch_speed_residual": []}
    for name in args.files:
        table = residuals(name, args.samples, args.seed)
        print(f"{name}: {len(table)} tracked balls in play; mean residual launch speed "
              f"{table['launch_speed_residual'].mean():+.2f} mph, launch angle "
              f"{table['launch_angle_residual'].mean():+.2f} deg")
        for column, unit in (("launch_angle_residual", "deg"),
                             ("launch_speed_residual", "mph")):
            beta, err = coefficients(table, column)
            found[column].append((beta, err))
            print(_line(f"{column} ({unit} per unit)", beta, err))
    if len(args.files) > 1:
        print("combined (inverse-variance weights):")
        for column, estimates in found.items():
            print(_line(column, *combined(estimates)))
    return 0


if __name__ == "__main__":
    main()
