"""Fixtures of tests/study/: the every-kind study and its first 200,000 samples (built once
per test module)."""

import pytest

from mcbat.study import Study
from tests.study.cases import ALL_KINDS


@pytest.fixture(scope="module")
def all_kinds():
    return Study.from_dict(ALL_KINDS)


@pytest.fixture(scope="module")
def all_kinds_sample(all_kinds):
    return all_kinds.sample(0, 200_000)
