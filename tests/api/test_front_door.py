"""The front door, ``mcbat``: real signatures, the case types on first use, the doctests."""

import doctest
import importlib
import inspect
import math
import pydoc
import re
from pathlib import Path

import pytest

import mcbat

KEYWORD_ONLY = inspect.Parameter.KEYWORD_ONLY


def _options(function):
    return {name: p.default for name, p in inspect.signature(function).parameters.items()
            if p.kind is KEYWORD_ONLY}


def _no_hidden_parameters(function):
    kinds = {p.kind for p in inspect.signature(function).parameters.values()}
    return inspect.Parameter.VAR_KEYWORD not in kinds and \
        inspect.Parameter.VAR_POSITIONAL not in kinds


@pytest.mark.parametrize("front, library, extra", [
    ("run", "mcbat.runner.study_run:run_study", {"columns": None}),
    ("solve_frame", "mcbat.runner.frame:solve_frame", {}),
    ("load", "mcbat.dataset.load:load", {}),
    ("check", "mcbat.dataset.check:check_dataset", {}),
])
def test_the_front_door_shows_the_library_options_as_keywords(front, library, extra):
    module, name = library.split(":")
    target = getattr(importlib.import_module(module), name)
    function = getattr(mcbat, front)
    assert _no_hidden_parameters(function)
    expected = {n: p.default for n, p in inspect.signature(target).parameters.items()
                if p.default is not inspect.Parameter.empty}
    if front == "check":  # the front door checks every byte unless told otherwise
        expected["checksums"] = True
    assert _options(function) == {**expected, **extra}


def test_help_of_run_lists_its_options():
    text = pydoc.render_doc(mcbat.run, renderer=pydoc.plaintext)
    text = re.sub(r": '[^']*' = ", "=", text)  # the annotations aside: name=default
    for shown in ("samples=None", "seed=None", "engine='local'", "tolerance=None",
                  "columns=None", "progress=True"):
        assert shown in text
    assert "**" not in str(inspect.signature(mcbat.run))
    assert list(_options(mcbat.solve)) == ["settings"]
    assert _no_hidden_parameters(mcbat.solve) and _no_hidden_parameters(mcbat.load_study)
    assert _no_hidden_parameters(mcbat.load_summary)


def test_the_case_and_result_types_load_on_first_use():
    from mcbat import api

    for name in ("ImpactCase", "ImpactResult", "GameCase", "GameResult", "FlightCase",
                 "FlightResult", "SolverSettings"):
        assert getattr(mcbat, name) is getattr(api, name)
        assert name in mcbat.__all__ and name in dir(mcbat)
    with pytest.raises(AttributeError):
        mcbat.NoSuchName  # noqa: B018


@pytest.mark.parametrize("name", ["mcbat", "mcbat.api", "mcbat.api.impact", "mcbat.api.game",
                                  "mcbat.api.flight", "mcbat.api.contract"])
def test_the_doctests_hold(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0 and result.failed == 0


def test_every_subpackage_is_reachable_from_import_mcbat():
    import mcbat

    assert callable(mcbat.statcast.read) and callable(mcbat.inference.infer_spin)
    assert {"statcast", "inference", "papers"} <= set(dir(mcbat))
    root = Path(mcbat.__file__).parent
    packages = {p.parent.name for p in root.glob("*/__init__.py")} - {"cli", "data", "studies"}
    for name in packages:
        assert getattr(mcbat, name).__name__ == f"mcbat.{name}"


def test_the_fit_and_the_run_summary_are_at_the_front_door():
    import mcbat
    from mcbat.runner.study_run import RunSummary
    from mcbat.stats.fit.estimate import FitResult, fit

    assert (mcbat.fit, mcbat.FitResult, mcbat.RunSummary) == (fit, FitResult, RunSummary)
    assert {"fit", "FitResult", "RunSummary"} <= set(mcbat.__all__)
    with pytest.raises(AttributeError):
        mcbat.analysis  # noqa: B018 (the old name of mcbat.stats.analysis is gone)


def test_a_flight_result_has_every_attribute_its_docstring_names():
    from mcbat.api import FlightCase, solve_flight

    r = solve_flight(FlightCase(launch_speed=46.0, launch_angle=0.47, spray_angle=0.2,
                                backspin=210.0))
    for name in ("hit_distance", "landing_x", "landing_y", "apex", "hang_time"):
        assert math.isfinite(getattr(r, name)), name
    assert r.landing_x == r.landing_x_m / 0.3048 and r.apex == r.apex_m / 0.3048
    assert r.to_dict()["landing_y"] == r.landing_y
    assert math.hypot(r.landing_x, r.landing_y) == pytest.approx(r.hit_distance)
