"""Population fits: a game study's distributions fitted to a table of measured batted balls.

A per-row fit (``mcbat.stats.fit.estimate``) asks, for each ball, how likely its observables are
given a Gaussian of the model's draws. A batting population is no Gaussian (one swing
gives launch angles from -30 to 60 deg), and what a season measures is the *joint
distribution* of the batted balls. This module fits the parameters of the study's
distributions (the mean and width of the bat speed, the attack angle, the undercut, the
contact position; ``mu`` and ``e_x`` when the study draws them) and the physics constants
``e`` (the game restitution's ``e*`` at its reference speed), ``mu`` and ``e_x`` so that
the simulated distribution of ``launch_speed`` x ``launch_angle`` (optionally x
``spray_angle`` and, for a study with a ``[flight]``, x ``hit_distance``), *given each
row's measured pitch*, matches the table's.

The method (``docs/population.md`` has the reasons and the checks):

* **Templates conditioned on the measured pitches.** The study is rewritten with a
  ``[pitches]`` section holding the table's own rows (their plate speed, approach angles,
  spin and the batter's side), so every draw meets one of the measured pitches, resampled
  with replacement; the swing and the contact come from the study's distributions. Pitch
  values a row lacks (``spin_axis`` before 2020) come from the study's own distribution of
  that key, as ``[pitches.fallback]``.
* **Reweighting.** The distributions' parameters are fitted by reweighting one set of
  draws: they are drawn once from a *proposal*, the study's distribution of each free key
  widened by ``BROADEN`` (same support), and draw ``k`` weighs
  ``prod_keys p(x_k | theta) / q(x_k)``. Exact for parameters of input distributions, and
  smooth in them, so MIGRAD sees a smooth likelihood. A second pass draws again from a
  proposal centred on the first pass's best fit, which keeps the weights' effective
  sample size high wherever the truth lies.
* **The distance.** With ``hit_distance`` among the observables every draw is also flown
  with the study's ``[flight]`` (as an engine's run of it flies it). The distance is a
  deterministic function of the launch (velocity and spin) and the flight's fixed
  settings, so a draw's weight, a function of its inputs alone, weighs its distance as it
  weighs its launch: the reweighting carries over unchanged.
* **Physics constants by a grid.** ``e``, ``mu`` and ``e_x`` are not distributions of the
  inputs but constants of the map from inputs to batted balls, so no weight can change
  them: each is simulated at ``NODES`` values (the same random numbers at every node)
  and the bin contents are interpolated linearly between nodes (multilinearly for several).
  The first pass's grid is coarse; the second's is centred on its best fit and spans +-4
  of its errors, where a linear interpolation of the bins is accurate.
* **Likelihood.** Binned in the observables: equal-count bins of the data along each axis
  (open-ended at both ends, so every draw lands in a bin), the template normalised to the
  table's row count, and the cost of Dembinski & Abdelmotteleb (2022), a light
  Barlow-Beeston treatment of *weighted* templates of finite size
  (``iminuit.cost.template_chi2_da``): each bin's template has its weights' sum and
  variance, and the template's own fluctuations widen the intervals instead of biasing
  them. The minimum is asymptotically chi2 distributed (``cells - 1 - free`` degrees of
  freedom, counting the cells some draw reaches or some row lies in), which is the
  goodness of fit reported.
* **Intervals.** MINOS profile-likelihood intervals (a rise of 1 in the chi2-like cost).

Beside this module (the fit): ``mcbat.stats.population.table`` (the rows used),
``mcbat.stats.population.parameters`` (the free parameters),
``mcbat.stats.population.templates`` (the draws) and
``mcbat.stats.population.likelihood`` (bins and cost); the names a caller needs are
importable from here.

Where the template draws run: ``engine="memory"`` solves them in this process (numba
threads, nothing written); ``"local"`` and ``"dask"`` run the derived studies with
``mcbat.runner.study_run.run_study`` into a directory and read the datasets back, so
the draws of a season's fit scale out on a cluster. The draws are the same on every engine
(same study, same seed: the project's reproducibility).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from mcbat.bodies.restitution import GAME_RESTITUTION
from mcbat.errors import InputError
from mcbat.stats.population.likelihood import (
    BinnedCost,
    bin_index,
    equal_count_edges,
    grid_corners,
)
from mcbat.stats.population.parameters import (
    PHYSICS,
    PHYSICS_RANGE,
    fittable_parameters,
    parse_free,
)
from mcbat.stats.population.table import FLIGHT_OBSERVABLES, OBSERVABLES, population_table
from mcbat.stats.population.templates import ENGINES, TemplateSimulator, simulate_table

__all__ = ["BROADEN", "DEFAULT_DRAWS", "ENGINES", "NODES", "OBSERVABLES", "PHYSICS",
           "PopulationResult", "fit_population", "fittable_parameters", "grid_corners",
           "population_table", "simulate_table"]

_COARSE = {"e": 0.06, "mu": 0.3, "e_x": 0.3}
"""Half-width of the first pass's grid about the study's value."""
NODES = 5
"""Grid values per physics constant and pass."""
BROADEN = 1.5
"""The proposal's width over the distribution's (a wider proposal covers more of the
parameter space for a lower effective sample size at the truth)."""
DEFAULT_DRAWS = 100
"""Template draws per table row."""
ROWS_PER_BIN = 8
"""Default binning: about this many rows per bin on average."""


# ------------------------------------------------------------------ the fit


@dataclass
class PopulationResult:
    """A population fit's values, MINOS intervals and goodness of fit."""

    parameters: list
    chi2: float
    dof: int
    p_value: float
    rows: int
    dropped: dict
    bins: dict
    draws: int
    effective_draws: float
    observables: tuple
    engine: str
    warnings: list = field(default_factory=list)
    figure_data: dict = field(default_factory=dict, repr=False)
    cells: dict = field(default_factory=dict)
    """``total``: the bins' cells; ``used``: those the draws reach or the data hold (the
    others can hold no ball and count no degree of freedom)."""

    def lines(self):
        """One line per parameter: value, MINOS interval, unit."""
        out = []
        for p in self.parameters:
            lo = "?" if p["lower_error"] is None else f"{p['lower_error']:.3g}"
            hi = "?" if p["upper_error"] is None else f"{p['upper_error']:.3g}"
            unit = "" if p["unit"] == "1" else f" {p['unit']}"
            out.append(f"  {p['name']} = {p['value']:.4g} -{lo} +{hi}{unit} "
                       f"(study: {p['study_value']:.4g})")
        return out

    def to_dict(self):
        """JSON-ready (no NaN)."""
        return {"parameters": self.parameters, "chi2": self.chi2, "dof": self.dof,
                "p_value": self.p_value, "rows": self.rows, "dropped": self.dropped,
                "bins": self.bins, "draws": self.draws,
                "effective_draws": self.effective_draws,
                "observables": list(self.observables), "cells": self.cells,
                "engine": self.engine,
                "method": "binned likelihood, Barlow-Beeston-lite for weighted templates "
                          "(iminuit.cost.template_chi2_da), MINOS intervals",
                "warnings": self.warnings}


def fit_population(study, table, free, *, draws=None, bins=None,
                   observables=("launch_speed", "launch_angle"), seed=0, engine="memory",
                   workdir=None, passes=2):
    """Fit ``free`` parameters of a game ``study`` to the batted balls of ``table``.

    Parameters
    ----------
    study : GameStudy
        The game (its ``[pitches]``, if any, is replaced by the table's rows).
    table : pandas.DataFrame
        A tidy Statcast table (``mcbat.statcast.read``); rows are selected by
        ``population_table``.
    free : sequence of str
        ``<section>.<key>.mean`` / ``.std`` of the study's normal or truncnormal keys, and
        any of ``e``, ``mu``, ``e_x`` (``fittable_parameters``).
    draws : int, optional
        Template draws per row (default ``DEFAULT_DRAWS``).
    bins : int, optional
        Bins per observable (default: about ``ROWS_PER_BIN`` rows per bin).
    observables : sequence of str
        Of ``OBSERVABLES``; ``hit_distance`` (ft, read from Statcast's
        ``hit_distance_sc``; rows without one are left out) needs a study with a
        ``[flight]`` section.
    seed : int
        The template draws' seed.
    engine : {"memory", "local", "dask"}
        Where the draws are solved (module docstring).
    workdir : path, optional
        Where the engines write the templates (default: a temporary directory).
    passes : int
        Proposal passes (the last is reported).

    Returns
    -------
    PopulationResult

    Raises
    ------
    InputError
        Bad parameters, observables, table, or a template that cannot cover the data.
    """
    observables = tuple(observables)
    if bins is not None and bins < 2:
        raise InputError("bins", f"must be at least 2, got {bins}")
    if draws is not None and draws < 1:
        raise InputError("draws", f"must be at least 1, got {draws}")
    if not observables or len(set(observables)) != len(observables):
        raise InputError("observables", "give each observable once, at least one")
    for name in observables:
        if name not in OBSERVABLES:
            raise InputError("observables", f"unknown observable {name!r} (choose from "
                             f"{', '.join(OBSERVABLES)})")
    flown = [o for o in observables if o in FLIGHT_OBSERVABLES]
    if flown and getattr(study, "flight", None) is None:
        raise InputError("observables", f"{flown[0]} needs a study with a [flight] section "
                         f"(docs/flight.md); study {study.name!r} has none")
    keys, params, physics = parse_free(study, tuple(free))
    source = table.attrs.get("source")
    real = getattr(study, "pitches", None)
    data, dropped = population_table(table, observables, source,
                                     swing=bool(real is not None and real.swing),
                                     filters=dict(real.filters) if real is not None else None)
    rows = len(data)
    # about ROWS_PER_BIN rows per bin, but at least 5 bins an axis (3 with three
    # observables): 100 rows in 3 x 3 bins left 3 degrees of freedom for 5 parameters
    per_axis = bins or max(5 if len(observables) < 3 else 3,
                           int((rows / ROWS_PER_BIN) ** (1.0 / len(observables))))
    edges = [equal_count_edges(data[o].to_numpy(float), per_axis) for o in observables]
    nbins = int(np.prod([len(e) + 1 for e in edges]))
    n = np.bincount(bin_index([data[o].to_numpy(float) for o in observables], edges),
                    minlength=nbins).astype(float)
    m = (draws or DEFAULT_DRAWS) * rows
    sim = TemplateSimulator(study, data, m, seed, engine, workdir, flight=bool(flown))
    study_values = {key: (k.mean, k.std) for key, k in keys.items()}
    centre = {key: [k.mean, k.std] for key, k in keys.items()}
    phys0 = {p: _study_physics(study, p) for p in physics}
    phys_centre, phys_width = dict(phys0), {p: _COARSE[p] for p in physics}
    warnings = []
    try:
        npass = extra = 0
        while True:
            cost, nodes = _build_cost(sim, keys, params, physics, centre, phys_centre,
                                      phys_width, observables, edges, n, nbins)
            if npass == 0:
                _check_cover(cost, n, data, observables, edges, source)
            mn = _minimise(cost, keys, params, physics, centre, phys_centre, nodes)
            dists, phys = cost.values(np.array(mn.values))
            err = dict(zip(mn.parameters, mn.errors))
            # the next proposal about the best fit, never narrower than half the study's
            # width (a width the first pass could not bound would starve the draws)
            centre = {key: [v[0], max(v[1], 0.5 * keys[key].std)] for key, v in dists.items()}
            phys_centre = phys
            npass += 1
            # a constant at the end of its grid: another pass on a grid twice as wide
            edge = [p for p in physics if _at_edge(phys[p], nodes[p], PHYSICS_RANGE[p])]
            if edge and extra < 3:
                extra += 1
            elif npass >= passes + extra:
                break
            phys_width = {p: 2.0 * phys_width[p] if p in edge else max(4.0 * err[p], 0.005)
                          for p in physics}
        _minos(mn)
    finally:
        sim.close()
    theta = np.array(mn.values)
    w = cost.weights(theta)
    ess = float(w.sum() ** 2 / np.sum(w**2))
    if not mn.valid:
        warnings.append("MIGRAD did not converge: the values are not a minimum")
    if dropped.get("no_hit_distance"):
        warnings.append(f"{dropped['no_hit_distance']} batted balls without a measured "
                        "distance (hit_distance_sc) left out: balls the tracking lost, whose "
                        "launch is not measured either; the fit describes the tracked balls")
    result_params = _parameters(mn, keys, params, physics, study_values, phys0, warnings)
    chi2 = float(mn.fval)
    # A cell no draw of the last pass reaches (at any node) and no row lies in (a launch
    # speed, angle and distance that no flight joins) adds nothing to the cost: it is no
    # degree of freedom.
    used = int(np.sum(_reached(cost) | (n > 0)))
    dof = used - 1 - len(theta)
    if ess < 5 * rows:
        warnings.append(f"the template's effective size at the best fit is {ess:.0f} draws, "
                        f"under 5 per row: raise --draws")
    return PopulationResult(
        result_params, chi2, dof, float(stats.chi2.sf(chi2, dof)) if dof > 0 else math.nan,
        rows, dropped, {o: [float(x) for x in e] for o, e in zip(observables, edges)},
        m, ess, observables, engine, warnings,
        {"data": data, "cost": cost, "theta": np.array(mn.values), "edges": edges,
         "n": n, "minuit": mn}, {"total": nbins, "used": used})


def _minimise(cost, keys, params, physics, centre, phys_centre, nodes):
    """MIGRAD from the proposal's centre."""
    from iminuit import Minuit

    start = ([centre[key][0 if what == "mean" else 1] for _, key, what in params]
             + [phys_centre[p] for p in physics])
    mn = Minuit(cost, start, name=[p[0] for p in params] + physics)
    _limits(mn, keys, params, physics, nodes)
    mn.migrad()
    return mn


def _minos(mn, attempts=3):
    """MINOS, from a minimum polished with the careful strategy; where MINOS walks into a
    lower minimum than MIGRAD's (a long, curved valley: the widths of two inputs that both
    widen the launch angles), MIGRAD restarts from there and MINOS runs again."""
    mn.strategy = 2
    mn.tol = 0.01
    mn.migrad()
    mn.hesse()
    for _ in range(attempts):
        mn.minos()
        if not _restart_at_new_minimum(mn):
            break
    if any(name not in mn.merrors for name in mn.parameters):
        mn.minos()  # (a restart that found nothing lower re-ran MIGRAD, which clears them)


def _restart_at_new_minimum(mn):
    """Restart MIGRAD from the end of a MINOS walk that found a lower value; True when a
    lower minimum was found."""
    best, values = mn.fval, np.array(mn.values)
    errors = {name: mn.merrors[name] for name in mn.parameters if name in mn.merrors}
    for i, name in enumerate(mn.parameters):
        me = errors.get(name)
        if me is None or not (me.lower_new_min or me.upper_new_min):
            continue
        trial = values.copy()
        trial[i] += me.lower if me.lower_new_min else me.upper
        lo, hi = mn.limits[i]
        trial[i] = min(max(trial[i], lo), hi)
        mn.values = trial
        mn.migrad()
        if mn.fval < best - 1e-6:
            mn.hesse()
            return True
        mn.values = values
        mn.migrad()
    return False


def _at_edge(value, z, physical):
    """Whether ``value`` sits at an end of grid ``z`` that is not a physical end."""
    tol = 1e-3 * (z[-1] - z[0])
    return ((abs(value - z[0]) < tol and z[0] > physical[0])
            or (abs(value - z[-1]) < tol and z[-1] < physical[1]))


def _study_physics(study, name):
    section, key = PHYSICS[name]
    dist = study.inputs.get(f"{section}.{key}")
    if dist is None and name == "e":
        dist = study.inputs.get("restitution.e")
    if dist is None:
        return getattr(study.restitution if section == "restitution" else GAME_RESTITUTION,
                       key, None) or getattr(GAME_RESTITUTION, key)
    if dist.kind == "fixed":
        return dist.value
    lo, hi = dist.support()
    return float(dist.mean) if hasattr(dist, "mean") else 0.5 * (lo + hi)


def _build_cost(sim, keys, params, physics, centre, phys_centre, phys_width, observables,
                edges, n, nbins):
    """Simulate the proposal at every physics node and bin the draws."""
    proposal = {key: (k, centre[key][0], BROADEN * centre[key][1]) for key, k in keys.items()}
    nodes = {}
    for p in physics:
        lo = max(PHYSICS_RANGE[p][0], phys_centre[p] - phys_width[p])
        hi = min(PHYSICS_RANGE[p][1], phys_centre[p] + phys_width[p])
        nodes[p] = np.linspace(lo, hi, NODES)
    columns = [k.column for k in keys.values()]
    idx, obs = {}, {}
    x = logq = None
    for corner in np.ndindex(*(NODES for _ in physics)):
        values = {p: float(nodes[p][j]) for p, j in zip(physics, corner)}
        inputs, observed, ok = sim.run(proposal, values, columns, observables)
        index = bin_index([observed[o] for o in observables], edges)
        index[~ok] = -1
        idx[corner] = index
        obs[corner] = np.stack([np.where(ok, observed[o], np.nan) for o in observables])
        if x is None:  # the inputs are the same at every node (same random numbers)
            x = {key: inputs[k.column] / k.scale for key, k in keys.items()}
            logq = sum((k.logpdf(x[key], proposal[key][1], proposal[key][2])
                        for key, k in keys.items()), np.zeros(len(ok)))
    cost = BinnedCost(n, keys, params, physics, nodes, x, logq, idx, nbins)
    cost.proposal, cost.observed = proposal, obs
    return cost, nodes


def _limits(mn, keys, params, physics, nodes):
    for name, key, what in params:
        k = keys[key]
        if what == "mean":
            mn.limits[name] = (k.low if math.isfinite(k.low) else None,
                               k.high if math.isfinite(k.high) else None)
        else:
            # Not below a quarter of the study's width: there the proposal (1.5 times the
            # study's width) leaves a few effective draws, and on 100-row tables the attack
            # angle's width (which the undercut's can stand in for) collapsed onto a limit
            # of 0.02 times it, in a minimum made of a handful of heavy draws.
            mn.limits[name] = (0.25 * k.std, 5.0 * k.std)
        mn.errors[name] = 0.1 * k.std
    for p in physics:
        mn.limits[p] = (float(nodes[p][0]), float(nodes[p][-1]))
        mn.errors[p] = 0.1 * (nodes[p][-1] - nodes[p][0])


def _check_cover(cost, n, data, observables, edges, source):
    """Refuse data in bins the proposal's draws never reach (at any node)."""
    empty = (n > 0) & ~_reached(cost)
    if empty.any():
        where = np.isin(bin_index([data[o].to_numpy(float) for o in observables], edges),
                        np.flatnonzero(empty))
        ranges = ", ".join(f"{o} {data[o][where].min():.4g} to {data[o][where].max():.4g} "
                           f"{OBSERVABLES[o]}" for o in observables)
        raise InputError("data", f"{int(where.sum())} rows ({ranges}) lie where the study's "
                         "draws give no batted ball, even with its distributions widened: "
                         "the template cannot cover the data (widen the study's contact "
                         "or swing distributions, raise --draws, or check the table's "
                         "units)", source)


def _reached(cost):
    """The bins some draw reaches, at any node."""
    reached = np.zeros(cost.nbins, bool)
    for idx in cost.idx.values():
        reached[idx[idx >= 0]] = True
    return reached


def _parameters(mn, keys, params, physics, study_values, phys0, warnings):
    out = []
    for name in mn.parameters:
        if name in physics:
            unit, study_value = "1", phys0[name]
        else:
            _, key, what = next(p for p in params if p[0] == name)
            unit = keys[key].unit
            study_value = study_values[key][0 if what == "mean" else 1]
        me = mn.merrors[name] if name in mn.merrors else None
        lower = upper = None
        if me is not None and (me.lower_valid or me.upper_valid):
            # (one side of an interval is reported when MINOS found only that one)
            lower = float(-me.lower) if me.lower_valid else None
            upper = float(me.upper) if me.upper_valid else None
        if me is None:
            warnings.append(f"{name}: no MINOS interval")
        elif not me.is_valid:
            why = [k for k in ("lower_new_min", "upper_new_min", "at_lower_max_fcn",
                               "at_upper_max_fcn", "at_lower_limit", "at_upper_limit")
                   if getattr(me, k)]
            warnings.append(f"{name}: MINOS found no valid interval "
                            f"({', '.join(why) or 'no crossing'})")
        if me is not None and (me.at_lower_limit or me.at_upper_limit):
            side = "lower" if me.at_lower_limit else "upper"
            warnings.append(f"{name}: its interval reaches the fit's {side} limit")
        out.append({"name": name, "value": float(mn.values[name]),
                    "stderr": float(mn.errors[name]), "lower_error": lower,
                    "upper_error": upper, "unit": unit, "study_value": float(study_value)})
    return out
