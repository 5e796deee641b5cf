"""Statistics, one room per job: the per-row fit (``mcbat.stats.fit``), the draw models it
solves (``mcbat.stats.models``), population fits (``mcbat.stats.population``), two-sample
comparisons (``mcbat.stats.compare``); measurement tables (``mcbat.stats.measurements``,
their columns in ``mcbat.stats.columns``) and the common cuts of datasets
(``mcbat.stats.analysis``)."""

from mcbat.stats import analysis, compare, fit, measurements, models, population

__all__ = ["analysis", "compare", "fit", "measurements", "models", "population"]
