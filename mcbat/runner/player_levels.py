"""Estimate each row's batter and pitcher contact from their other games
(``[pitches.player_levels]``, ``mcbat.study.player_levels``).

For every row drawn from, the study's own prediction (its mean launch speed and angle
over ``draws`` draws of the row) is set against the measured balls in play. A player's
level for a row is the mean of his residuals (measured - predicted) over his balls in
play in the file's *other* games, shrunk by ``tau^2 / (tau^2 + sigma^2 / n)`` (``tau``
the levels' sd of the table, ``sigma`` the residuals' sd over the file's other games,
``n`` his other balls): no ball's own outcome, nor any of its game's, enters its
prediction. The row's batter and pitcher levels add, and the two traits of the contact
that carry them (the spread along the bat, as ``log spread``, and the undercut's shift)
follow from the levels through the study's own sensitivities: the mean change of launch
speed and angle when every row's spread is multiplied by ``exp(-0.2)``, and when every
undercut moves by 0.25 in, on the same draws (common random numbers), a 2 x 2 linear
solve.

Everything is a function of the study, its seed and the file: the same in every process
(a Dask worker estimates what the client did), chunking and thread count.
"""

from __future__ import annotations

import numpy as np

from mcbat.core.status import ImpactStatus
from mcbat.errors import InputError
from mcbat.solving import GAME_OUTPUT_FIELDS, solve_games
from mcbat.solving.derived import derive_game
from mcbat.study import units as u
from mcbat.study.pitches import IDENTIFIERS
from mcbat.study.player_levels import SPREAD_LIMIT

__all__ = ["OBSERVED", "estimate_levels", "with_player_levels"]

#: The measured columns a level is taken from (Statcast's units: mph, deg).
OBSERVED = ("launch_speed", "launch_angle")
#: The steps of the sensitivities: the spread's log, the undercut (m).
LOG_SPREAD_STEP = -0.2
UNDERCUT_STEP = 0.25 * u.UNITS[u.LENGTH]["in"]
#: Samples solved at once (memory: about 1 kB each).
CHUNK = 131_072
#: Samples the sensitivities are measured on (the first of the prediction's).
SENSITIVITY_SAMPLES = 262_144
_PRIOR_UNITS = {"launch_speed": (u.SPEED, "mph"), "launch_angle": (u.ANGLE, "deg")}


def with_player_levels(study):
    """``study`` with its rows' players' contact (the study itself without
    ``[pitches.player_levels]``); its rows must be loaded."""
    source = getattr(study, "pitches", None)
    if source is None or source.player_levels is None:
        return study
    m = study.pitch_rows.index.size
    if any(c not in study.pitch_table.columns for c in OBSERVED):
        return study.with_player_contact(np.ones(m), np.zeros(m), {
            "rows_moved": 0, "measured": "the file has no launch_speed or launch_angle"})
    found = estimate_levels(study)
    spread, shift = found["contact"]
    moved = (spread != 1.0) | (shift != 0.0)
    summary = {f"{kind}s_with_level": n for kind, n in found["players"].items()}
    summary.update(rows_moved=int(moved.sum()),
                   spread_range=[float(spread.min()), float(spread.max())],
                   undercut_shift_range=[float(shift.min()), float(shift.max())])
    return study.with_player_contact(spread, shift, summary)


def estimate_levels(study, own_game=False) -> dict:
    """The levels of the loaded ``study``'s rows: ``{"levels": float64[2, M] (mph, deg),
    "contact": (spread[M], shift[M] m), "sensitivity": float64[2, 2] (mph and deg per
    log spread and per m; None when no player has another game), "players": {kind:
    players with another game}}``. ``own_game=True`` takes each level over all the
    player's balls, the row's own included: in sample, for judging what leaving the
    game out costs (no study does so).

    Raises
    ------
    InputError
        On ``pitches.player_levels`` when the contact's two traits move the launch speed
        and angle alike (no solution for the two levels).
    """
    if study.player_contact is not None:  # (the league's contact predicts the rows)
        study = study.with_pitch_table(study.pitch_table)
    spec, rows = study.pitches.player_levels, study.pitch_rows
    m = rows.index.size
    game = rows.identifiers[IDENTIFIERS.index("game_pk")]
    if not own_game and not any(
            _in_several_games(rows.identifiers[IDENTIFIERS.index(kind)], game)
            for kind in spec.spread):  # (a day's export: nothing to predict)
        return {"levels": np.zeros((2, m)), "contact": (np.ones(m), np.zeros(m)),
                "sensitivity": None, "players": dict.fromkeys(spec.spread, 0)}
    measured = np.vstack([np.asarray(study.pitch_table.columns[c], np.float64)[rows.index]
                          for c in OBSERVED])
    samples = spec.draws * m
    sums, counts = np.zeros((2, m)), np.zeros(m)
    for start in range(0, samples, CHUNK):
        stop = min(start + CHUNK, samples)
        out, ok, row = _solve(study, start, stop)
        counts += np.bincount(row[ok], minlength=m)
        for k in range(2):
            sums[k] += np.bincount(row[ok], out[k][ok], minlength=m)
    with np.errstate(invalid="ignore", divide="ignore"):
        residual = measured - sums / counts
    levels, players = np.zeros((2, m)), {}
    for kind, priors in spec.spread.items():
        player = rows.identifiers[IDENTIFIERS.index(kind)]
        for k, name in enumerate(OBSERVED):
            quantity, unit = _PRIOR_UNITS[name]
            tau = priors[k] / u.UNITS[quantity][unit]
            found, players[kind] = _other_games(residual[k], player, game, tau,
                                                own_game)
            levels[k] += found
    if not levels.any():  # (no player has another game: the league's contact everywhere)
        return {"levels": levels, "contact": (np.ones(m), np.zeros(m)),
                "sensitivity": None, "players": players}
    sensitivity = _sensitivity(study, min(samples, SENSITIVITY_SAMPLES))
    if not abs(np.linalg.det(sensitivity)) > 1e-9 * np.abs(sensitivity).max() ** 2:
        raise InputError("pitches.player_levels", "the study's contact does not move the "
                         "launch speed and angle apart (its spread along the bat and its "
                         "undercut act alike): widen [contact] from_barrel_end or undercut")
    log_spread, shift = np.linalg.solve(sensitivity, levels)
    spread = np.clip(np.exp(log_spread), 1.0 / SPREAD_LIMIT, SPREAD_LIMIT)
    return {"levels": levels, "contact": (spread, shift), "sensitivity": sensitivity,
            "players": players}


def _in_several_games(player, game) -> bool:
    """Whether any player appears in more than one game."""
    pairs = np.unique(np.column_stack([player, game]), axis=0)
    return len(pairs) > np.unique(player).size


def _other_games(residual, player, game, tau, own_game=False) -> tuple[np.ndarray, int]:
    """Each row's shrunk mean of its player's ``residual`` over his other games, and how
    many players have another game (NaN residuals count for nothing). The residuals'
    variance ``sigma^2`` is the file's without the row's own game too. ``own_game``:
    over all his games, the row's own included (in sample)."""
    valid = np.isfinite(residual)
    value = np.where(valid, residual, 0.0)
    _, g = np.unique(game, return_inverse=True)
    _, p = np.unique(player, return_inverse=True)
    _, pg = np.unique(np.column_stack([player, game]), axis=0, return_inverse=True)
    g, p, pg = g.ravel(), p.ravel(), pg.ravel()
    drop = 0.0 if own_game else 1.0  # (whether the row's own game is left out)
    n_rest = valid.sum() - drop * np.bincount(g, valid)[g]
    s_rest = value.sum() - drop * np.bincount(g, value)[g]
    q_rest = (value ** 2).sum() - drop * np.bincount(g, value ** 2)[g]
    sigma2 = np.where(n_rest > 1.5, (q_rest - s_rest ** 2 / np.maximum(n_rest, 1.0))
                      / np.maximum(n_rest, 1.0), 0.0)
    n_other = np.bincount(p, valid)[p] - drop * np.bincount(pg, valid)[pg]
    s_other = np.bincount(p, value)[p] - drop * np.bincount(pg, value)[pg]
    has = n_other > 0.5
    mean = np.where(has, s_other / np.maximum(n_other, 1.0), 0.0)
    shrink = np.where(has, tau ** 2 / (tau ** 2 + sigma2 / np.maximum(n_other, 1.0)), 0.0)
    return shrink * mean, int(np.unique(player[has]).size)


def _sensitivity(study, samples) -> np.ndarray:
    """Mean change of launch speed (mph) and angle (deg) per unit log spread and per m
    of undercut, over the first ``samples`` draws (the same draws moved)."""
    m = study.pitch_rows.index.size
    ones, zeros = np.ones(m), np.zeros(m)
    steps = ((np.exp(np.full(m, LOG_SPREAD_STEP)), zeros, LOG_SPREAD_STEP),
             (ones, np.full(m, UNDERCUT_STEP), UNDERCUT_STEP))
    base, ok_base, _ = _solve(study, 0, samples)
    out = np.zeros((2, 2))
    for j, (spread, shift, step) in enumerate(steps):
        moved, ok, _ = _solve(study.with_player_contact(spread, shift), 0, samples)
        both = ok & ok_base
        out[:, j] = (moved[:, both] - base[:, both]).mean(axis=1) / step
    return out


def _solve(study, start, stop):
    """Launch speed (mph) and angle (deg) of samples ``start .. stop - 1``, which were
    solved, and the row each drew."""
    inputs = study.sample_inputs(start, stop, study.seed)
    row = study.pitch_rows.draw_rows(study.seed, start, stop - start)
    _, _, game_out, status, _ = solve_games(inputs, study.solver_settings)
    g = {name: game_out[i] for i, name in enumerate(GAME_OUTPUT_FIELDS)}
    batted = derive_game([g[f"field_ball_v{c}"] for c in "xyz"],
                         [g[f"field_ball_w{c}"] for c in "xyz"])
    out = np.vstack([np.asarray(batted[c], np.float64) for c in OBSERVED])
    return out, (status == ImpactStatus.OK) & np.isfinite(out).all(axis=0), row
