"""A simulated dataset against a measured table (``mcbat compare``): ``comparison``
(``compare``, ``Comparison``), the two sides read by ``inputs``, their ``units``, the
statistics of ``two_sample`` and the ``figure``."""

__all__ = []
