"""Calibrate one model parameter on one measured number, for any study.

``calibrate(study, "launch_speed", 100.0)`` finds the ``e*`` at which the mean launch
speed of the study's first ``samples`` rows is 100 mph. The rows are drawn once (the same
seed at every trial value: common random numbers), so the mean is a smooth function of the
parameter and Brent's method finds the root to ``xtol``. The paper's calibration (Cabo et
al. Sec. V: the exit speed of one drop, ``mcbat.papers.cabo2012.calibration``) is the
special case of a study with no scatter.

A mean need not be monotonic in the parameter (the Sec. V exit speed falls, then rises, as
``e*`` grows from 0): the parameter's range is scanned on a grid first; every bracket of the
target is refined, and the root nearest the study's own value of the parameter is returned,
with the others listed.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np
from scipy.optimize import brentq

from mcbat.errors import InputError
from mcbat.stats.columns import table_columns
from mcbat.stats.fit.estimate import FREE
from mcbat.stats.models.draws import GameModel
from mcbat.stats.models.simulate import solve_study

__all__ = ["CalibrationResult", "calibrate"]

GRID = 41
"""Points of the scan of the parameter's range that brackets the roots."""


@dataclass(frozen=True)
class CalibrationResult:
    """Result of ``calibrate``; ``column``'s values in its table unit (``unit``)."""

    study: str
    parameter: str
    value: float
    column: str
    unit: str
    target: float
    achieved: float
    samples: int
    seed: int
    other_roots: list = field(default_factory=list)

    def to_dict(self) -> dict:
        """The fields as a plain (JSON-serialisable) dict."""
        return asdict(self)


def calibrate(study, column, target, parameter="e", *, samples=None, seed=None, xtol=1e-10):
    """The value of ``parameter`` at which the study's mean ``column`` equals ``target``.

    Parameters
    ----------
    study : mcbat.study.Study or mcbat.study.game.GameStudy
    column : str
        An observable of the study's kind (a drop test: ``exit_speed`` m/s,
        ``scattering_angle`` deg, ``spin_out`` rad/s; a game: ``launch_speed`` mph,
        ``launch_angle``, ``spray_angle`` deg, ``spin_rate`` rpm).
    target : float
        The measured mean, in the column's unit.
    parameter : str
        ``e`` (the default), ``mu`` or ``e_x``.
    samples : int, optional
        Rows averaged (default: the study's ``samples``, at most 20,000).
    seed : int, optional
        Their seed (default: the study's).
    xtol : float
        Brent's tolerance on the parameter.

    Raises
    ------
    InputError
        Naming ``column``, ``parameter``, ``target`` or ``samples``.
    """
    game = getattr(study, "kind", None) == "game"
    columns = table_columns(game)
    observables = [c for c, (_, role) in columns.items() if role == "observable"]
    if column not in observables:
        raise InputError("column", f"{column!r} is not an observable of a "
                         f"{'game' if game else 'bat-frame'} study (one of "
                         f"{', '.join(observables)})")
    if parameter not in ("e", "mu", "e_x"):
        raise InputError("parameter", f"must be one of e, mu, e_x, got {parameter!r}")
    if isinstance(target, bool) or not isinstance(target, (int, float)) or not math.isfinite(
            target):
        raise InputError("target", f"must be a finite number, got {target!r}")
    samples = min(study.samples, 20_000) if samples is None else samples
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
        raise InputError("samples", f"must be an integer >= 1, got {samples!r}")
    seed = study.seed if seed is None else seed

    def mean(value):
        _, observed, ok = solve_study(study, samples, seed, {parameter: float(value)})
        return float(np.mean(observed[column][ok])) if ok.any() else math.nan

    lo, hi = FREE[parameter]
    if parameter == "mu":
        hi = 1.0  # beyond, every impact of a batting study sticks: mu leaves no trace
    grid = np.linspace(lo, hi, GRID)
    values = np.array([mean(v) for v in grid])
    gap = values - target
    roots = []
    for a, b, ga, gb in zip(grid[:-1], grid[1:], gap[:-1], gap[1:]):
        if ga == 0.0:
            roots.append(float(a))
        elif np.isfinite(ga) and np.isfinite(gb) and np.sign(ga) * np.sign(gb) < 0:
            roots.append(float(brentq(lambda v: mean(v) - target, a, b, xtol=xtol)))
    if gap[-1] == 0.0:
        roots.append(float(grid[-1]))
    if not roots:
        unit = columns[column][0]
        raise InputError("target", f"the mean {column} of this study stays within "
                         f"{np.nanmin(values):.6g}..{np.nanmax(values):.6g} {unit} for "
                         f"{parameter} in {lo:g}..{hi:g}; {target!r} is out of reach")
    own = _study_value(study, parameter, game)
    best = min(roots, key=lambda r: abs(r - own))
    return CalibrationResult(study=study.name, parameter=parameter, value=best, column=column,
                             unit=columns[column][0], target=float(target),
                             achieved=mean(best), samples=samples, seed=int(seed),
                             other_roots=[r for r in roots if r != best])


def _study_value(study, parameter, game):
    """The study's own (median) value of ``parameter``: the root nearest it is chosen."""
    if game:
        values = study.sample_inputs(0, 64, study.seed)[GameModel.PARAMETERS[parameter]]
    else:
        values = study.sample(0, 64, study.seed)[parameter]
    return float(np.median(values))
