"""mcbat: Monte Carlo study of ball-bat impacts with Coulomb friction.

The physics follows Cabo, Soler & González, "Scattering solution of a ball by a bat"
(Rev. Mex. Fís. 58, 2012); the equations, the frame and the paper's printing errors are in
``docs/physics.md``.

The front door (``import mcbat`` stays light: everything loads on first use)::

    mcbat.solve(case)              one case -> its result: an ImpactCase, GameCase or
                                   FlightCase, a JSON object or a JSON file (as
                                   ``mcbat impact`` and ``mcbat flight`` read them)
    mcbat.run("study.toml", out)   a study file or Study -> a Parquet dataset directory
    mcbat.solve_frame(df)          a DataFrame of inputs -> a DataFrame of results
    mcbat.load(out)                a dataset directory -> a DataFrame (units in df.attrs)
    mcbat.load_summary(out)        a run's [summary] -> a DataFrame, one row per bin
    mcbat.load_study(path)         a TOML study file -> a validated Study
    mcbat.check(out)               a dataset directory checked against its manifest
    mcbat.fit(study, table, free)  a measurement table -> a FitResult (maximum likelihood:
                                   ``mcbat.stats.fit.estimate.fit``)

The case and result types (``mcbat.ImpactCase``, ``mcbat.GameResult``...,
``mcbat.SolverSettings``) are those of ``mcbat.api``; ``mcbat.RunSummary`` is what
``mcbat.run`` returns, ``mcbat.FitResult`` what ``mcbat.fit`` returns. Every subpackage is
reachable as an attribute (``mcbat.statcast.read``), imported on first use. Units: an
impact is SI; a game case is SI, its batted ball in Statcast's mph, deg and rpm; a flight
case is SI, its distances in ft (and m). Every JSON answer (``result.to_dict()``) carries
a ``units`` block.

>>> import mcbat
>>> result = mcbat.solve({"ball": {"mass": 0.145, "radius": 0.036},
...                       "bat": {"mass": 0.989, "radius": 0.03335,
...                               "transverse_inertia": 0.046, "axial_inertia": 4.39e-4},
...                       "contact": {"axial": 0.115, "angle": 0.0},
...                       "ball_velocity": [-4.0, 0.0, 0.0], "mu": 0.5,
...                       "restitution": {"e": 0.618}})
>>> type(result).__name__, result.end_state
('ImpactResult', 'stuck')
>>> flight = mcbat.solve({"launch_speed": {"value": 103, "unit": "mph"},
...                       "launch_angle": {"value": 27, "unit": "deg"},
...                       "backspin": {"value": 2000, "unit": "rpm"}})
>>> type(flight).__name__, flight.to_dict()["units"].get("hit_distance")
('FlightResult', 'ft')

Layers, data flowing one way (study -> samples -> kernel -> dataset -> statistics):

``mcbat.core``     pure jitted physics, one folder per model; no I/O
``mcbat.bodies``   the ball, the bat, profiles and presets
``mcbat.solving``  the one caller of the kernels: impacts, games, flights; SolverSettings
``mcbat.study``    TOML studies -> validated Study -> samples
``mcbat.runner``   the run plan, the engines (local, Dask), run_study, solve_frame
``mcbat.dataset``  the column schema, storage, chunk files, load
``mcbat.stats``    measurement tables, fits, analysis
``mcbat.papers``   reproductions of papers (used by the command line only)
``mcbat.testing``  slow scipy reference solvers for tests and benchmarks
``mcbat.api``      single cases (impact, game, flight) and their JSON; ``mcbat.cli`` the
                   ``mcbat`` command
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, cast

if TYPE_CHECKING:  # the types only: ``import mcbat`` loads none of these modules
    from pathlib import Path

    import pandas as pd

    from mcbat.api import (
        FlightCase,
        FlightResult,
        GameCase,
        GameResult,
        ImpactCase,
        ImpactResult,
        SolverSettings,
    )
    from mcbat.dataset.check import DatasetCheck
    from mcbat.runner.study_run import RunSummary
    from mcbat.study import Study

    Result = ImpactResult | GameResult | FlightResult

__version__ = "0.1.0"


# The case and result types, the fit and a run's summary, loaded on first use from the
# module that defines them.
_LAZY = {"Ball": "mcbat.bodies", "Bat": "mcbat.bodies", "Contact": "mcbat.api",
         "ImpactCase": "mcbat.api", "ImpactResult": "mcbat.api", "GameCase": "mcbat.api",
         "GameResult": "mcbat.api", "FlightCase": "mcbat.api", "FlightResult": "mcbat.api",
         "SolverSettings": "mcbat.api", "fit": "mcbat.stats.fit.estimate",
         "FitResult": "mcbat.stats.fit.estimate", "RunSummary": "mcbat.runner.study_run"}

__all__ = ["Ball", "Bat", "Contact", "FitResult", "FlightCase", "FlightResult", "GameCase",
           "GameResult", "ImpactCase", "ImpactResult", "RunSummary", "SolverSettings",
           "__version__", "check", "fit", "load", "load_study", "load_summary", "run", "solve",
           "solve_frame"]


def solve(case: ImpactCase | GameCase | FlightCase | dict[str, Any] | str
          | os.PathLike[str], *,
          settings: SolverSettings | None = None) -> Result | list[Result]:
    """Solve one case; the result's type follows the case's.

    Parameters
    ----------
    case : ImpactCase, GameCase, FlightCase, dict, str or Path
        A case; or a JSON object as ``mcbat impact`` reads it (an impact or a game case)
        or as ``mcbat flight`` reads it (a flight: one with ``launch_speed``; the answer of
        ``mcbat impact`` for a game case is one, read in its ``units``); or the path of a
        JSON file holding such an object (or an array of them: a list of results).
    settings : SolverSettings, optional
        The impact solver's accuracy (impacts and games; default ``SolverSettings()``).

    Returns
    -------
    ImpactResult, GameResult or FlightResult
        For an ``ImpactCase``, a ``GameCase``, a ``FlightCase`` (or the
        JSON of one). ``result.to_dict()`` is the JSON answer, with its ``units``.

    Raises
    ------
    InputError
        Naming the field (and the file) of a bad input, or ``settings`` given for a
        flight.

    Examples
    --------
    >>> import math, mcbat
    >>> from mcbat.bodies import BALL_PRESETS, bat_preset
    >>> game = mcbat.solve(mcbat.GameCase(
    ...     ball=BALL_PRESETS["baseball"], bat=bat_preset("r161"), mu=0.5,
    ...     pitch_speed=40.0, bat_speed=31.0, attack_angle=math.radians(10.0)))  # SI
    >>> type(game).__name__, game.to_dict()["units"]["launch_speed"]
    ('GameResult', 'mph')
    >>> flight = mcbat.solve(mcbat.FlightCase.from_result(game))  # mph, deg, rpm -> SI
    >>> flight.hit_distance > 100                                  # ft
    True
    """
    from mcbat import api
    from mcbat.errors import InputError

    if isinstance(case, (str, os.PathLike)):
        data = _read_json(case)
        try:
            if isinstance(data, list):
                return [cast("Result", solve(api.any_case_from_dict(item), settings=settings))
                        for item in data]
            return solve(api.any_case_from_dict(data), settings=settings)
        except InputError as err:
            raise err.within(source=os.fspath(case)) from None
    if isinstance(case, dict):
        case = api.any_case_from_dict(case)
    if isinstance(case, api.FlightCase):
        if settings is not None:
            raise InputError("settings", "a flight has no impact solver settings (its own "
                             "are FlightCase.settings)")
        return api.solve_flight(case)
    if settings is None:
        settings = api.SolverSettings()
    if isinstance(case, api.GameCase):
        return api.solve_game(case, settings)
    if isinstance(case, api.ImpactCase):
        return api.solve(case, settings)
    raise InputError("case", "must be an ImpactCase, a GameCase, a FlightCase, a JSON object "
                     f"(dict) or the path of a JSON file, got {type(case).__name__}")


def _read_json(path: str | os.PathLike[str]) -> dict[str, Any] | list[Any]:
    """The JSON in the file at ``path`` (UTF-8; NaN and Infinity refused, as ``mcbat impact``
    refuses them)."""
    import json

    from mcbat.errors import InputError

    source = os.fspath(path)

    def refuse(constant: str) -> Any:
        raise InputError(None, f"not valid JSON: {constant} is not a JSON number", source)

    try:
        with open(path, encoding="utf-8-sig") as handle:
            text = handle.read()
    except OSError as err:
        raise InputError(None, f"cannot read input: {err.strerror}", source) from None
    except UnicodeDecodeError as err:
        raise InputError(None, f"not UTF-8 text (byte {err.start})", source) from None
    try:
        data = json.loads(text, parse_constant=refuse)
    except InputError:
        raise
    except ValueError as err:
        raise InputError(None, f"not valid JSON: {err}", source) from None
    if not (isinstance(data, dict) or isinstance(data, list) and data):
        raise InputError(None, "expected a JSON object (one case) or a non-empty array of "
                         "them", source)
    return cast("dict[str, Any] | list[Any]", data)


def run(study: str | Path | Study, out: str | Path, *, samples: int | None = None,
        seed: int | None = None, threads: int | None = None, chunk_size: int | None = None,
        overwrite: bool = False, progress: bool = True, engine: str = "local",
        scheduler: str | None = None, workers: int | None = None, summary_only: bool = False,
        tolerance: float | None = None, columns: list[str] | None = None) -> RunSummary:
    """Run a study into a dataset directory (resuming if possible); returns a
    ``mcbat.runner.study_run.RunSummary``.

    Parameters
    ----------
    study : str, Path or mcbat.study.Study
        A TOML study file, or a loaded study.
    out : str or Path
        The dataset directory (or a URL).
    samples, seed, chunk_size : int, optional
        Override the study's defaults.
    threads : int, optional
        Numba threads for the kernel (default: all; with ``engine="dask"``, per worker).
    overwrite : bool
        Replace an existing dataset of a different config.
    progress : bool
        Show a progress bar.
    engine : {"local", "dask"}
        Where the chunks are computed; the data are identical either way.
    scheduler : str, optional
        ``dask``: the address of a running scheduler to join.
    workers : int, optional
        ``dask``: start a local cluster of this many worker processes.
    summary_only : bool
        Compute the study's ``[summary]`` without storing the rows.
    tolerance : float, optional
        Override the study's ``[solver] tolerance`` (``0 < tolerance < 1``).
    columns : list of str, optional
        Column names: override the study's ``[output] columns``.

    See Also
    --------
    mcbat.runner.run_study : the details.
    """
    from mcbat.runner import run_study
    from mcbat.study import Study, load_study

    if not isinstance(study, Study):
        study = load_study(study)
    if columns is not None:
        study = study.with_overrides(columns=columns)
    return run_study(study, out, samples=samples, seed=seed, threads=threads,
                     chunk_size=chunk_size, overwrite=overwrite, progress=progress,
                     engine=engine, scheduler=scheduler, workers=workers,
                     summary_only=summary_only, tolerance=tolerance)


def solve_frame(frame: pd.DataFrame, *, steps: int = 8, tolerance: float = 5e-9,
                max_steps: int = 20_000, threads: int | None = None) -> pd.DataFrame:
    """A DataFrame of inputs -> a DataFrame of results, in memory, with the parallel
    kernel: see ``mcbat.runner.frame.solve_frame`` (the same defaults: the kernel's;
    ``tolerance`` finite with ``0 < tolerance < 1``)."""
    from mcbat.runner.frame import solve_frame as _solve_frame

    result: pd.DataFrame = _solve_frame(frame, steps=steps, tolerance=tolerance,
                                        max_steps=max_steps, threads=threads)
    return result


def load(directory: str | Path, *, columns: list[str] | None = None, labels: bool = False,
         allow_partial: bool = False) -> pd.DataFrame:
    """A dataset directory as a pandas DataFrame: see ``mcbat.dataset.load``."""
    from mcbat.dataset import load as _load

    df: pd.DataFrame = _load(directory, columns=columns, labels=labels,
                             allow_partial=allow_partial)
    return df


def load_summary(directory: str | Path) -> pd.DataFrame:
    """The binned statistics of a run with a ``[summary]`` section, one row per bin: see
    ``mcbat.dataset.summary.load_summary``."""
    from mcbat.dataset.summary import load_summary as _load_summary

    df: pd.DataFrame = _load_summary(directory)
    return df


def check(directory: str | Path, *, checksums: bool = True) -> DatasetCheck:
    """Check a dataset directory against its manifest (with ``checksums``, every byte's
    CRC-32): see ``mcbat.dataset.check.check_dataset``."""
    from mcbat.dataset.check import check_dataset

    return check_dataset(directory, checksums=checksums)


def load_study(path: str | Path) -> Study:
    """A TOML study file -> a validated study: see ``mcbat.study.load_study``. A game
    study's ``[pitches]`` file is read too (``mcbat.runner.pitches.load_pitches``), so
    the study samples at once."""
    from mcbat.study import load_study as _load_study

    study = _load_study(path)
    if getattr(study, "pitches", None) is None:
        return study
    from mcbat.runner.pitches import load_pitches  # (pandas: only for such a study)

    with_pitches: Study = load_pitches(study)
    return with_pitches


_SUBPACKAGES = ("api", "bodies", "checks", "core", "dataset", "errors", "inference", "papers",
                "runner", "solving", "statcast", "stats", "study", "testing")


def __getattr__(name: str) -> Any:
    # Subpackages and the case types on first use (``mcbat.stats.analysis``,
    # ``mcbat.ImpactCase``...), so that ``import mcbat`` imports neither numba nor pandas.
    import importlib

    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    if name in _SUBPACKAGES:
        return importlib.import_module(f"mcbat.{name}")
    raise AttributeError(f"module 'mcbat' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY) | set(_SUBPACKAGES))
