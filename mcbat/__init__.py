"""mcbat: Monte Carlo study of rigid ball-bat impacts with Coulomb friction.

The physics follows Cabo, Soler & Gonzalez, "Scattering solution of a ball by a bat"
(Rev. Mex. Fis. 58, 2012), restated in matrix form in ``mcbat/core/cabo2012/README.md``.

Layers
------
``mcbat.core``
    Pure, jitted physics on plain floats and arrays (no I/O).
``mcbat.api``
    Python objects for one impact case: build, validate, solve, ``to_dict()``.
``mcbat.study``, ``mcbat.runner``, ``mcbat.dataset``, ``mcbat.analysis``
    Monte Carlo scans: TOML studies, the resumable run, Parquet datasets, common cuts.
``mcbat.cli``
    The ``mcbat`` command.
"""

__version__ = "0.1.0"


def load(directory, columns=None, labels=False):
    """Load an ``mcbat run`` dataset directory as a pandas DataFrame.

    See :func:`mcbat.dataset.load`.
    """
    from mcbat.dataset import load as _load

    return _load(directory, columns=columns, labels=labels)


def __getattr__(name):
    # `mcbat.analysis` without importing pandas on `import mcbat`.
    if name == "analysis":
        import importlib

        return importlib.import_module("mcbat.analysis")
    raise AttributeError(name)
