"""Distributions of the numeric inputs of a study: parse, validate, sample.

Any numeric input of a study file is one of

==============  ==========================================================  ===========
form            TOML                                                        family
==============  ==========================================================  ===========
fixed           ``x = 1.5`` or ``x = { value = 1.5, unit = "cm" }``           fixed
uniform         ``{ dist = "uniform", low = a, high = b }``                  random
normal          ``{ dist = "normal", mean = m, std = s }``                   random
truncnormal     ``{ dist = "truncnormal", mean, std, low, high }``           random
choice          ``{ dist = "choice", values = [..], weights = [..] }``       random
mixture         ``{ dist = "mixture", components = [..], weights = [..] }``  random
grid            ``{ dist = "grid", start = a, stop = b, num = n }``          grid
sobol           ``{ dist = "sobol", low = a, high = b }``                    sobol
lhs             ``{ dist = "lhs", low = a, high = b }``                      lhs
==============  ==========================================================  ===========

Every form accepts an optional ``unit`` (see :mod:`mcbat.study.units`); values are stored
in SI. ``weights`` are optional (default: equal), non-negative, and need not sum to 1.
A mixture's ``components`` are fixed, uniform, normal, truncnormal or choice specs (plain
numbers allowed); a component without its own ``unit`` takes the mixture's.

This module only knows single inputs. How the families are drawn so that sample ``i``
depends on ``(study, seed, i)`` alone is in :mod:`mcbat.study.spec`; the ``random`` family
draws a fixed count of values per call (:meth:`RandomDist.draw`), so the stream consumed
by one input never depends on the values drawn.
"""

from __future__ import annotations

import abc
import math
from dataclasses import dataclass
from dataclasses import field as dc_field
from typing import NamedTuple

import numpy as np

from mcbat.errors import InputError
from mcbat.study import units as u

__all__ = ["Choice", "DIST_KINDS", "Dist", "Fixed", "Grid", "LHS", "MIXTURE_COMPONENT_KINDS",
           "Mixture", "Normal", "Point", "RandomDist", "Sobol", "TruncNormal", "Uniform",
           "check_keys", "check_range", "integer", "number", "parse"]

#: The distribution names of ``dist = ...``.
DIST_KINDS = ("uniform", "normal", "truncnormal", "choice", "mixture", "grid", "sobol", "lhs")

#: Kinds a mixture component may be.
MIXTURE_COMPONENT_KINDS = ("fixed", "uniform", "normal", "truncnormal", "choice")

# Required and optional keys of each kind (besides "dist" and "unit").
_KEYS = {
    "uniform": (("low", "high"), ()),
    "normal": (("mean", "std"), ()),
    "truncnormal": (("mean", "std", "low", "high"), ()),
    "choice": (("values",), ("weights",)),
    "mixture": (("components",), ("weights",)),
    "grid": (("start", "stop", "num"), ()),
    "sobol": (("low", "high"), ()),
    "lhs": (("low", "high"), ()),
}

# A truncated normal whose interval lies further than this many standard deviations from
# the mean in one tail is refused: its probability underflows.
_MAX_TAIL_SIGMAS = 35.0


class Point(NamedTuple):
    """An extreme point of a support, for range checks: where it was written and its value."""

    field: str
    si: float
    raw: object


# ---------------------------------------------------------------- small validators


def _sub(field, key):
    return f"{field}.{key}" if field else key


def _type_name(value):
    return {dict: "table", list: "array", str: "string", bool: "boolean"}.get(
        type(value), type(value).__name__)


def number(value, field):
    """A finite float from a TOML number, or :class:`InputError` on ``field``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(field, f"must be a number, got {_type_name(value)} {_short(value)}")
    try:
        value = float(value)
    except OverflowError:  # an integer beyond the largest float
        raise InputError(field, f"must be finite, got {_short(value)}") from None
    if not math.isfinite(value):
        raise InputError(field, f"must be finite, got {value!r}")
    return value


def integer(value, field, minimum=None, maximum=2**63 - 1):
    """A TOML integer (not a float, not a boolean) ``>= minimum`` and ``<= maximum``
    (default: what a 64-bit integer holds)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(field, f"must be an integer, got {_type_name(value)} "
                         f"{_short(value)}")
    if minimum is not None and value < minimum:
        raise InputError(field, f"must be >= {minimum}, got {_short(value)}")
    if maximum is not None and value > maximum:
        raise InputError(field, f"must be <= {maximum:,}, got {_short(value)}")
    return int(value)


def _short(value) -> str:
    """``repr(value)``, shortened to ~60 characters (a 400-digit integer is one line)."""
    text = repr(value) if not isinstance(value, int) or value.bit_length() < 200 \
        else f"an integer of about {int(value.bit_length() * 0.30103) + 1} digits"
    return text if len(text) <= 60 else text[:57] + "..."


def check_keys(table, field, required=(), optional=()):
    """``table`` must be a dict with every ``required`` key and nothing else but ``optional``."""
    if not isinstance(table, dict):
        raise InputError(field, f"must be a table, got {_type_name(table)} {table!r}")
    allowed = tuple(required) + tuple(optional)
    for key in table:
        if key not in allowed:
            raise InputError(_sub(field, key),
                             f"unknown key (expected one of: {', '.join(allowed)})")
    for key in required:
        if key not in table:
            raise InputError(_sub(field, key), "missing required key")
    return table


# ---------------------------------------------------------------- the distributions


@dataclass(frozen=True, eq=False)
class Dist(abc.ABC):
    """Base class: one numeric input's distribution, values in SI.

    Attributes
    ----------
    field : str
        Dotted TOML key of the input (``"friction.mu"``).
    quantity : str
        Its physical quantity (:mod:`mcbat.study.units`).
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
    """Drawn by the counter-based sampler (:mod:`mcbat.study.random_program`)."""

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
        return [Point(_sub(self.field, "low"), self.low, self.raw["low"]),
                Point(_sub(self.field, "high"), self.high, self.raw["high"])]

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
        """The mean, at ``<field>.mean`` (the support is unbounded: :attr:`bounded` is False)."""
        return [Point(_sub(self.field, "mean"), self.mean, self.raw["mean"])]

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
        return [Point(_sub(self.field, "low"), self.low, self.raw["low"]),
                Point(_sub(self.field, "high"), self.high, self.raw["high"])]

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
        return [Point(f"{_sub(self.field, 'values')}[{i}]", v, self.raw["values"][i])
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
        pts = [Point(_sub(self.field, "start"), self.start, self.raw["start"])]
        if self.num > 1:
            pts.append(Point(_sub(self.field, "stop"), self.stop, self.raw["stop"]))
        return pts

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
        return [Point(_sub(self.field, "low"), self.low, self.raw["low"]),
                Point(_sub(self.field, "high"), self.high, self.raw["high"])]

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


# ---------------------------------------------------------------- parsing


def _low_high(spec, field, si):
    low = number(spec["low"], _sub(field, "low"))
    high = number(spec["high"], _sub(field, "high"))
    if not low < high:
        raise InputError(_sub(field, "low"),
                         f"must be < high, got low = {spec['low']!r} >= high = {spec['high']!r}")
    return si(low), si(high)


def _std(spec, field, si):
    std = number(spec["std"], _sub(field, "std"))
    if not std > 0.0:
        raise InputError(_sub(field, "std"), f"must be > 0, got {spec['std']!r}")
    std = si(std)
    if not std > 0.0:  # a subnormal value that the unit conversion rounds to 0
        raise InputError(_sub(field, "std"), f"too small: {spec['std']!r} is 0 in SI")
    return std


#: Most points of one grid axis (its values are held in memory: 80 MB at this size).
MAX_GRID_POINTS = 10**7


def _weights(spec, field, count, what):
    if "weights" not in spec:
        return (1.0,) * count
    raw = spec["weights"]
    name = _sub(field, "weights")
    if not isinstance(raw, list):
        raise InputError(name, f"must be an array of numbers, got {_type_name(raw)} {raw!r}")
    if len(raw) != count:
        raise InputError(name, f"must have one weight per {what} ({count}), got {len(raw)}")
    weights = tuple(number(w, f"{name}[{i}]") for i, w in enumerate(raw))
    for i, w in enumerate(weights):
        if w < 0.0:
            raise InputError(f"{name}[{i}]", f"must be >= 0, got {raw[i]!r}")
    if not sum(weights) > 0.0:
        raise InputError(name, f"must not all be zero, got {raw!r}")
    return weights


def parse(spec, field, quantity, *, kinds=None, default_unit=None) -> Dist:
    """Parse and validate one numeric input.

    Parameters
    ----------
    spec : number or dict
        The TOML value.
    field : str
        Its dotted key, for error messages.
    quantity : str
        Its physical quantity (fixes the accepted units).
    kinds : iterable of str, optional
        The forms allowed here (default: all; ``"fixed"`` is the plain-number form).
    default_unit : str, optional
        Unit for values without their own (mixture components inherit the mixture's).

    Raises
    ------
    InputError
        Naming the offending key and value.
    """
    allowed = tuple(kinds) if kinds is not None else ("fixed",) + DIST_KINDS

    def refuse(kind):
        if kind not in allowed:
            only = ("a fixed number" if allowed == ("fixed",)
                    else "one of: " + ", ".join(allowed))
            raise InputError(field, f"a {kind} distribution is not allowed here "
                                    f"(expected {only})")

    if not isinstance(spec, dict):
        if isinstance(spec, (int, float)) and not isinstance(spec, bool):
            refuse("fixed")
            value = number(spec, field)
            si = u.to_si(value, default_unit, quantity, field)
            return Fixed(field, quantity, default_unit, value=si, raw=spec, written=field)
        raise InputError(field, f"must be a number or a table (a distribution), got "
                                f"{_type_name(spec)} {spec!r}")

    unit = spec.get("unit", default_unit)
    if "dist" not in spec:
        return _parse_value_table(spec, field, quantity, unit, refuse)
    kind = _distribution_kind(spec, field)
    required, optional = _KEYS[kind]
    check_keys(spec, field, ("dist",) + required, optional + ("unit",))
    refuse(kind)
    u.factor(unit, quantity, _sub(field, "unit"))  # validates the unit

    def f(value):  # to SI, exactly (see mcbat.study.units)
        return u.to_si(value, unit, quantity, field)

    raw = {k: spec[k] for k in required + optional if k in spec}
    common = dict(field=field, quantity=quantity, unit=unit)
    return _BUILDERS[kind](spec, field, f, raw, common)


def _parse_value_table(spec, field, quantity, unit, refuse) -> Fixed:
    """A fixed number written as a table, ``{value = ..., unit = "..."}``."""
    if "value" not in spec:
        raise InputError(_sub(field, "dist"),
                         "missing required key (a distribution: one of "
                         f"{', '.join(DIST_KINDS)}; or 'value' for a fixed number)")
    check_keys(spec, field, ("value",), ("unit",))
    refuse("fixed")
    u.factor(unit, quantity, _sub(field, "unit"))  # validates the unit
    value = number(spec["value"], _sub(field, "value"))
    return Fixed(field, quantity, unit,
                 value=u.to_si(value, unit, quantity, _sub(field, "value")),
                 raw=spec["value"], written=_sub(field, "value"))


def _distribution_kind(spec, field) -> str:
    """The validated ``dist`` key of a distribution table."""
    kind = spec["dist"]
    if not isinstance(kind, str):
        raise InputError(_sub(field, "dist"),
                         f"must be a string, got {_type_name(kind)} {kind!r}")
    if kind not in DIST_KINDS:
        raise InputError(_sub(field, "dist"), f"unknown distribution {kind!r} "
                                              f"(expected one of: {', '.join(DIST_KINDS)})")
    return kind


# Builders of the distributions from their validated tables: ``(spec, field, f, raw,
# common)``, where ``f`` converts a number of the table's unit to SI and ``common`` holds
# the field, quantity and unit.

def _build_uniform(spec, field, f, raw, common):
    low, high = _low_high(spec, field, f)
    return Uniform(**common, low=low, high=high, raw=raw)


def _build_unit_cube(kind):
    def build(spec, field, f, raw, common):
        low, high = _low_high(spec, field, f)
        return (Sobol if kind == "sobol" else LHS)(**common, low=low, high=high, raw=raw)
    return build


def _build_normal(spec, field, f, raw, common):
    mean = f(number(spec["mean"], _sub(field, "mean")))
    return Normal(**common, mean=mean, std=_std(spec, field, f), raw=raw)


def _build_truncnormal(spec, field, f, raw, common):
    mean = f(number(spec["mean"], _sub(field, "mean")))
    std = _std(spec, field, f)
    low, high = _low_high(spec, field, f)
    dist = TruncNormal(**common, mean=mean, std=std, low=low, high=high, raw=raw)
    a, b = (low - mean) / std, (high - mean) / std
    tail = a if a > 0.0 else (-b if b < 0.0 else 0.0)  # sigmas to the nearest end
    if tail > _MAX_TAIL_SIGMAS or not dist._pb > dist._pa:
        raise InputError(field, f"the interval [{spec['low']!r}, {spec['high']!r}] lies "
                                f"more than {_MAX_TAIL_SIGMAS:g} standard deviations from "
                                f"the mean {spec['mean']!r}: use a uniform distribution")
    return dist


def _build_choice(spec, field, f, raw, common):
    values_raw = spec["values"]
    name = _sub(field, "values")
    if not isinstance(values_raw, list) or not values_raw:
        raise InputError(name, f"must be a non-empty array of numbers, got "
                               f"{_type_name(values_raw)} {values_raw!r}")
    values = tuple(f(number(v, f"{name}[{i}]")) for i, v in enumerate(values_raw))
    weights = _weights(spec, field, len(values), "value")
    return Choice(**common, values=values, weights=weights, raw=raw)


def _build_grid(spec, field, f, raw, common):
    start = f(number(spec["start"], _sub(field, "start")))
    stop = f(number(spec["stop"], _sub(field, "stop")))
    num = integer(spec["num"], _sub(field, "num"), minimum=1, maximum=MAX_GRID_POINTS)
    return Grid(**common, start=start, stop=stop, num=num, raw=raw)


def _build_mixture(spec, field, f, raw, common):
    comps_raw = spec["components"]
    name = _sub(field, "components")
    if not isinstance(comps_raw, list) or not comps_raw:
        raise InputError(name, f"must be a non-empty array of distributions, got "
                               f"{_type_name(comps_raw)} {comps_raw!r}")
    components = []
    for i, c in enumerate(comps_raw):
        sub = f"{name}[{i}]"
        if isinstance(c, dict) and c.get("dist") not in (None,) + MIXTURE_COMPONENT_KINDS:
            if c.get("dist") in DIST_KINDS:
                raise InputError(_sub(sub, "dist"), f"a mixture component cannot be "
                                 f"{c['dist']!r} (expected one of: "
                                 f"{', '.join(MIXTURE_COMPONENT_KINDS)})")
        components.append(parse(c, sub, common["quantity"], kinds=MIXTURE_COMPONENT_KINDS,
                                default_unit=common["unit"]))
    weights = _weights(spec, field, len(components), "component")
    return Mixture(**common, components=tuple(components), weights=weights)


_BUILDERS = {"uniform": _build_uniform, "sobol": _build_unit_cube("sobol"),
             "lhs": _build_unit_cube("lhs"), "normal": _build_normal,
             "truncnormal": _build_truncnormal, "choice": _build_choice,
             "grid": _build_grid, "mixture": _build_mixture}


# ---------------------------------------------------------------- range checks


def _bound_text(bound, quantity):
    si = u.SI_UNITS[quantity]
    return f"{bound:.6g}" if quantity == u.DIMENSIONLESS else f"{bound:.6g} {si}"


def check_range(dist: Dist, *, minimum=None, maximum=None, strict_minimum=False,
                strict_maximum=False, what=None):
    """Every value ``dist`` can take must lie in the given (SI) range.

    Raises
    ------
    InputError
        On the key of the first offending point (``friction.mu.low``), naming its value;
        for an unbounded normal distribution, on the input itself, suggesting truncnormal.
    """
    if minimum is None and maximum is None:
        return
    conditions = []
    if minimum is not None:
        op = ">" if strict_minimum else ">="
        conditions.append(f"{op} {_bound_text(minimum, dist.quantity)}")
    if maximum is not None:
        op = "<" if strict_maximum else "<="
        conditions.append(f"{op} {_bound_text(maximum, dist.quantity)}")
    need = " and ".join(conditions)
    what = what or "this input"
    if not dist.bounded:
        if minimum is not None and maximum is not None:
            fix = f"truncnormal with low {conditions[0]} and high {conditions[1]}"
        elif minimum is not None:
            fix = f"truncnormal with low {conditions[0]}"
        else:
            fix = f"truncnormal with high {conditions[0]}"
        raise InputError(dist.field, f"a normal distribution is unbounded, but {what} must be "
                                     f"{need}: use {fix}")
    for p in dist.points():
        bad = False
        if minimum is not None:
            bad |= p.si <= minimum if strict_minimum else p.si < minimum
        if maximum is not None:
            bad |= p.si >= maximum if strict_maximum else p.si > maximum
        if bad:
            raise InputError(p.field, f"{what} must be {need}, got {dist.describe(p)}")
