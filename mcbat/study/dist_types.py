"""The distribution types of a study's numeric inputs: what each form holds (SI values),
its support for range checks, and its canonical description for the study's config.

``mcbat.study.distributions`` parses study-file values into these; the ``random``
family is drawn by ``mcbat.study.random_program``, the others by ``mcbat.study.drawing``.
"""

from __future__ import annotations

import abc
import math
from dataclasses import dataclass
from dataclasses import field as dc_field
from typing import NamedTuple

import numpy as np

from mcbat.checks import subfield
from mcbat.study import units as u

__all__ = ["Choice", "Dist", "Fixed", "Grid", "LHS", "Mixture", "Normal", "Point",
           "RandomDist", "Sobol", "TruncNormal", "Uniform"]


class Point(NamedTuple):
    """An extreme point of a support, for range checks: where it was written and its value."""

    field: str
    si: float
    raw: object



@dataclass(frozen=True, eq=False)
class Dist(abc.ABC):
    """Base class: one numeric input's distribution, values in SI.

    Attributes
    ----------
    field : str
        Dotted TOML key of the input (``"friction.mu"``).
    quantity : str
        Its physical quantity (``mcbat.study.units``).
    unit : str or None
        The unit it was written in (``None``: SI).
    """

    field: str
    quantity: str
    unit: str | None
    kind = "?"
    family = "?"
    bounded = True

    @abc.abstractmethod
    def points(self) -> list[Point]:
        """Points whose convex hull is the support (every value the input can take lies
        between the smallest and the largest)."""

    def support(self) -> tuple[float, float]:
        """``(smallest, largest)`` value, SI (``-inf``/``inf`` when unbounded)."""
        if not self.bounded:
            return -math.inf, math.inf
        values = [p.si for p in self.points()]
        return min(values), max(values)

    @abc.abstractmethod
    def config(self) -> dict:
        """Canonical JSON-ready description, SI values."""

    def describe(self, point: Point) -> str:
        """``point`` as written, with its SI value (for error messages)."""
        return u.format_value(point.si, point.raw, self.unit, self.quantity)

    def _written(self, *keys: str) -> list[Point]:
        """The points of the parameters ``keys``, at ``<field>.<key>``: their SI values
        and, from the subclass's ``raw`` (a dict by key), the values as written."""
        return [Point(subfield(self.field, key), getattr(self, key), self.raw[key])
                for key in keys]


@dataclass(frozen=True, eq=False)
class Fixed(Dist):
    """A fixed value. ``written`` is the field the number sits at (``x`` or ``x.value``)."""

    value: float = 0.0
    raw: object = None
    written: str = ""
    kind = "fixed"
    family = "fixed"

    def points(self):
        """The value itself, at the key it was written at."""
        return [Point(self.written or self.field, self.value, self.raw)]

    def config(self):
        """Canonical JSON-ready description, SI values."""
        return {"dist": "fixed", "value": self.value}


class RandomDist(Dist):
    """Drawn by the counter-based sampler (``mcbat.study.random_program``)."""

    family = "random"


@dataclass(frozen=True, eq=False)
class Uniform(RandomDist):
    """Uniform on ``[low, high]`` (SI)."""

    low: float = 0.0
    high: float = 1.0
    raw: dict = dc_field(default_factory=dict)
    kind = "uniform"

    def points(self):
        """``low`` and ``high``, at the keys they were written at."""
        return self._written("low", "high")

    def config(self):
        """Canonical JSON-ready description, SI values."""
        return {"dist": "uniform", "low": self.low, "high": self.high}


@dataclass(frozen=True, eq=False)
class Normal(RandomDist):
    """Normal with ``mean`` and standard deviation ``std`` (SI); unbounded."""

    mean: float = 0.0
    std: float = 1.0
    raw: dict = dc_field(default_factory=dict)
    kind = "normal"
    bounded = False

    def points(self):
        """The mean, at ``<field>.mean`` (the support is unbounded: ``bounded`` is False)."""
        return self._written("mean")

    def config(self):
        """Canonical JSON-ready description, SI values."""
        return {"dist": "normal", "mean": self.mean, "std": self.std}


@dataclass(frozen=True, eq=False)
class TruncNormal(RandomDist):
    """Normal(mean, std) restricted to [low, high], drawn by the inverse CDF of one
    uniform per value (the interval is reflected into the lower tail when it lies above
    the mean, where the CDF keeps its relative precision)."""

    mean: float = 0.0
    std: float = 1.0
    low: float = -1.0
    high: float = 1.0
    raw: dict = dc_field(default_factory=dict)
    kind = "truncnormal"

    def __post_init__(self):
        a = (self.low - self.mean) / self.std
        b = (self.high - self.mean) / self.std
        flip = a > 0.0
        if flip:
            a, b = -b, -a
        object.__setattr__(self, "_flip", flip)
        object.__setattr__(self, "_pa", _normal_cdf(a))
        object.__setattr__(self, "_pb", _normal_cdf(b))

    def points(self):
        """``low`` and ``high``, at the keys they were written at."""
        return self._written("low", "high")

    def config(self):
        """Canonical JSON-ready description, SI values."""
        return {"dist": "truncnormal", "mean": self.mean, "std": self.std,
                "low": self.low, "high": self.high}


_SQRT_HALF = math.sqrt(0.5)


def _normal_cdf(x: float) -> float:
    """The standard normal CDF, cephes' ndtr (scipy's) formula: ``1/2 + erf(x/sqrt 2)/2``
    near 0, else from ``erfc``, which keeps the lower tail's relative precision."""
    z = x * _SQRT_HALF
    if abs(z) < _SQRT_HALF:
        return 0.5 + 0.5 * math.erf(z)
    y = 0.5 * math.erfc(abs(z))
    return 1.0 - y if z > 0.0 else y


def _selector(weights):
    """``(cumulative weights, last index with a positive weight)``."""
    w = np.asarray(weights, dtype=np.float64)
    with np.errstate(over="ignore"):
        finite = np.isfinite(w.sum())
    if not finite:  # huge weights: only their ratios matter
        w = w / w.max()
    return np.cumsum(w), int(np.flatnonzero(w > 0.0)[-1])


@dataclass(frozen=True, eq=False)
class Choice(RandomDist):
    """One of ``values`` (SI), with probabilities proportional to ``weights``."""

    values: tuple = ()
    weights: tuple = ()
    raw: dict = dc_field(default_factory=dict)
    kind = "choice"

    def __post_init__(self):
        cum, last = _selector(self.weights)
        object.__setattr__(self, "_cum", cum)
        object.__setattr__(self, "_last", last)
        object.__setattr__(self, "_values", np.asarray(self.values, dtype=np.float64))

    def points(self):
        """Every value, at ``<field>.values[i]``."""
        return [Point(f"{subfield(self.field, 'values')}[{i}]", v, self.raw["values"][i])
                for i, v in enumerate(self.values)]

    def config(self):
        """Canonical JSON-ready description, SI values."""
        return {"dist": "choice", "values": list(self.values), "weights": list(self.weights)}


@dataclass(frozen=True, eq=False)
class Mixture(RandomDist):
    """Component ``j`` with probability ``weights[j]``: one uniform picks the component,
    then every component draws ``n`` values (so the stream used is fixed)."""

    components: tuple = ()
    weights: tuple = ()
    kind = "mixture"

    def __post_init__(self):
        cum, last = _selector(self.weights)
        object.__setattr__(self, "_cum", cum)
        object.__setattr__(self, "_last", last)
        object.__setattr__(self, "bounded", all(c.bounded for c in self.components))

    def points(self):
        """The points of every component, in order."""
        return [p for c in self.components for p in c.points()]

    def describe(self, point):
        """``point`` as written, with its SI value (for error messages)."""
        for c in self.components:
            if any(p.field == point.field for p in c.points()):
                return c.describe(point)
        return super().describe(point)

    def config(self):
        """Canonical JSON-ready description, SI values."""
        return {"dist": "mixture", "components": [c.config() for c in self.components],
                "weights": list(self.weights)}


@dataclass(frozen=True, eq=False)
class Grid(Dist):
    """``num`` evenly spaced values from ``start`` to ``stop`` (both included)."""

    start: float = 0.0
    stop: float = 1.0
    num: int = 1
    raw: dict = dc_field(default_factory=dict)
    kind = "grid"
    family = "grid"

    def points(self):
        """``start``, and ``stop`` when ``num > 1``, at the keys they were written at."""
        return self._written("start", "stop") if self.num > 1 else self._written("start")

    def values(self):
        """The grid points, SI."""
        return np.linspace(self.start, self.stop, self.num)

    def config(self):
        """Canonical JSON-ready description, SI values."""
        return {"dist": "grid", "start": self.start, "stop": self.stop, "num": self.num}


@dataclass(frozen=True, eq=False)
class _UnitCube(Dist):
    """Uniform on [low, high] through a point of a shared quasi-random design."""

    low: float = 0.0
    high: float = 1.0
    raw: dict = dc_field(default_factory=dict)

    def points(self):
        """``low`` and ``high``, at the keys they were written at."""
        return self._written("low", "high")

    def config(self):
        """Canonical JSON-ready description, SI values."""
        return {"dist": self.kind, "low": self.low, "high": self.high}

    def from_unit(self, unit_values):
        """Map design coordinates in [0, 1) to [low, high)."""
        return self.low + (self.high - self.low) * unit_values


class Sobol(_UnitCube):
    """Quasi-random Sobol points on ``[low, high]`` (``scipy.stats.qmc``), one dimension
    of the study's joint Sobol sequence."""

    kind = "sobol"
    family = "sobol"


class LHS(_UnitCube):
    """Latin hypercube samples on ``[low, high]`` (``scipy.stats.qmc``), one dimension of
    the study's joint design."""

    kind = "lhs"
    family = "lhs"

