"""Input checks: a value the user gave, validated, or an ``mcbat.errors.InputError``
that names the field and shows the offending value on one line.

Two families, because the two kinds of input differ:

* **Study-file values** (TOML: ``number``, ``integer``, ``check_keys``,
  ``check_string``, ``check_tolerance``): only what ``tomllib`` returns is
  accepted (``int``, ``float``, ``str``, ``dict``), and errors name the dotted key
  (``solver.steps``) and the value's TOML type.
* **Python arguments** (``check_real``, ``check_vector``, ``check_count``,
  ``positive_int``, ``int_from_text``): numpy scalars are accepted too, and errors
  name the parameter.

Every layer that reads input (studies, bodies, the runner, the fits, the command line) uses
these, so one kind of mistake gets one wording. The module imports nothing of mcbat but
``mcbat.errors`` (``pyproject.toml`` holds it to that).
"""

from __future__ import annotations

import math

import numpy as np

from mcbat.errors import InputError

__all__ = ["check_count", "check_keys", "check_real", "check_string", "check_tolerance",
           "check_vector", "int_from_text", "integer", "number", "positive_int",
           "short_repr", "subfield", "type_name"]


# ---------------------------------------------------------------- message helpers


def subfield(field: str, key: str) -> str:
    """The dotted key of ``key`` inside ``field`` (``key`` alone at the top level)."""
    return f"{field}.{key}" if field else key


def type_name(value) -> str:
    """The TOML name of ``value``'s type (``table``, ``array``, ``string``, ``boolean``),
    else the Python one."""
    return {dict: "table", list: "array", str: "string", bool: "boolean"}.get(
        type(value), type(value).__name__)


def short_repr(value) -> str:
    """``repr(value)``, shortened to ~60 characters (a 400-digit integer is one line)."""
    text = repr(value) if not isinstance(value, int) or value.bit_length() < 200 \
        else f"an integer of about {int(value.bit_length() * 0.30103) + 1} digits"
    return text if len(text) <= 60 else text[:57] + "..."


# ---------------------------------------------------------------- study-file values


def number(value, field) -> float:
    """A finite float from a TOML number, or ``InputError`` on ``field``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(field, f"must be a number, got {type_name(value)} "
                         f"{short_repr(value)}")
    try:
        value = float(value)
    except OverflowError:  # an integer beyond the largest float
        raise InputError(field, f"must be finite, got {short_repr(value)}") from None
    if not math.isfinite(value):
        raise InputError(field, f"must be finite, got {value!r}")
    return value


def integer(value, field, minimum=None, maximum=2**63 - 1) -> int:
    """A TOML integer (not a float, not a boolean) ``>= minimum`` and ``<= maximum``
    (default: what a 64-bit integer holds)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(field, f"must be an integer, got {type_name(value)} "
                         f"{short_repr(value)}")
    if minimum is not None and value < minimum:
        raise InputError(field, f"must be >= {minimum}, got {short_repr(value)}")
    if maximum is not None and value > maximum:
        raise InputError(field, f"must be <= {maximum:,}, got {short_repr(value)}")
    return int(value)


def check_keys(table, field, required=(), optional=()) -> dict:
    """``table`` must be a dict with every ``required`` key and nothing else but ``optional``."""
    if not isinstance(table, dict):
        raise InputError(field, f"must be a table, got {type_name(table)} {table!r}")
    allowed = tuple(dict.fromkeys((*required, *optional)))  # each key once, in order
    for key in table:
        if key not in allowed:
            raise InputError(subfield(field, key),
                             f"unknown key (expected one of: {', '.join(allowed)})")
    for key in required:
        if key not in table:
            raise InputError(subfield(field, key), "missing required key")
    return table


def check_string(value, field) -> str:
    """The string ``value`` of key ``field`` (InputError naming it otherwise)."""
    if not isinstance(value, str):
        raise InputError(field, f"must be a string, got {value!r}")
    return value


def check_tolerance(value, field) -> float:
    """The kernel's ``tolerance`` (the local error allowed per slip step, relative to the
    impact's scales; ``mcbat.core.cabo2012.contact.DEFAULT_TOLERANCE``) as a finite float
    with ``0 < tolerance < 1``, or ``InputError`` naming ``field``."""
    tolerance = number(value, field)
    if not 0.0 < tolerance < 1.0:
        raise InputError(field, f"must be > 0 and < 1, got {tolerance!r}")
    return tolerance


# ---------------------------------------------------------------- Python arguments


def check_count(value, name, minimum=0) -> int:
    """``value`` (an int or numpy integer, not a bool) ``>= minimum`` as an int, or
    ``InputError`` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(name, f"must be an integer >= {minimum}, got {value!r}")
    return int(value)


def positive_int(value, name: str) -> int:
    """``value`` as an int, or ``InputError`` naming ``name`` unless it is >= 1."""
    return check_count(value, name, 1)


def int_from_text(text: str, name: str) -> int:
    """The integer written in ``text`` (a command-line value), or ``InputError``
    naming ``name`` (the flag)."""
    try:
        return int(text)
    except (TypeError, ValueError):
        raise InputError(name, f"must be an integer, got {text!r}") from None


# ---------------------------------------------------------------- Python arguments

def check_real(value, name, *, positive=False, minimum=None, maximum=None) -> float:
    """``value`` as a finite float, or ``InputError`` naming ``name``.

    Parameters
    ----------
    value : object
        A real number (bool is refused).
    name : str
        The parameter or key to name in the error.
    positive : bool
        Require ``value > 0``.
    minimum, maximum : float, optional
        Inclusive bounds.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise InputError(name, f"must be a number, got {value!r}")
    try:
        value = float(value)
    except OverflowError:  # an integer beyond the largest float
        raise InputError(name, f"must be finite, got an integer of "
                         f"{int(value).bit_length()} bits") from None
    if not math.isfinite(value):
        raise InputError(name, f"must be finite, got {value!r}")
    if positive and not value > 0.0:
        raise InputError(name, f"must be > 0, got {value!r}")
    if minimum is not None and value < minimum:
        raise InputError(name, f"must be >= {minimum}, got {value!r}")
    if maximum is not None and value > maximum:
        raise InputError(name, f"must be <= {maximum}, got {value!r}")
    return value


def check_vector(value, name) -> tuple[float, float, float]:
    """``value`` as a tuple of 3 finite floats, or ``InputError`` naming ``name``."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 3:
        raise InputError(name, f"must be a list of 3 numbers [x, y, z], got {value!r}")
    return tuple(check_real(v, f"{name}[{i}]") for i, v in enumerate(value))
