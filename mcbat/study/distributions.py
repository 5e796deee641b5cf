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

Every form accepts an optional ``unit`` (see ``mcbat.study.units``); values are stored
in SI. ``weights`` are optional (default: equal), non-negative, and need not sum to 1.
A mixture's ``components`` are fixed, uniform, normal, truncnormal or choice specs (plain
numbers allowed); a component without its own ``unit`` takes the mixture's.

This module parses and range-checks single inputs; the types it builds are in
``mcbat.study.dist_types``. How the families are drawn so that sample ``i`` depends on
``(study, seed, i)`` alone is in ``mcbat.study.drawing`` (and ``docs/study-format.md``).
"""

from __future__ import annotations

import math

from mcbat.checks import check_keys, integer, number, subfield, type_name
from mcbat.errors import InputError
from mcbat.study import units as u
from mcbat.study.dist_types import (
    LHS,
    Choice,
    Dist,
    Fixed,
    Grid,
    Mixture,
    Normal,
    Point,
    RandomDist,
    Sobol,
    TruncNormal,
    Uniform,
)

__all__ = ["Choice", "DIST_KINDS", "Dist", "Fixed", "Grid", "LHS", "MAX_GRID_POINTS",
           "MIXTURE_COMPONENT_KINDS", "Mixture", "Normal", "Point", "RandomDist", "Sobol",
           "TruncNormal", "Uniform", "check_range", "fixed_value", "parse"]

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


# ---------------------------------------------------------------- parsing


def _low_high(spec, field, si):
    low = number(spec["low"], subfield(field, "low"))
    high = number(spec["high"], subfield(field, "high"))
    if not low < high:
        raise InputError(subfield(field, "low"),
                         f"must be < high, got low = {spec['low']!r} >= high = {spec['high']!r}")
    return si(low), si(high)


def _std(spec, field, si):
    std = number(spec["std"], subfield(field, "std"))
    if not std > 0.0:
        raise InputError(subfield(field, "std"), f"must be > 0, got {spec['std']!r}")
    std = si(std)
    if not std > 0.0:  # a subnormal value that the unit conversion rounds to 0
        raise InputError(subfield(field, "std"), f"too small: {spec['std']!r} is 0 in SI")
    return std


#: Most points of one grid axis (its values are held in memory: 80 MB at this size).
MAX_GRID_POINTS = 10**7


def _weights(spec, field, count, what):
    if "weights" not in spec:
        return (1.0,) * count
    raw = spec["weights"]
    name = subfield(field, "weights")
    if not isinstance(raw, list):
        raise InputError(name, f"must be an array of numbers, got {type_name(raw)} {raw!r}")
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
                                f"{type_name(spec)} {spec!r}")

    unit = spec.get("unit", default_unit)
    if "dist" not in spec:
        return _parse_value_table(spec, field, quantity, unit, refuse)
    kind = _distribution_kind(spec, field)
    required, optional = _KEYS[kind]
    check_keys(spec, field, ("dist",) + required, optional + ("unit",))
    refuse(kind)
    u.factor(unit, quantity, subfield(field, "unit"))  # validates the unit

    def f(value):  # to SI, exactly (see mcbat.study.units)
        return u.to_si(value, unit, quantity, field)

    raw = {k: spec[k] for k in required + optional if k in spec}
    common = dict(field=field, quantity=quantity, unit=unit)
    return _BUILDERS[kind](spec, field, f, raw, common)


def _parse_value_table(spec, field, quantity, unit, refuse) -> Fixed:
    """A fixed number written as a table, ``{value = ..., unit = "..."}``."""
    if "value" not in spec:
        raise InputError(subfield(field, "dist"),
                         "missing required key (a distribution: one of "
                         f"{', '.join(DIST_KINDS)}; or 'value' for a fixed number)")
    check_keys(spec, field, ("value",), ("unit",))
    refuse("fixed")
    u.factor(unit, quantity, subfield(field, "unit"))  # validates the unit
    value = number(spec["value"], subfield(field, "value"))
    return Fixed(field, quantity, unit,
                 value=u.to_si(value, unit, quantity, subfield(field, "value")),
                 raw=spec["value"], written=subfield(field, "value"))


def _distribution_kind(spec, field) -> str:
    """The validated ``dist`` key of a distribution table."""
    kind = spec["dist"]
    if not isinstance(kind, str):
        raise InputError(subfield(field, "dist"),
                         f"must be a string, got {type_name(kind)} {kind!r}")
    if kind not in DIST_KINDS:
        raise InputError(subfield(field, "dist"), f"unknown distribution {kind!r} "
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
    mean = f(number(spec["mean"], subfield(field, "mean")))
    return Normal(**common, mean=mean, std=_std(spec, field, f), raw=raw)


def _build_truncnormal(spec, field, f, raw, common):
    mean = f(number(spec["mean"], subfield(field, "mean")))
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


def _nonempty_array(spec, field, key, what):
    """``spec[key]``, which must be a non-empty array (of ``what``), and its field name."""
    items = spec[key]
    name = subfield(field, key)
    if not isinstance(items, list) or not items:
        raise InputError(name, f"must be a non-empty array of {what}, got "
                               f"{type_name(items)} {items!r}")
    return items, name


def _build_choice(spec, field, f, raw, common):
    values_raw, name = _nonempty_array(spec, field, "values", "numbers")
    values = tuple(f(number(v, f"{name}[{i}]")) for i, v in enumerate(values_raw))
    weights = _weights(spec, field, len(values), "value")
    return Choice(**common, values=values, weights=weights, raw=raw)


def _build_grid(spec, field, f, raw, common):
    start = f(number(spec["start"], subfield(field, "start")))
    stop = f(number(spec["stop"], subfield(field, "stop")))
    num = integer(spec["num"], subfield(field, "num"), minimum=1, maximum=MAX_GRID_POINTS)
    return Grid(**common, start=start, stop=stop, num=num, raw=raw)


def _build_mixture(spec, field, f, raw, common):
    comps_raw, name = _nonempty_array(spec, field, "components", "distributions")
    components = []
    for i, c in enumerate(comps_raw):
        sub = f"{name}[{i}]"
        if isinstance(c, dict) and c.get("dist") not in (None,) + MIXTURE_COMPONENT_KINDS:
            if c.get("dist") in DIST_KINDS:
                raise InputError(subfield(sub, "dist"), f"a mixture component cannot be "
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


def fixed_value(spec, field, quantity, example) -> float:
    """A key that must be one finite fixed value (SI), e.g. a trend's shift;
    ``example`` is shown in the error (``'{ value = 10, unit = "mph" }'``)."""
    dist = parse(spec, field, quantity)
    if dist.family != "fixed" or not math.isfinite(dist.value):
        raise InputError(field, f"must be a fixed value (e.g. {example}), got {spec!r}")
    return float(dist.value)
