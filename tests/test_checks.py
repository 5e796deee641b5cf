"""The input checks every layer shares (mcbat.checks): what each accepts, and errors that
name the field and show the value."""

import math

import numpy as np
import pytest

import mcbat.errors
from mcbat import checks
from mcbat.errors import InputError


def _refused(check, *args, **kwargs):
    with pytest.raises(InputError) as info:
        check(*args, **kwargs)
    return info.value


def test_a_toml_number_is_a_finite_int_or_float():
    assert checks.number(3, "x") == 3.0 and isinstance(checks.number(3, "x"), float)
    assert _refused(checks.number, True, "a.b").message == "must be a number, got boolean True"
    assert _refused(checks.number, "1", "a.b").message == "must be a number, got string '1'"
    assert _refused(checks.number, math.inf, "a.b").message == "must be finite, got inf"
    huge = _refused(checks.number, 10**400, "a.b")
    assert huge.field == "a.b" and "an integer of about 401 digits" in huge.message


def test_a_toml_integer_is_an_int_within_bounds():
    assert checks.integer(5, "n", minimum=1, maximum=10) == 5
    assert _refused(checks.integer, 1.0, "n").message == "must be an integer, got float 1.0"
    assert _refused(checks.integer, 0, "n", minimum=1).message == "must be >= 1, got 0"
    assert _refused(checks.integer, 2**63, "n").message.startswith(
        "must be <= 9,223,372,036,854,775,807")


def test_check_keys_names_the_dotted_key():
    table = {"a": 1}
    assert checks.check_keys(table, "s", ("a",), ("b",)) is table
    err = _refused(checks.check_keys, {"a": 1, "c": 2}, "s", ("a",), ("b",))
    assert (err.field, err.message) == ("s.c", "unknown key (expected one of: a, b)")
    assert _refused(checks.check_keys, {}, "s", ("a",)).field == "s.a"
    assert _refused(checks.check_keys, {"z": 1}, "", ()).field == "z"  # the top level
    assert "must be a table, got array" in _refused(checks.check_keys, [1], "s").message


def test_strings_and_tolerances():
    assert checks.check_string("x", "s.name") == "x"
    assert _refused(checks.check_string, 3, "s.name").field == "s.name"
    assert checks.check_tolerance(1e-9, "tol") == 1e-9
    for bad in (0, 1, -1e-9, "1e-9", math.nan):
        assert _refused(checks.check_tolerance, bad, "tol").field == "tol"


def test_counts_accept_numpy_integers_and_refuse_booleans():
    assert checks.check_count(np.int64(4), "draws", 4) == 4
    assert type(checks.check_count(np.int32(0), "seed")) is int
    err = _refused(checks.check_count, 3, "draws", 4)
    assert (err.field, err.message) == ("draws", "must be an integer >= 4, got 3")
    assert checks.positive_int(np.uint8(1), "threads") == 1
    for bad in (0, True, 2.0, "2"):
        assert _refused(checks.positive_int, bad, "threads").message.startswith(
            "must be an integer >= 1, got ")


def test_an_integer_written_as_text():
    assert checks.int_from_text(" 12 ", "--samples") == 12
    err = _refused(checks.int_from_text, "1e6", "--samples")
    assert (err.field, err.message) == ("--samples", "must be an integer, got '1e6'")


def test_real_and_vector_checks_live_with_the_other_input_checks():
    assert not hasattr(mcbat.errors, "check_real") and not hasattr(mcbat.errors, "check_vector")
    assert checks.check_real(np.float32(2.5), "m", positive=True) == 2.5
    assert _refused(checks.check_vector, [1, 2], "v").field == "v"
