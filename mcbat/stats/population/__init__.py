"""Population fits (``mcbat fit --population``): ``fit`` (``fit_population``), its
binned ``likelihood``, its free ``parameters``, the measured ``table``, the simulated
``templates`` and the ``figure``."""

__all__ = []
