"""Study files: TOML definitions of Monte Carlo scans, validated into a :class:`Study`
that produces deterministic solver input columns (:meth:`Study.sample`).

The file format and the determinism scheme are described in ``docs/study-format.md``;
``studies/README.md`` walks through the shipped studies. :func:`load_study` reads a file
(:mod:`mcbat.study.spec`); importing it here also registers every kind of study with
:meth:`Study.from_dict`.
"""

from mcbat.study.spec import COLUMNS, LHS_BLOCK, Study, load_study

__all__ = ["COLUMNS", "LHS_BLOCK", "Study", "load_study"]
