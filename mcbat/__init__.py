"""mcbat: Monte Carlo study of rigid ball-bat impacts with Coulomb friction.

The physics follows Cabo, Soler & Gonzalez, "Scattering solution of a ball by a bat"
(Rev. Mex. Fis. 58, 2012), restated in matrix form in ``mcbat/core/cabo2012/README.md``.

Layers
------
``mcbat.core``
    Pure, jitted physics on plain floats and arrays (no I/O).
``mcbat.api``
    Python objects for one impact case: build, validate, solve, ``to_dict()``.
``mcbat.cli``
    The ``mcbat`` command.
"""

__version__ = "0.1.0"
