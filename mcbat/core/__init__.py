"""Physics core: pure functions on plain floats and arrays (and, in ``sampling.py``, the
counter-based random sampler the study layer compiles its distributions for).

Nothing in this package performs I/O or imports pandas, pyarrow or matplotlib; an
import-linter contract in ``pyproject.toml`` (and ``tests/test_layers.py``) keeps it
that way. Jitted functions take scalars/arrays, return tuples or write into ``out``
arrays, and report failures through status codes (``mcbat.core.status``), never by raising.
"""

__all__ = []
