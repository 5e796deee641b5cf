"""How a study's inputs are drawn (mcbat.study.drawing): samples independent of chunking and
offsets, seeds, and the grid, Sobol' and Latin-hypercube designs."""

import math

import numpy as np
import pytest

from mcbat.study import COLUMNS, LHS_BLOCK, Study, load_study
from tests.study.cases import PROFILED, STUDIES, study

SPLITS = [
    [0, 200_000],
    [0, 1, 65_535, 65_537, 100_000, 131_072, 131_073, 199_999, 200_000],
    [0, 777, 70_001, 130_000, 196_607, 196_609, 200_000],
    [0, 65_536, 131_072, 196_608, 200_000],
]


@pytest.mark.parametrize("bounds", SPLITS)
def test_chunking_does_not_change_samples(all_kinds, all_kinds_sample, bounds):
    pieces = [all_kinds.sample(a, b) for a, b in zip(bounds[:-1], bounds[1:])]
    for name in COLUMNS:
        joined = np.concatenate([p[name] for p in pieces])
        assert np.array_equal(joined, all_kinds_sample[name]), name


def test_chunking_profiled_study():
    s = Study.from_dict(PROFILED)
    whole = s.sample(0, 140_000)
    bounds = [0, 3, 65_536, 65_539, 131_000, 140_000]
    for name in COLUMNS:
        joined = np.concatenate([s.sample(a, b)[name] for a, b in zip(bounds[:-1], bounds[1:])])
        assert np.array_equal(joined, whole[name]), name


def test_far_offset_equals_prefix_slice():
    s = Study.from_dict(PROFILED)
    start = 3 * LHS_BLOCK + 12_345
    tail = s.sample(start, start + 100)
    whole = s.sample(0, start + 100)
    for name in COLUMNS:
        assert np.array_equal(tail[name], whole[name][start:]), name


def test_seed_changes_random_inputs_not_grid(all_kinds, all_kinds_sample):
    other = all_kinds.sample(0, 200_000, seed=8)
    for name in ("axial", "angle", "ball_vx_in", "ball_vy_in", "ball_vz_in", "ball_wx_in",
                 "bat_vx_in", "bat_vy_in", "bat_wy_in", "mu", "e", "impact_parameter"):
        assert not np.array_equal(other[name], all_kinds_sample[name]), name
    for name in ("ball_wy_in", "ball_wz_in", "bat_vz_in"):
        assert np.array_equal(other[name], all_kinds_sample[name]), name
    # The default seed is the study's.
    assert np.array_equal(all_kinds.sample(10, 20)["mu"], all_kinds_sample["mu"][10:20])


def test_grid_outer_product(all_kinds, all_kinds_sample):
    assert all_kinds.grid_size == 12
    wy, wz = all_kinds_sample["ball_wy_in"], all_kinds_sample["ball_wz_in"]
    # Sample i uses grid point i mod 12; the first declared grid (wy) varies slowest.
    assert np.array_equal(wy[:12], np.repeat([0.0, 1.0, 2.0, 3.0], 3))
    assert np.array_equal(wz[:12], np.tile([10.0, 20.0, 30.0], 4))
    assert len(set(zip(wy[:12], wz[:12]))) == 12
    i = np.arange(wy.size)
    assert np.array_equal(wy, wy[i % 12]) and np.array_equal(wz, wz[i % 12])
    single = study(ball_spin__x={"dist": "grid", "start": 2.0, "stop": 9.0, "num": 1})
    assert single.grid_size == 12 and np.all(single.sample(0, 50)["ball_wx_in"] == 2.0)
    assert study(ball_spin__y=0.0, ball_spin__z=0.0).grid_size is None


def test_sobol_balanced(all_kinds_sample):
    y = all_kinds_sample["bat_vy_in"][:16_384]  # the second sobol dimension, on [0, 1)
    assert y.min() >= 0.0 and y.max() < 1.0
    # A scrambled Sobol' net: each of 2^14 equal bins holds exactly one of the first 2^14.
    assert np.array_equal(np.sort(np.floor(y * 16_384)), np.arange(16_384))


def test_sobol_two_dimensions_form_a_net():
    s = study(contact__approach_azimuth=0.0,
              bat_velocity__x={"dist": "sobol", "low": 0.0, "high": 1.0})
    cols = s.sample(0, 16_384)
    # bat_vx, bat_vy: the first two Sobol' dimensions are a (0, m, 2)-net in base 2, so
    # each of the 128 x 128 squares holds one of the first 2^14 points.
    a = cols["bat_vx_in"]
    b = cols["bat_vy_in"]
    cells = np.floor(a * 128).astype(int) * 128 + np.floor(b * 128).astype(int)
    assert np.array_equal(np.sort(cells), np.arange(16_384))


def test_lhs_strata_once_per_block(all_kinds_sample):
    for name in ("angle", "bat_wy_in"):
        for k in range(3):  # three full blocks of 65,536
            u = all_kinds_sample[name][k * LHS_BLOCK:(k + 1) * LHS_BLOCK]
            assert u.min() >= 0.0 and u.max() < 1.0
            strata = np.sort(np.floor(u * LHS_BLOCK).astype(np.int64))
            assert np.array_equal(strata, np.arange(LHS_BLOCK)), (name, k)


@pytest.mark.slow
def test_sampling_two_million_rows_is_fast():
    import time

    s = load_study(STUDIES / "throughput.toml")
    s.sample(0, 1000)
    best = math.inf
    for _ in range(3):
        t0 = time.perf_counter()
        s.sample(0, 2_000_000)
        best = min(best, time.perf_counter() - t0)
    assert best < 1.0
