"""Statistics: measurement tables, maximum-likelihood fits and model comparison, and the
common cuts of datasets (``mcbat.stats.analysis``)."""

from mcbat.stats import analysis, fit, measurements

__all__ = ["analysis", "fit", "measurements"]
