"""What a fit solves: the model's draws for every row of a measurement table.

A fit compares each measured row with ``M`` draws of the model for that row. A *draw
model* builds those ``rows x M`` cases once (the study's nuisance scatter, the row's
measured inputs, their errors) and solves them at any value of the free parameters, so that
``mcbat.stats.fit.likelihood.Likelihood`` never needs to know which kernel it is fitting:

* ``BatFrameModel``: a ball moving across a bat onto its axis, in the bat frame (a
  drop test: ``studies/cross_nathan_2006.toml``); the table gives each row's impact
  parameter (and incoming spin), the observables are ``exit_speed`` (m/s),
  ``scattering_angle`` (deg) and ``spin_out`` (rad/s, about the bat axis).
* ``GameModel``: a game study (a pitch and a swing in the field frame); the table
  gives what a tracking system reports, in Statcast's names and units: ``launch_speed``
  (mph), ``launch_angle`` and ``spray_angle`` (deg), ``spin_rate``, ``backspin`` and
  ``sidespin`` (rpm); optionally each row's measured swing and pitch (``bat_speed`` and
  ``pitch_speed`` in mph, ``attack_angle`` in deg, ``undercut`` and ``from_barrel_end``
  in m). Inputs the table does not give are drawn from the study.

Measured inputs with an ``_err`` column are drawn from their posterior given the
measurement: the prior of the true values times a normal of that width about the measured
value, over a bounded range. The draws come from the posterior under a flat prior over that
range; the mixture likelihood of ``mcbat.stats.fit.likelihood`` reweights them to a prior it
estimates with the parameters (``mcbat.stats.models.input_priors.PriorFamily``), so that a
table whose true values pile up somewhere (at the ends of the range, say) is not fitted as
if they were spread evenly. The draws are *stratified*: draw ``k`` of a row lies in the
``k``-th of ``M`` equal-probability slices of that posterior for the first such input (the
slices of any further one are shuffled, as in a Latin hypercube). The order matters:
``mcbat.stats.fit.likelihood.draw_moments`` pairs neighbouring slices to measure the Monte
Carlo error of the mean.

The range and the prior of a measured input's true values are
``mcbat.stats.models.input_priors``'s; every fit reports the range it used
(``_DrawModel.priors``).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import stats

from mcbat.core.geometry import angles_from_impact_parameters, ball_centre_radial_distance
from mcbat.core.status import OK
from mcbat.core.units import M_S_PER_MPH, RAD_PER_DEG
from mcbat.errors import InputError
from mcbat.solving import (
    GAME_INPUT_FIELDS,
    GAME_OUTPUT_FIELDS,
    INPUT_FIELDS,
    OUTPUT_FIELDS,
    allocate_games,
    allocate_impacts,
    solve_games,
    solve_impacts,
)
from mcbat.solving.derived import derive, derive_game
from mcbat.stats.columns import BAT_FRAME_COLUMNS, GAME_TABLE_COLUMNS
from mcbat.stats.models.input_priors import (
    WIDEN_P_VALUE,
    covering_range,
    prior_range,
)

__all__ = ["BatFrameModel", "DrawModel", "GameModel", "OUTLIER_SIGMA", "rows_text"]

OUTLIER_SIGMA = 8.0
"""A measured value further than this many sigma beyond every model prediction over the
search ranges is refused (a typo or a wrong unit), not fitted; likewise a measured input
this many of its errors outside the study's range."""
GRAZING = 0.999
"""A measured ``|b|`` at or above this fraction of the reach ``R + r`` (a contact angle
above 87.4 deg) is refused: the ball grazes the bat."""


PILOT_POINTS = 61
"""Values of a measured impact parameter a row's pilot scan solves (``BatFrameModel.
refine_draws``), evenly over +-``PILOT_SIGMA`` of its errors."""
PILOT_SIGMA = 6.0


def rows_text(mask, values=None, limit=5):
    """``"rows 3, 7 (value ...)"``: the 1-based rows where ``mask`` holds."""
    idx = np.flatnonzero(mask)
    shown = ", ".join(str(i + 1) + (f" ({values[i]:.6g})" if values is not None else "")
                      for i in idx[:limit])
    more = f" and {len(idx) - limit} more" if len(idx) > limit else ""
    return f"row{'s' if len(idx) > 1 else ''} {shown}{more}"


class _DrawModel:
    """Shared bookkeeping: the table's columns checked against the model's, the measured
    inputs drawn, the free parameters written into the input array."""

    COLUMNS: dict = {}
    PARAMETERS: dict = {}
    """Fit parameter -> row of the input array it sets."""
    KIND = ""
    FAILURE_HINTS: dict = {}
    DEFAULT_DRAWS = 48
    """Draws per row unless the user asks for another number."""
    LIKELIHOOD = "gaussian"
    """The form of a row's likelihood unless the user asks for another
    (``mcbat.stats.fit.estimate``): a normal of the draws' mean and covariance."""
    SEARCH: dict = {}
    """Search ranges of the fit's coarse grid that differ from the default
    (``mcbat.stats.fit.likelihood.SEARCH``)."""

    def __init__(self, study, table, draws, seed, fixed, input_prior="cover"):
        self.source = table.attrs.get("source")
        self.study = study
        self.rows = len(table)
        self.draws = draws
        self.input_prior = input_prior
        self.priors = {}
        """Measured input -> the range its draws cover: ``study_range`` and ``range``
        (table units), ``widened`` (the two differ), and whether the measured values reject
        the study's range (``rejects_study_range``, with the ``p_value`` of
        ``mcbat.stats.models.input_priors.beyond_range_test``)."""
        self.prior_draws = {}
        """Measured input over a bounded range -> ``(draws (rows x M), lo, hi)`` in table
        units: its draws, taken from the posterior under a flat prior over ``[lo, hi]``,
        which a likelihood may reweight to another prior (``mcbat.stats.fit.estimate``)."""
        self._stratified = False
        self.smeared = {}
        """Measured input over a bounded range -> ``(value, sigma, lo, hi, scale)`` (SI)."""
        self.draw_log_weight = None
        """Importance weights (log, rows x M) of the draws, once ``refine_draws`` has
        drawn some of them near each row's posterior; None: every draw weighs the same."""
        self.plain_draws = draws
        """The first ``plain_draws`` draws of a row come from the posterior of its measured
        inputs given their measurement alone (its mean and covariance estimate the row's
        predictions); after ``refine_draws``, the rest lie near the posterior given the
        observables too."""
        known = {c for c in self.COLUMNS} | {f"{c}_err" for c in self.COLUMNS}
        for col in table.columns:
            if col not in known:
                base = col[:-4] if col.endswith("_err") else col
                what = "an uncertainty of " if col.endswith("_err") else ""
                raise InputError(col, f"a {self.KIND} study's model cannot use {what}"
                                 f"{base!r} (its columns: {', '.join(self.COLUMNS)}, each "
                                 f"optionally with an _err column)", self.source)
        self.observables = [c for c, (_, role) in self.COLUMNS.items()
                            if role == "observable" and c in table.columns]
        if not self.observables:
            names = [c for c, (_, role) in self.COLUMNS.items() if role == "observable"]
            raise InputError(None, f"the table has none of the observables of a "
                             f"{self.KIND} study: {', '.join(names)}", self.source)
        for name in fixed or {}:
            if name not in self.PARAMETERS:
                raise InputError("fixed", f"unknown parameter {name!r} for a {self.KIND} "
                                 f"study (choose from {', '.join(self.PARAMETERS)})")
        self.rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(2**31 + 13,)))

    def measured_draws(self, name, table, support, scale=1.0, physical=(-math.inf, math.inf),
                       key=None):
        """Per-draw values (SI: the table's value times ``scale``) of measured input
        ``name``: its value repeated, or smeared by its ``_err`` (module docstring) over
        the range of ``prior``; ``physical`` is the input's physical range and ``key``
        the study's name of the input (for messages)."""
        value = table[name].to_numpy(float) * scale
        if f"{name}_err" not in table.columns:
            return np.repeat(value, self.draws)
        sigma = table[f"{name}_err"].to_numpy(float) * scale
        lo, hi = self.prior(name, value, sigma, support, physical, scale, key)
        slices = np.tile(np.arange(self.draws), (self.rows, 1))
        if self._stratified:  # a further smeared input: its slices shuffled per row
            slices = self.rng.permuted(slices, axis=1)
        self._stratified = True
        u = (slices + self.rng.uniform(size=slices.shape)) / self.draws
        a = ((lo - value) / sigma)[:, None]
        b = ((hi - value) / sigma)[:, None]
        far = (a > OUTLIER_SIGMA).ravel() | (b < -OUTLIER_SIGMA).ravel()
        if far.any():
            where = "the study's" if not self.priors[name]["widened"] else "the widened"
            raise InputError(name, f"{rows_text(far, value / scale)}: more than "
                             f"{OUTLIER_SIGMA:g} of its errors outside {where} range "
                             f"{lo / scale:g}..{hi / scale:g} (the physical range ends there: "
                             f"a typo or another unit?)", self.source)
        if math.isinf(lo) and math.isinf(hi):
            z = stats.norm.ppf(u)
        else:
            z = stats.truncnorm.ppf(u, a, b)
        draws = value[:, None] + sigma[:, None] * z
        if math.isfinite(lo) and math.isfinite(hi):
            self.prior_draws[name] = (draws / scale, lo / scale, hi / scale)
            self.smeared[name] = (value, sigma, lo, hi, scale)
        return draws.ravel()

    def prior(self, name, value, sigma, support, physical, scale, key):
        """The flat prior's range (SI) of measured input ``name`` (module docstring),
        recorded in ``priors``; ``InputError`` when the data reject the study's
        range and ``input_prior`` is ``"study"``."""
        (lo, hi), p_value = prior_range(value, sigma, support, physical)
        rejected = p_value < WIDEN_P_VALUE
        if rejected and self.input_prior == "study":
            beyond = (value < support[0] - 2 * sigma) | (value > support[1] + 2 * sigma)
            rows = (f"{rows_text(beyond, value / scale)} lie more than 2 of their errors "
                    if beyond.any() else "the measured values lie ")
            raise InputError(name, f"{rows}outside the study's range {support[0] / scale:g}.."
                             f"{support[1] / scale:g}, which the data reject (p = "
                             f"{p_value:.2g} < {WIDEN_P_VALUE:g} if every true value lay "
                             f"within it): widen {key or name} in the study, or let the fit "
                             f"marginalise beyond it (--input-prior cover)", self.source)
        if self.input_prior == "cover":
            lo, hi = covering_range(value, sigma, support, physical)
        elif not rejected:
            lo, hi = support
        self.priors[name] = {"study_range": [support[0] / scale, support[1] / scale],
                             "range": [lo / scale, hi / scale],
                             "widened": bool(lo < support[0] or hi > support[1]),
                             "rejects_study_range": bool(rejected), "p_value": p_value}
        return lo, hi

    def support(self, key):
        """The study's range of input ``key`` (unbounded when it is not drawn)."""
        dist = self.study.inputs.get(key)
        if dist is None or getattr(dist, "family", None) == "fixed":
            return -math.inf, math.inf
        return dist.support()

    def record_study_values(self):
        """Keep the study's own value of every parameter (the mean over the draws) in
        ``study_values``, before a fit changes them."""
        self.study_values = {name: float(np.mean(self.inputs[row]))
                             for name, row in self.PARAMETERS.items()}

    def set_parameters(self, values):
        """Write ``{parameter: value}`` into every draw."""
        for name, value in values.items():
            self.inputs[self.PARAMETERS[name]] = value


DrawModel = _DrawModel
"""The base of a draw model, for models defined outside this module
(``mcbat.stats.models.flight.FlightModel``)."""


class BatFrameModel(_DrawModel):
    """The bat-frame kernel (``mcbat.solving.solve_impacts``) on a drop-test table.

    The study must place the contact by ``contact.impact_parameter``; each row's measured
    impact parameter sets the contact angle of its draws (about the study's approach
    azimuth of each draw), a measured ``spin_in`` the incoming spin about the bat axis.
    """

    COLUMNS = BAT_FRAME_COLUMNS
    KIND = "bat-frame"
    LIKELIHOOD = "mixture"  # the draws vary mainly in the stratified measured inputs
    PARAMETERS = {name: INPUT_FIELDS.index(name)
                  for name in ("e", "mu", "ball_inertia_factor", "axial", "e_x")}
    FAILURE_HINTS = {"not_approaching": ("impact_parameter", " (the ball does not approach "
                                         "the bat at the contact: an impact parameter at the "
                                         "reach of ball and bat?)")}

    def __init__(self, study, table, draws, seed, fixed=None, input_prior="cover"):
        super().__init__(study, table, draws, seed, fixed, input_prior)
        source, rows = self.source, self.rows
        if "contact.impact_parameter" not in study.inputs:
            raise InputError("impact_parameter", f"study {study.name!r} places the contact by "
                             f"contact.angle, not contact.impact_parameter: a measured impact "
                             f"parameter needs a study of a ball moving across the bat onto "
                             f"its axis (as studies/cross_nathan_2006.toml)", source)
        if "impact_parameter" not in table.columns:
            raise InputError("impact_parameter", "missing required column", source)
        index = {name: i for i, name in enumerate(INPUT_FIELDS)}
        cols = study.sample(0, rows * draws, seed)
        inputs = np.stack([np.asarray(cols[n], np.float64) for n in INPUT_FIELDS])
        b_meas = table["impact_parameter"].to_numpy(float)
        n = rows * draws
        ball_r = inputs[index["ball_radius"]]
        radius, slope = inputs[index["bat_radius"]], inputs[index["bat_slope"]]
        reach = np.array([ball_centre_radial_distance(*v) for v in zip(ball_r, radius, slope)])
        edge = GRAZING * reach.min()
        b = self.measured_draws("impact_parameter", table,
                                study.inputs["contact.impact_parameter"].support(),
                                physical=(-edge, edge), key="contact.impact_parameter")
        # The study's approach azimuth of each draw, then the contact angle of the row's b.
        angle0 = np.empty(n)
        angles_from_impact_parameters(np.asarray(cols["impact_parameter"], float), ball_r,
                                      radius, slope, np.zeros(n), angle0)
        azimuth = inputs[index["angle"]] - angle0
        angles_from_impact_parameters(b, ball_r, radius, slope, azimuth,
                                      inputs[index["angle"]])
        self._geometry = (ball_r, radius, slope, azimuth)
        grazing = (np.abs(b_meas) >= GRAZING * reach.reshape(rows, draws).min(axis=1))
        if grazing.any():
            raise InputError("impact_parameter", f"{rows_text(grazing, b_meas)}: at the reach "
                             f"of ball and bat ({reach.min():.5g} m): a grazing contact, not a "
                             f"measurable impact", source)
        missed = np.isnan(inputs[index["angle"]]).reshape(rows, draws).all(axis=1)
        if missed.any():
            raise InputError("impact_parameter", f"{rows_text(missed, b_meas)}: beyond the "
                             f"reach of ball and bat (the ball would miss)", source)
        if "spin_in" in table.columns:
            inputs[index["ball_wz_in"]] = self.measured_draws("spin_in", table,
                                                              (-math.inf, math.inf))
        self.inputs = inputs
        self.record_study_values()
        self.set_parameters(fixed or {})  # e.g. e_x = 0: the rigid model
        self._axial = inputs[index["axial"]].copy()
        self._out = allocate_impacts(n)

    def set_parameters(self, values):
        """As the base class; ``axial`` shifts the study's impact points (keeping their
        scatter) instead of replacing them."""
        for name, value in values.items():
            if name == "axial":
                self.inputs[self.PARAMETERS[name]] = self._axial + value
            else:
                self.inputs[self.PARAMETERS[name]] = value

    def refine_draws(self, y, s2, observables):
        """Move half of each row's draws of the measured impact parameter next to its
        posterior given the observables, at the current parameters; returns whether it did.

        The draws from the posterior given the measured ``b`` alone (stratified, 5 mm wide
        in a drop test) resolve badly what the observables say: the scattering angle alone
        fixes ``b`` to about a millimetre, so a row measured three errors from its true
        ``b`` had one draw or none near it, and the likelihood of ``mu`` moved by up to four
        of its errors between 48 and 384 draws. Here a pilot scan of ``b`` (61 values over
        +-6 errors, the row's first draw otherwise) finds the posterior's mean and spread;
        the second half of the draws is stratified over a truncated normal there, twice as
        wide, and every draw is weighted by the ratio of the measurement's posterior to the
        two halves' mixture (defensive importance sampling: Hesterberg, Technometrics 37,
        185 (1995)), so the likelihood stays the same integral, better resolved.

        Parameters
        ----------
        y, s2 : ndarray, (rows, observables)
            The measured observables and their variances.
        observables : list of str
            Their names (``observables``).
        """
        if "impact_parameter" not in self.smeared or self.draws < 4:
            return False
        value, sigma, lo, hi, _ = self.smeared["impact_parameter"]
        rows, draws, points = self.rows, self.draws, PILOT_POINTS
        index = {name: i for i, name in enumerate(INPUT_FIELDS)}
        first = np.arange(rows) * draws
        z = np.linspace(-PILOT_SIGMA, PILOT_SIGMA, points)
        b_grid = np.clip(value[:, None] + sigma[:, None] * z, lo, hi)
        pilot = np.repeat(self.inputs[:, first], points, axis=1)
        ball_r, radius, slope, azimuth = (np.repeat(g[first], points) for g in self._geometry)
        angles_from_impact_parameters(b_grid.ravel(), ball_r, radius, slope, azimuth,
                                      pilot[index["angle"]])
        values, status = self._solve(pilot, allocate_impacts(rows * points))
        f = np.stack([values[c].reshape(rows, points) for c in observables], axis=2)
        log_post = (-0.5 * ((y[:, None, :] - f) ** 2 / s2[:, None, :]).sum(axis=2)
                    - 0.5 * ((b_grid - value[:, None]) / sigma[:, None]) ** 2)
        log_post = np.where((status == OK).reshape(rows, points) & np.isfinite(log_post),
                            log_post, -np.inf)
        if not np.isfinite(log_post).any(axis=1).all():
            return False
        p = np.exp(log_post - log_post.max(axis=1, keepdims=True))
        p /= p.sum(axis=1, keepdims=True)
        centre = (p * b_grid).sum(axis=1)
        spread = np.sqrt((p * (b_grid - centre[:, None]) ** 2).sum(axis=1))
        width = np.maximum(2.0 * spread, 2.0 * PILOT_SIGMA / (points - 1) * sigma)
        plain = draws // 2
        strata = [np.arange(plain), np.arange(draws - plain)]
        u = [(k + self.rng.uniform(size=(rows, len(k)))) / len(k) for k in strata]
        posterior = stats.truncnorm(((lo - value) / sigma)[:, None],
                                    ((hi - value) / sigma)[:, None],
                                    loc=value[:, None], scale=sigma[:, None])
        near = stats.truncnorm(((lo - centre) / width)[:, None], ((hi - centre) / width)[:, None],
                               loc=centre[:, None], scale=width[:, None])
        b = np.concatenate([posterior.ppf(u[0]), near.ppf(u[1])], axis=1)
        share = plain / draws
        log_q = np.logaddexp(math.log(share) + posterior.logpdf(b),
                             math.log(1.0 - share) + near.logpdf(b))
        self.draw_log_weight = posterior.logpdf(b) - log_q
        self.plain_draws = plain
        angles_from_impact_parameters(b.ravel(), *self._geometry, self.inputs[index["angle"]])
        scale = self.smeared["impact_parameter"][4]
        self.prior_draws["impact_parameter"] = (b / scale, lo / scale, hi / scale)
        return True

    def solve(self):
        """Solve every draw: ``{observable: float64[rows * draws]}`` and the status."""
        return self._solve(self.inputs, self._out)

    def _solve(self, inputs, buffers):
        out, status, _ = solve_impacts(inputs, self.study.solver_settings, into=buffers)
        o = {name: out[i] for i, name in enumerate(OUTPUT_FIELDS)}
        derived = derive([o[f"ball_v{c}"] for c in "xyz"], [o[f"ball_w{c}"] for c in "xyz"])
        values = {"exit_speed": derived["exit_speed"],
                  "scattering_angle": derived["scattering_angle"],
                  "spin_out": derived["spin_axial"]}
        return {c: values[c] for c in self.observables}, status


class GameModel(_DrawModel):
    """The game kernel (``mcbat.solving.solve_games``) on a tracking table.

    Each row's measured pitch and swing (any of ``pitch_speed``, ``bat_speed``,
    ``attack_angle``, ``undercut``, ``from_barrel_end``) replace the study's draws of
    them; the rest of the study's scatter is nuisance. Parameters: ``e`` (the game
    restitution's ``e*`` at its reference speed, ``e_ref``), ``mu`` and ``e_x``.
    """

    COLUMNS = GAME_TABLE_COLUMNS
    KIND = "game"
    PARAMETERS = {"e": GAME_INPUT_FIELDS.index("e_ref"), "mu": GAME_INPUT_FIELDS.index("mu"),
                  "e_x": GAME_INPUT_FIELDS.index("e_x")}
    MEASURED = {"pitch_speed": ("pitch.speed", M_S_PER_MPH),
                "bat_speed": ("swing.bat_speed", M_S_PER_MPH),
                "attack_angle": ("swing.attack_angle", RAD_PER_DEG),
                "undercut": ("contact.undercut", 1.0),
                "from_barrel_end": ("contact.from_barrel_end", 1.0)}
    DEFAULT_DRAWS = 128
    """A game's nuisance scatter (impact point, bat angles, ...) is drawn independently,
    so the covariance of a row's 4 observables is estimated from its draws with noise, and
    the inverse of a noisy covariance is too large on average (by ``~(d + 1)/M``): with 48
    draws chi2/dof came out 1.11 on a 1000-row table, 1.03 with 192, so the likelihood was
    ~10 % too sharp. 128 draws leave ~4 %. (A drop test's spread is dominated by its
    stratified impact parameter or by the measurement errors: chi2/dof 0.98-1.01 at 48.)"""
    SEARCH = {"e": (0.2, 0.8)}
    """A baseball's e* at game speeds lies well within 0.2-0.8 (the game preset: 0.555 at
    85 ft/s, docs/batting.md): the coarse grid covers that range, so launch speeds in another
    unit (which would need e* near 0.07 for m/s or 0.96 for km/h) are refused with a hint
    instead of fitted."""
    FAILURE_HINTS = {"not_approaching": ("undercut", " (the ball misses or does not meet the "
                                         "bat: an undercut beyond the reach of ball and "
                                         "barrel?)")}

    def __init__(self, study, table, draws, seed, fixed=None, input_prior="cover"):
        super().__init__(study, table, draws, seed, fixed, input_prior)
        inputs = study.sample_inputs(0, self.rows * draws, seed)
        cols = {name: inputs[i] for i, name in enumerate(GAME_INPUT_FIELDS)}
        reach = float(np.max(cols["ball_radius"] + cols["bat_radius"]))
        physical = {"pitch_speed": (0.0, math.inf), "bat_speed": (0.0, math.inf),
                    "attack_angle": (-0.5 * math.pi, 0.5 * math.pi),
                    "undercut": (-reach, reach),
                    "from_barrel_end": (0.0, float(np.min(cols["bat_length"])))}
        for name, (key, scale) in self.MEASURED.items():
            if name in table.columns:
                cols[name][:] = self.measured_draws(name, table, self.support(key), scale,
                                                    physical[name], key)
        if "from_barrel_end" in table.columns:
            study.fill_contact(cols)
        self.inputs = inputs
        self.record_study_values()
        self.set_parameters(fixed or {})
        self._out = allocate_games(self.rows * draws)

    def solve(self):
        """Solve every draw: ``{observable: float64[rows * draws]}`` (table units) and the
        status."""
        _, _, game_out, status, _ = solve_games(self.inputs, self.study.solver_settings,
                                                into=self._out)
        g = {name: game_out[i] for i, name in enumerate(GAME_OUTPUT_FIELDS)}
        batted = derive_game([g[f"field_ball_v{c}"] for c in "xyz"],
                             [g[f"field_ball_w{c}"] for c in "xyz"])
        return {c: batted[c] for c in self.observables}, status
