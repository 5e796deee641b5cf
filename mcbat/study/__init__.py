"""Study files: TOML definitions of Monte Carlo scans, validated into a :class:`Study`
that produces deterministic solver input columns (:meth:`Study.sample`).

See :mod:`mcbat.study.spec` for the file format and the determinism scheme, and
``studies/README.md`` for a walk-through.
"""

from mcbat.study.spec import COLUMNS, LHS_BLOCK, Study, load_study

__all__ = ["COLUMNS", "LHS_BLOCK", "Study", "load_study"]
