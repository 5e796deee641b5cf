"""The attack angle the data leave open: the inference runs at Gauss-Hermite nodes of
the true attack angle's distribution (given the measured one, where there is one), weighs
each node's contact by its density (the population's, over the Jacobian of the change of
variables from the contact to the measured ball) and combines the nodes into one result
per ball (``docs/spin_inference.md``, "The open swing")."""

from __future__ import annotations

import math

import numpy as np

from mcbat.core.units import RAD_PER_DEG
from mcbat.inference.assumptions import SpinAssumptions
from mcbat.solving import GAME_INPUT_FIELDS, GAME_OUTPUT_FIELDS, solve_games
from mcbat.solving.inference import INFER_BAT_SPEED, SOLUTION_FIELDS, InferenceStatus

__all__ = ["attack_angle_nodes", "combine", "posterior_weight"]


def attack_angle_nodes(measured, a: SpinAssumptions, count):
    """The attack angles (rad, one array per node) and their prior weights: Gauss-Hermite
    nodes of the true attack angle's distribution, given the measured one where there is
    one (``SpinAssumptions``); one node: the measured, else the assumed, attack angle."""
    finite = np.isfinite(measured)
    if count == 1:
        return [(np.where(finite, measured * RAD_PER_DEG, a.attack_angle), 1.0)]
    sd, error = a.attack_angle_sd, a.attack_angle_error
    total = sd * sd + error * error
    k = sd * sd / total if total > 0.0 else 1.0
    m = np.where(finite, measured * RAD_PER_DEG, a.attack_angle)
    centre = np.where(finite, a.attack_angle + k * (m - a.attack_angle), a.attack_angle)
    spread = np.where(finite, math.sqrt(k) * error, sd)
    x, w = np.polynomial.hermite_e.hermegauss(count)
    w = w / w.sum()
    return [(centre + spread * xi, float(wi)) for xi, wi in zip(x, w)]


def launch(game, options):
    """Launch speed (m/s), angle and spray (rad) of the game inputs ``game``."""
    game_out = solve_games(game, options.solver).game_out
    i = GAME_OUTPUT_FIELDS.index("field_ball_vx")
    vx, vy, vz = game_out[i], game_out[i + 1], game_out[i + 2]
    return np.stack((np.sqrt(vx * vx + vy * vy + vz * vz), np.arctan2(vz, np.hypot(vx, vy)),
                     np.arctan2(vx, vy)))


def posterior_weight(game, mode, solution, ok, a: SpinAssumptions, options):
    """The density of the contact that gives each ball at one attack-angle node (0 where
    none does), up to a factor common to the nodes: the population's density of the
    undercut, the attack direction and the bat speed (where inferred; the contact
    position where the bat speed is measured), over ``|det J|``, ``J`` the Jacobian of
    launch speed, angle and spray with respect to them (the change of variables from the
    contact to the measured ball)."""
    weight = np.zeros(ok.shape[0])
    cols = np.flatnonzero(ok)
    if cols.size == 0:
        return weight
    sol = dict(zip(SOLUTION_FIELDS, solution[:, cols]))
    g = np.ascontiguousarray(game[:, cols])
    rows = {name: i for i, name in enumerate(GAME_INPUT_FIELDS)}
    bat = a.bat
    z = sol["from_barrel_end"]
    radius, slope = bat.surface(np.asarray(bat.clip_axial(bat.cm_from_barrel_end - z)))
    g[rows["from_barrel_end"]] = z
    g[rows["bat_radius"]] = radius
    g[rows["bat_slope"]] = slope
    g[rows["e_location_factor"]] = a.restitution.location_factor(z)
    g[rows["bat_speed"]] = sol["bat_speed"]
    g[rows["undercut"]] = sol["undercut"]
    g[rows["attack_direction"]] = sol["attack_direction"]
    speed_mode = (mode[cols] == INFER_BAT_SPEED) | (np.abs(
        sol["bat_speed"] - game[rows["bat_speed"], cols]) > 1e-9 * sol["bat_speed"])
    base = launch(g, options)
    jac = np.empty((cols.size, 3, 3))
    steps = (1e-5, 1e-4, 1e-5)
    for k, name in enumerate(("undercut", None, "attack_direction")):
        shifted = g.copy()
        if name is None:
            # the second unknown: the bat speed (inferred or moved), else the position
            h = np.where(speed_mode, 1e-4 * sol["bat_speed"], steps[1])
            shifted[rows["bat_speed"]] += np.where(speed_mode, h, 0.0)
            zz = z + np.where(speed_mode, 0.0, h)
            r2, s2 = bat.surface(np.asarray(bat.clip_axial(bat.cm_from_barrel_end - zz)))
            shifted[rows["from_barrel_end"]] = zz
            shifted[rows["bat_radius"]] = r2
            shifted[rows["bat_slope"]] = s2
            shifted[rows["e_location_factor"]] = a.restitution.location_factor(zz)
        else:
            h = np.full(cols.size, steps[k])
            shifted[rows[name]] += h
        jac[:, :, k] = ((launch(shifted, options) - base) / h).T
    det = np.abs(np.linalg.det(jac))
    u = (sol["undercut"] - a.undercut_mean) / a.undercut_sd
    d = sol["attack_direction"] / a.attack_direction_sd
    if a.from_barrel_end_sd > 0.0:
        second = np.where(speed_mode,
                          (sol["bat_speed"] - a.bat_speed_mean) / a.bat_speed_sd,
                          (z - a.from_barrel_end_mean) / a.from_barrel_end_sd)
        # the two densities' own scales (1/sd) differ: keep them
        scale2 = np.where(speed_mode, 1.0 / a.bat_speed_sd, 1.0 / a.from_barrel_end_sd)
    else:
        second, scale2 = np.zeros(cols.size), np.ones(cols.size)
    dens = np.exp(-0.5 * (u * u + d * d + second * second)) * scale2
    w = np.where(det > 0.0, dens / np.where(det > 0.0, det, 1.0), 0.0)
    weight[cols] = np.where(np.isfinite(w), w, 0.0)
    return weight


def combine(runs, a: SpinAssumptions):
    """One result per ball from the runs at each attack-angle node: the mean over the
    nodes that give the ball (converged, within the bat speed's error), each weighted by
    its prior weight times the undercut's density (``SpinAssumptions.undercut_mean``,
    ``undercut_sd``). Returns ``(solution, status, iterations, evaluations, adjustment,
    bat_speed_inconsistent, attack_angle deg)``."""
    if len(runs) == 1:
        attack, _, solution, status, iterations, evaluations, adjustment, bad = runs[0]
        return solution, status, iterations, evaluations, adjustment, bad, np.degrees(attack)
    n = runs[0][2].shape[1]
    total = np.zeros(n)
    solution = np.zeros_like(runs[0][2])
    adjustment = np.zeros(n)
    attack = np.zeros(n)
    iterations = np.zeros(n, np.int32)
    evaluations = np.zeros(n, np.int32)
    any_bad = np.zeros(n, bool)
    for node, prior, sol, status, its, evs, adj, bad in runs:
        ok = (status == InferenceStatus.CONVERGED) & ~bad
        w = np.where(ok, np.nan_to_num(prior), 0.0)
        total += w
        solution += np.where(ok, w * np.where(ok, sol, 0.0), 0.0)
        adjustment += np.where(ok, w * np.nan_to_num(adj), 0.0)
        attack += w * np.where(ok, node, 0.0)
        iterations += its
        evaluations += evs
        any_bad |= bad
    found = total > 0.0
    # a ball no node gives: the status of the central node (the distribution's mean)
    centre = runs[len(runs) // 2]
    status = np.where(found, 0, np.where(centre[3] == 0, 1, centre[3])).astype(np.int8)
    scale = np.where(found, 1.0 / np.where(found, total, 1.0), np.nan)
    solution = solution * scale
    adjustment = np.where(np.isnan(runs[0][6]), np.nan, adjustment * scale)
    adjustment[np.abs(adjustment) < 1e-9] = 0.0
    bad = ~found & any_bad
    return (solution, status, iterations, evaluations, adjustment, bad,
            np.degrees(attack * scale))
