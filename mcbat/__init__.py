"""mcbat: Monte Carlo study of ball-bat impacts with Coulomb friction.

The physics follows Cabo, Soler & González, "Scattering solution of a ball by a bat"
(Rev. Mex. Fís. 58, 2012); the equations, the frame and the paper's printing errors are in
``docs/physics.md``.

The front door (``import mcbat`` stays light: everything loads on first use)::

    mcbat.solve(case)              one impact (mcbat.api.ImpactCase) -> ImpactResult
    mcbat.run("study.toml", out)   a study file or Study -> a Parquet dataset directory
    mcbat.solve_frame(df)          a DataFrame of inputs -> a DataFrame of results
    mcbat.load(out)                a dataset directory -> a DataFrame (units in df.attrs)
    mcbat.load_summary(out)        a run's [summary] -> a DataFrame, one row per bin
    mcbat.load_study(path)         a TOML study file -> a validated Study

Layers, data flowing one way (study -> samples -> kernel -> dataset -> statistics):

``mcbat.core``     pure jitted physics, one folder per model; no I/O
``mcbat.bodies``   the ball, the bat, profiles and presets
``mcbat.study``    TOML studies -> validated Study -> samples
``mcbat.runner``   the run plan, the engines (local, Dask), run_study, solve_frame
``mcbat.dataset``  the column schema, storage, chunk files, load
``mcbat.stats``    measurement tables, fits, analysis
``mcbat.papers``   reproductions of papers (used by the command line only)
``mcbat.testing``  slow scipy reference solvers for tests and benchmarks
``mcbat.api``      single impacts; ``mcbat.cli`` the ``mcbat`` command
"""

__version__ = "0.1.0"

__all__ = ["__version__", "check", "load", "load_study", "load_summary", "run", "solve",
           "solve_frame"]


def solve(case, settings=None):
    """Solve one impact: see :func:`mcbat.api.solve`."""
    from mcbat.api import SolverSettings
    from mcbat.api import solve as _solve

    return _solve(case, SolverSettings() if settings is None else settings)


def run(study, out, **options):
    """Run a study into a dataset directory; returns a
    :class:`~mcbat.runner.study_run.RunSummary`.

    Parameters
    ----------
    study : str, Path or mcbat.study.Study
        A TOML study file, or a loaded study.
    out : str or Path
        The dataset directory (or a URL).
    **options
        ``samples``, ``seed``, ``threads``, ``chunk_size``, ``overwrite``, ``progress``,
        ``engine``, ``scheduler``, ``workers``, ``summary_only``, ``tolerance``: see
        :func:`mcbat.runner.run_study`; ``columns`` (a list of column names) overrides the
        study's ``[output] columns``.
    """
    from mcbat.runner import run_study
    from mcbat.study import Study, load_study

    if not isinstance(study, Study):
        study = load_study(study)
    columns = options.pop("columns", None)
    if columns is not None:
        study = study.with_overrides(columns=columns)
    return run_study(study, out, **options)


def solve_frame(frame, **settings):
    """A DataFrame of inputs -> a DataFrame of results, in memory, with the parallel
    kernel: see :func:`mcbat.runner.frame.solve_frame`."""
    from mcbat.runner.frame import solve_frame as _solve_frame

    return _solve_frame(frame, **settings)


def load(directory, columns=None, labels=False, allow_partial=False):
    """A dataset directory as a pandas DataFrame: see :func:`mcbat.dataset.load`."""
    from mcbat.dataset import load as _load

    return _load(directory, columns=columns, labels=labels, allow_partial=allow_partial)


def load_summary(directory):
    """The binned statistics of a run with a ``[summary]`` section, one row per bin: see
    :func:`mcbat.dataset.summary.load_summary`."""
    from mcbat.dataset.summary import load_summary as _load_summary

    return _load_summary(directory)


def check(directory, checksums=True):
    """Check a dataset directory against its manifest: see
    :func:`mcbat.dataset.check.check_dataset`."""
    from mcbat.dataset.check import check_dataset

    return check_dataset(directory, checksums=checksums)


def load_study(path):
    """A TOML study file -> a validated study: see :func:`mcbat.study.load_study`. A game
    study's ``[pitches]`` file is read too (:func:`mcbat.runner.pitches.load_pitches`), so
    the study samples at once."""
    from mcbat.study import load_study as _load_study

    study = _load_study(path)
    if getattr(study, "pitches", None) is None:
        return study
    from mcbat.runner.pitches import load_pitches  # (pandas: only for such a study)

    return load_pitches(study)


_SUBPACKAGES = ("api", "bodies", "core", "dataset", "errors", "runner", "stats", "study",
                "testing")


def __getattr__(name):
    # Subpackages on first use (``mcbat.stats.analysis``...), so that ``import mcbat``
    # imports neither numba nor pandas.
    import importlib

    if name in _SUBPACKAGES:
        return importlib.import_module(f"mcbat.{name}")
    if name == "analysis":  # the name of mcbat <= 0.1's module; now mcbat.stats.analysis
        return importlib.import_module("mcbat.stats.analysis")
    raise AttributeError(f"module 'mcbat' has no attribute {name!r}")
