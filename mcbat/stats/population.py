"""Population fits: a game study's distributions fitted to a table of measured batted balls.

A per-row fit (:mod:`mcbat.stats.fit`) asks, for each ball, how likely its observables are
given a Gaussian of the model's draws. A batting population is no Gaussian (one swing
gives launch angles from -30 to 60 deg), and what a season measures is the *joint
distribution* of the batted balls. This module fits the parameters of the study's
distributions (the mean and width of the bat speed, the attack angle, the undercut, the
contact position; ``mu`` and ``e_x`` when the study draws them) and the physics constants
``e`` (the game restitution's ``e*`` at its reference speed), ``mu`` and ``e_x`` so that
the simulated distribution of ``launch_speed`` x ``launch_angle`` (optionally x
``spray_angle``), *given each row's measured pitch*, matches the table's.

The method (``docs/population.md`` has the reasons and the checks):

* **Templates conditioned on the measured pitches.** The study is rewritten with a
  ``[pitches]`` section holding the table's own rows (their plate speed, approach angles,
  spin and the batter's side), so every draw meets one of the measured pitches, resampled
  with replacement; the swing and the contact come from the study's distributions. Pitch
  values a row lacks (``spin_axis`` before 2020) come from the study's own distribution of
  that key, as ``[pitches.fallback]``.
* **Reweighting.** The distributions' parameters are fitted by reweighting one set of
  draws: they are drawn once from a *proposal*, the study's distribution of each free key
  widened by :data:`BROADEN` (same support), and draw ``k`` weighs
  ``prod_keys p(x_k | theta) / q(x_k)``. Exact for parameters of input distributions, and
  smooth in them, so MIGRAD sees a smooth likelihood. A second pass draws again from a
  proposal centred on the first pass's best fit, which keeps the weights' effective
  sample size high wherever the truth lies.
* **Physics constants by a grid.** ``e``, ``mu`` and ``e_x`` are not distributions of the
  inputs but constants of the map from inputs to batted balls, so no weight can change
  them: each is simulated at :data:`NODES` values (the same random numbers at every node)
  and the bin contents are interpolated linearly between nodes (multilinearly for several).
  The first pass's grid is coarse; the second's is centred on its best fit and spans +-4
  of its errors, where a linear interpolation of the bins is accurate.
* **Likelihood.** Binned in the observables: equal-count bins of the data along each axis
  (open-ended at both ends, so every draw lands in a bin), the template normalised to the
  table's row count, and the cost of Dembinski & Abdelmotteleb (2022), a light
  Barlow-Beeston treatment of *weighted* templates of finite size
  (:func:`iminuit.cost.template_chi2_da`): each bin's template has its weights' sum and
  variance, and the template's own fluctuations widen the intervals instead of biasing
  them. The minimum is asymptotically chi2 distributed (``bins - 1 - free`` degrees of
  freedom), which is the goodness of fit reported.
* **Intervals.** MINOS profile-likelihood intervals (a rise of 1 in the chi2-like cost).

Where the template draws run: ``engine="memory"`` solves them in this process (numba
threads, nothing written); ``"local"`` and ``"dask"`` run the derived studies with
:func:`mcbat.runner.study_run.run_study` into a directory and read the datasets back, so
the draws of a season's fit scale out on a cluster. The draws are the same on every engine
(same study, same seed: the project's reproducibility).
"""

from __future__ import annotations

import copy
import math
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import special, stats

from mcbat.bodies.game import GAME_RESTITUTION
from mcbat.core.swing import GAME_INPUT_FIELDS
from mcbat.errors import InputError
from mcbat.stats.simulate import solve_game_inputs
from mcbat.study import units as u
from mcbat.study.game import KEYS
from mcbat.study.spec import Study

__all__ = ["BROADEN", "DEFAULT_DRAWS", "ENGINES", "NODES", "OBSERVABLES", "PHYSICS",
           "PopulationResult", "fit_population", "fittable_parameters", "grid_corners",
           "population_table", "simulate_table"]

OBSERVABLES = {"launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg"}
"""The batted-ball observables a population fit can bin (Statcast's names and units)."""
PITCH_COLUMNS = {"pitch.speed": "pitch_speed",
                 "pitch.vertical_approach_angle": "vertical_approach_angle",
                 "pitch.horizontal_approach_angle": "horizontal_approach_angle",
                 "pitch.spin_rate": "spin_rate", "pitch.spin_axis": "spin_axis"}
"""Study key -> the table's measured pitch column (mcbat.statcast's tidy names)."""
REQUIRED_PITCH = ("pitch_speed", "vertical_approach_angle", "horizontal_approach_angle")
"""A row without these is left out (counted): its template could not be conditioned."""
_IDENTIFIERS = ("game_pk", "at_bat_number", "pitch_number", "pitcher", "batter")
PHYSICS = {"e": ("restitution", "e_ref"), "mu": ("friction", "mu"),
           "e_x": ("restitution", "e_x")}
"""Physics constants a population fit can free, and the study key each sets."""
PHYSICS_RANGE = {"e": (0.2, 0.8), "mu": (0.0, 1.5), "e_x": (0.0, 1.0)}
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
ENGINES = ("memory", "local", "dask")
_FITTABLE_FIELDS = {"normal": ("mean", "std"), "truncnormal": ("mean", "std")}
_SI = {"speed": "mph", "angle": "deg", "length": "in", "spin": "rpm", "dimensionless": "1"}
"""The unit parameters are reported (and fitted) in when the study wrote none."""


# ------------------------------------------------------------------ the table


def population_table(df, observables=("launch_speed", "launch_angle"), source=None):
    """The rows of a tidy Statcast table (:func:`mcbat.statcast.read`) a population fit
    uses, and the counts of rows left out.

    A row is used when it has every observable and the pitch at the plate
    (:data:`REQUIRED_PITCH`) and the batter's side.

    Raises
    ------
    InputError
        A table without an observable's or a pitch column, or without a usable row.
    """
    for name in (*observables, *REQUIRED_PITCH, "handedness"):
        if name not in df.columns:
            what = ("a batted-ball observable" if name in OBSERVABLES else
                    "the measured pitch each row's template is conditioned on")
            raise InputError(name, f"missing column ({what}); a population fit reads a "
                             "Statcast export or mcbat's tidy table (mcbat statcast)", source)
    ok = np.ones(len(df), bool)
    dropped = {}
    for name in observables:
        good = np.isfinite(df[name].to_numpy(float))
        dropped[f"no_{name}"] = int(np.sum(ok & ~good))
        ok &= good
    for name in REQUIRED_PITCH:
        good = np.isfinite(df[name].to_numpy(float))
        dropped[f"no_{name}"] = int(np.sum(ok & ~good))
        ok &= good
    good = df["handedness"].isin(["R", "L"]).to_numpy()
    dropped["no_handedness"] = int(np.sum(ok & ~good))
    ok &= good
    if ok.sum() < 2:
        raise InputError(observables[0], f"no rows with {', '.join(observables)} and the "
                         "pitch at the plate (a table of batted balls is needed)", source)
    return df.loc[ok].reset_index(drop=True), dropped


def _write_pitches(table, path):
    """The table's pitches as a tidy CSV a study's ``[pitches]`` reads."""
    out = table[[c for c in (*PITCH_COLUMNS.values(), "handedness") if c in table.columns]]
    out = out.copy()
    for name in PITCH_COLUMNS.values():
        if name not in out.columns:
            out[name] = np.nan
    for k, name in enumerate(_IDENTIFIERS):
        # (identifiers only trace a draw to its pitch; a table without them gets the row)
        out[name] = table[name] if name in table.columns else np.arange(len(table)) + k
    out.to_csv(path, index=False)


# ------------------------------------------------------------------ parameters


@dataclass
class _Key:
    """A free study key: its distribution (in the reporting unit) and where it is drawn."""

    key: str
    column: str
    kind: str
    unit: str
    scale: float  # SI per reporting unit
    mean: float
    std: float
    low: float = -math.inf
    high: float = math.inf

    def logpdf(self, x, mean, std):
        """Log density (up to a constant common to every parameter value) at ``x``."""
        z = (x - mean) / std
        out = -0.5 * z * z - math.log(std)
        if self.kind == "truncnormal":
            mass = (special.ndtr((self.high - mean) / std)
                    - special.ndtr((self.low - mean) / std))
            out = out - math.log(max(mass, 1e-300))
        return out

    def spec(self, mean, std):
        """The TOML spec of this distribution with ``mean``, ``std`` (reporting unit)."""
        spec = {"dist": self.kind, "mean": mean, "std": std, "unit": self.unit}
        if self.kind == "truncnormal":
            spec.update(low=self.low, high=self.high)
        return spec


def _key_of(study, key):
    dist = study.inputs.get(key)
    section, name = key.split(".", 1)
    if dist is None or dist.kind not in _FITTABLE_FIELDS:
        what = "is not in the study" if dist is None else f"is a {dist.kind} distribution"
        raise InputError("free", f"{key} {what}: a population fit frees the mean and std "
                         f"of a normal or truncnormal key (the study's: "
                         f"{', '.join(fittable_parameters(study)) or 'none'})")
    unit = dist.unit or _SI.get(dist.quantity, u.SI_UNITS[dist.quantity])
    scale = u.factor(unit, dist.quantity)
    low, high = dist.support() if dist.kind == "truncnormal" else (-math.inf, math.inf)
    return _Key(key, KEYS[section][name][2], dist.kind, unit, scale, dist.mean / scale,
                dist.std / scale, low / scale, high / scale)


def fittable_parameters(study):
    """The names a population fit of ``study`` can free: ``<key>.mean``, ``<key>.std`` of
    its normal and truncnormal keys that are not measured pitch values, and
    :data:`PHYSICS`."""
    names = [f"{key}.{f}" for key, dist in study.inputs.items()
             if getattr(dist, "kind", None) in _FITTABLE_FIELDS and key not in PITCH_COLUMNS
             for f in _FITTABLE_FIELDS[dist.kind]]
    return names + list(PHYSICS)


def _parse_free(study, free):
    """``(keys, dist_params, physics)`` of the free parameter names, each checked."""
    if getattr(study, "kind", None) != "game":
        raise InputError("study", "a population fit needs a game study (with [pitch] and "
                         "[swing]: docs/batting.md)")
    keys, params, physics = {}, [], []
    for name in free:
        if name in PHYSICS:
            physics.append(name)
            continue
        key, _, what = name.rpartition(".")
        if key in PITCH_COLUMNS:
            raise InputError("free", f"{name}: the pitch is measured row by row, not drawn")
        if what not in ("mean", "std") or not key:
            raise InputError("free", f"unknown parameter {name!r} (the study's: "
                             f"{', '.join(fittable_parameters(study))})")
        if key not in keys:
            keys[key] = _key_of(study, key)
        params.append((name, key, what))
    if not free or len(set(free)) != len(free):
        raise InputError("free", "give each parameter once, at least one")
    for name in physics:
        section, key = PHYSICS[name]
        if f"{section}.{key}" in keys:
            raise InputError("free", f"{name} sets {section}.{key}, whose distribution's "
                             "parameters are free too: free one or the other")
    return keys, params, physics


# ------------------------------------------------------------------ templates


class _Simulator:
    """The study rewritten for the table (its pitches, proposals, physics nodes), solved
    on an engine; returns the draws' free-key columns and observables."""

    def __init__(self, study, table, draws, seed, engine, workdir):
        if engine not in ENGINES:
            raise InputError("engine", f"must be one of {', '.join(ENGINES)}, got {engine!r}")
        self.draws, self.seed, self.engine = draws, seed, engine
        self._tmp = tempfile.TemporaryDirectory(prefix="mcbat-population-")
        self.workdir = Path(workdir) if workdir is not None else Path(self._tmp.name)
        self.workdir.mkdir(parents=True, exist_ok=True)
        pitches = self.workdir / "pitches.csv"
        _write_pitches(table, pitches)
        self.base = _conditioned_definition(study, pitches)
        self.source = study.source
        self.runs = 0

    def run(self, proposal, physics, columns, observables):
        """Draws of the study with the free keys' ``proposal`` ({key: (_Key, mean, std)})
        and ``physics`` ({name: value}): ``(inputs, observed, ok)``."""
        data = copy.deepcopy(self.base)
        for key, (k, mean, std) in proposal.items():
            section, name = key.split(".", 1)
            data.setdefault(section, {})[name] = k.spec(mean, std)
        for name, value in physics.items():
            section, key = PHYSICS[name]
            if name == "e" and "e" in data.get("restitution", {}):
                key = "e"  # a study with a constant e*
            data.setdefault(section, {})[key] = float(value)
        study = Study.from_dict(data, source=self.source)
        self.runs += 1
        if self.engine == "memory":
            return _solve_memory(study, self.draws, self.seed, columns, observables)
        return self._solve_engine(study, columns, observables)

    def _solve_engine(self, study, columns, observables):
        from mcbat.dataset.load import load
        from mcbat.runner.study_run import run_study

        out = self.workdir / f"templates_{self.runs}"
        run_study(study, out, samples=self.draws, seed=self.seed, engine=self.engine,
                  progress=False, overwrite=True)
        df = load(out, columns=[*columns, *observables, "status"])
        ok = df["status"].to_numpy() == 0
        return ({c: df[c].to_numpy(float) for c in columns},
                {c: df[c].to_numpy(float) for c in observables}, ok)

    def close(self):
        """Remove the temporary files."""
        self._tmp.cleanup()


def _conditioned_definition(study, pitches):
    """The study's definition with its pitches drawn from ``pitches`` (the table's rows),
    each row's batter side, no flight and no summary."""
    data = study.definition()
    for section in ("flight", "summary", "output", "pitches"):
        data.pop(section, None)
    data.pop("handedness", None)  # each pitch meets the batter who saw it
    pitch = data.get("pitch", {})
    fallback = {}
    for key in PITCH_COLUMNS:
        name = key.split(".", 1)[1]
        if name in pitch:
            fallback[name] = pitch.pop(name)
        else:  # the game's default, for rows that lack the value
            default, quantity = KEYS["pitch"][name][1], KEYS["pitch"][name][0]
            fallback[name] = {"value": default, "unit": u.SI_UNITS[quantity]}
    data["pitch"] = pitch
    data["pitches"] = {"file": str(pitches), "fallback": fallback}
    if "restitution" not in data:  # the game preset, written out so e and e_x can be set
        r = GAME_RESTITUTION
        data["restitution"] = {"e_ref": r.e_ref, "e_slope": r.e_slope,
                               "e_speed_ref": {"value": r.e_speed_ref, "unit": "m/s"},
                               "e_x": r.e_x}
    return data


def _solve_memory(study, draws, seed, columns, observables):
    """Sample and solve the draws in this process (what an engine's chunk does)."""
    from mcbat.runner.pitches import load_pitches

    study = load_pitches(study)
    inputs = study.sample_inputs(0, draws, seed)
    batted, ok = solve_game_inputs(study, inputs)
    row = {name: i for i, name in enumerate(GAME_INPUT_FIELDS)}
    return ({c: inputs[row[c]].copy() for c in columns},
            {c: np.asarray(batted[c], float) for c in observables}, ok)


# ------------------------------------------------------------------ binning


def _edges(data, bins):
    """Interior edges of equal-count bins of ``data`` (the outer bins are open)."""
    q = np.quantile(data, np.arange(1, bins) / bins)
    return np.unique(q)


def _bin_index(values, edges):
    """Flat bin index of every point (``values``: list of arrays, one per axis)."""
    idx = np.zeros(len(values[0]), np.int64)
    for v, e in zip(values, edges):
        idx = idx * (len(e) + 1) + np.searchsorted(e, v, side="right")
    return idx


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
                "observables": list(self.observables), "engine": self.engine,
                "method": "binned likelihood, Barlow-Beeston-lite for weighted templates "
                          "(iminuit.cost.template_chi2_da), MINOS intervals",
                "warnings": self.warnings}


class _Cost:
    """The binned cost at any parameter vector (reporting units)."""

    def __init__(self, n, keys, params, physics, nodes, draws_x, logq, idx, nbins):
        self.n, self.keys, self.params, self.physics = n, keys, params, physics
        self.nodes, self.x, self.logq, self.idx, self.nbins = nodes, draws_x, logq, idx, nbins
        self.total = float(n.sum())
        self.errordef = 1.0  # a chi2-like cost: intervals where it rises by 1

    def values(self, theta):
        """``{key: (mean, std)}`` and ``{physics: value}`` of a parameter vector."""
        dists = {key: [k.mean, k.std] for key, k in self.keys.items()}
        for (_, key, what), value in zip(self.params, theta):
            dists[key][0 if what == "mean" else 1] = value
        phys = dict(zip(self.physics, theta[len(self.params):]))
        return dists, phys

    def weights(self, theta):
        """The draws' weights at ``theta``."""
        dists, _ = self.values(theta)
        logw = -self.logq.copy()
        for key, (mean, std) in dists.items():
            logw += self.keys[key].logpdf(self.x[key], mean, std)
        return np.exp(logw - np.max(logw))

    def template(self, theta):
        """Sum and variance of the weights in each bin, interpolated between nodes."""
        w = self.weights(theta)
        _, phys = self.values(theta)
        t = np.zeros(self.nbins)
        v = np.zeros(self.nbins)
        for corner, c in grid_corners(self.nodes, phys):
            idx = self.idx[corner]
            good = idx >= 0
            t += c * np.bincount(idx[good], w[good], self.nbins)
            # correlated nodes (common random numbers): sum c_g V_g bounds the variance
            v += c * np.bincount(idx[good], w[good] ** 2, self.nbins)
        return t, v

    def __call__(self, theta):
        from iminuit.cost import template_chi2_da

        t, v = self.template(np.asarray(theta, float))
        s = t.sum()
        if not s > 0:
            return 1e30
        mu = np.maximum(self.total * t / s, 1e-12)
        var = np.maximum(self.total**2 * v / s**2, 1e-24)
        return float(template_chi2_da(self.n, mu, var))


def grid_corners(nodes, phys):
    """``(node index tuple, coefficient)`` of the multilinear interpolation at ``phys``."""
    if not nodes:
        return [((), 1.0)]
    parts = []
    for name, z in nodes.items():
        x = float(np.clip(phys[name], z[0], z[-1]))
        j = int(min(np.searchsorted(z, x, side="right") - 1, len(z) - 2))
        t = (x - z[j]) / (z[j + 1] - z[j])
        parts.append(((j, 1.0 - t), (j + 1, t)))
    out = [((), 1.0)]
    for pair in parts:
        out = [(c + (j,), a * b) for c, a in out for j, b in pair if b > 0.0]
    return out


def fit_population(study, table, free, *, draws=None, bins=None,
                   observables=("launch_speed", "launch_angle"), seed=0, engine="memory",
                   workdir=None, passes=2):
    """Fit ``free`` parameters of a game ``study`` to the batted balls of ``table``.

    Parameters
    ----------
    study : GameStudy
        The game (its ``[pitches]``, if any, is replaced by the table's rows).
    table : pandas.DataFrame
        A tidy Statcast table (:func:`mcbat.statcast.read`); rows are selected by
        :func:`population_table`.
    free : sequence of str
        ``<section>.<key>.mean`` / ``.std`` of the study's normal or truncnormal keys, and
        any of ``e``, ``mu``, ``e_x`` (:func:`fittable_parameters`).
    draws : int, optional
        Template draws per row (default :data:`DEFAULT_DRAWS`).
    bins : int, optional
        Bins per observable (default: about :data:`ROWS_PER_BIN` rows per bin).
    observables : sequence of str
        Of :data:`OBSERVABLES`.
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
    keys, params, physics = _parse_free(study, tuple(free))
    source = table.attrs.get("source")
    data, dropped = population_table(table, observables, source)
    rows = len(data)
    # about ROWS_PER_BIN rows per bin, but at least 5 bins an axis (3 with three
    # observables): 100 rows in 3 x 3 bins left 3 degrees of freedom for 5 parameters
    per_axis = bins or max(5 if len(observables) < 3 else 3,
                           int((rows / ROWS_PER_BIN) ** (1.0 / len(observables))))
    edges = [_edges(data[o].to_numpy(float), per_axis) for o in observables]
    nbins = int(np.prod([len(e) + 1 for e in edges]))
    n = np.bincount(_bin_index([data[o].to_numpy(float) for o in observables], edges),
                    minlength=nbins).astype(float)
    m = (draws or DEFAULT_DRAWS) * rows
    sim = _Simulator(study, data, m, seed, engine, workdir)
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
    result_params = _parameters(mn, keys, params, physics, study_values, phys0, warnings)
    chi2 = float(mn.fval)
    dof = nbins - 1 - len(theta)
    if ess < 5 * rows:
        warnings.append(f"the template's effective size at the best fit is {ess:.0f} draws, "
                        f"under 5 per row: raise --draws")
    return PopulationResult(
        result_params, chi2, dof, float(stats.chi2.sf(chi2, dof)) if dof > 0 else math.nan,
        rows, dropped, {o: [float(x) for x in e] for o, e in zip(observables, edges)},
        m, ess, observables, engine, warnings,
        {"data": data, "cost": cost, "theta": np.array(mn.values), "edges": edges,
         "n": n, "minuit": mn})


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
        index = _bin_index([observed[o] for o in observables], edges)
        index[~ok] = -1
        idx[corner] = index
        obs[corner] = np.stack([np.where(ok, observed[o], np.nan) for o in observables])
        if x is None:  # the inputs are the same at every node (same random numbers)
            x = {key: inputs[k.column] / k.scale for key, k in keys.items()}
            logq = sum((k.logpdf(x[key], proposal[key][1], proposal[key][2])
                        for key, k in keys.items()), np.zeros(len(ok)))
    cost = _Cost(n, keys, params, physics, nodes, x, logq, idx, nbins)
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
    reached = np.zeros(len(n), bool)
    for idx in cost.idx.values():
        reached[idx[idx >= 0]] = True
    empty = (n > 0) & ~reached
    if empty.any():
        where = np.isin(_bin_index([data[o].to_numpy(float) for o in observables], edges),
                        np.flatnonzero(empty))
        ranges = ", ".join(f"{o} {data[o][where].min():.4g} to {data[o][where].max():.4g} "
                           f"{OBSERVABLES[o]}" for o in observables)
        raise InputError("data", f"{int(where.sum())} rows ({ranges}) lie where the study's "
                         "draws give no batted ball, even with its distributions widened: "
                         "the template cannot cover the data (widen the study's contact "
                         "or swing distributions, raise --draws, or check the table's "
                         "units)", source)


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


# ------------------------------------------------------------------ simulated tables


def simulate_table(study, pitches, rows, seed, values=None):
    """A table of ``rows`` batted balls of ``study`` with its distributions' parameters
    set to ``values`` (``{"swing.bat_speed.mean": 70, "e": 0.5, ...}``, reporting units:
    the study's), each ball meeting a pitch of ``pitches`` (a tidy Statcast table) drawn
    with replacement: the measured pitch columns and the observables, for injection
    tests."""
    values = dict(values or {})
    keys, params, physics = _parse_free(study, tuple(values)) if values else ({}, [], [])
    sim = _Simulator(study, pitches.reset_index(drop=True), rows, seed, "memory", None)
    try:
        proposal = {key: (k, k.mean, k.std) for key, k in keys.items()}
        for name, key, what in params:
            k, mean, std = proposal[key]
            proposal[key] = (k, values[name], std) if what == "mean" else (k, mean,
                                                                            values[name])
        phys = {p: values[p] for p in physics if p in values}
        inputs, observed, ok = sim.run(proposal, phys, ["pitch_speed"], tuple(OBSERVABLES))
        from mcbat.runner.pitches import load_pitches

        rewritten = load_pitches(Study.from_dict(sim.base, source=study.source))
        ids = rewritten.pitch_identifiers(0, rows, seed)["source_row"]
    finally:
        sim.close()
    table = pitches.reset_index(drop=True).iloc[ids].reset_index(drop=True).copy()
    for o in OBSERVABLES:
        table[o] = observed[o]
    return table.loc[ok].reset_index(drop=True)
