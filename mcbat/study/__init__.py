"""Study files: TOML definitions of Monte Carlo scans, validated into a ``Study``
that produces deterministic solver input columns (``Study.sample``).

The file format and the determinism scheme are described in ``docs/study-format.md``;
``studies/README.md`` walks through the shipped studies. ``load_study`` reads a file
(``mcbat.study.spec``); importing it here also registers every kind of study with
``Study.from_dict``.
"""

from mcbat.study.spec import COLUMNS, LHS_BLOCK, Study, load_study

__all__ = ["COLUMNS", "LHS_BLOCK", "Study", "load_study"]
