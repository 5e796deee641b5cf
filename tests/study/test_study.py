"""The study layer: TOML study files → validated Study → deterministic input columns."""

import copy
import json
import math
import pickle
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from mcbat.api import Ball, Bat, Contact
from mcbat.bodies.tables import r161_profile
from mcbat.core import status
from mcbat.core.batch import INPUT_FIELDS, OUTPUT_FIELDS, allocate_outputs, solve_batch
from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE
from mcbat.errors import InputError
from mcbat.study import COLUMNS, LHS_BLOCK, Study, load_study
from mcbat.study.units import UNITS, to_si

STUDIES = Path(__file__).resolve().parents[2] / "studies"

# Every distribution kind, on inputs of every section (cylinder bat: any axial is fine).
ALL_KINDS = {
    "study": {"name": "all kinds", "samples": 200_000, "seed": 7},
    "ball": {"preset": "baseball"},
    "bat": {"preset": "cross_nathan_2006"},
    "contact": {
        "axial": {"dist": "uniform", "low": 0.05, "high": 0.20},
        "angle": {"dist": "lhs", "low": 0.0, "high": 1.0},
        "approach_azimuth": {"dist": "sobol", "low": 0.0, "high": 1.0},
    },
    "ball_velocity": {
        "x": {"dist": "normal", "mean": -20.0, "std": 2.0},
        "y": {"dist": "truncnormal", "mean": 0.0, "std": 1.0, "low": -0.5, "high": 2.0},
        "z": {"dist": "truncnormal", "mean": 0.0, "std": 1.0, "low": 3.0, "high": 5.0},
    },
    "ball_spin": {
        "x": {"dist": "choice", "values": [-1.0, 0.0, 2.0], "weights": [1, 2, 5]},
        "y": {"dist": "grid", "start": 0.0, "stop": 3.0, "num": 4},
        "z": {"dist": "grid", "start": 10.0, "stop": 30.0, "num": 3},
    },
    "bat_velocity": {
        "x": {"dist": "mixture", "weights": [0.25, 0.75],
              "components": [5.0, {"dist": "uniform", "low": 0.0, "high": 1.0}]},
        "y": {"dist": "sobol", "low": 0.0, "high": 1.0},
        "z": 0.5,
    },
    "bat_spin": {"y": {"dist": "lhs", "low": 0.0, "high": 1.0}},
    "friction": {"mu": {"dist": "uniform", "low": 0.0, "high": 1.0}},
    "restitution": {"loss_fraction": {"dist": "uniform", "low": 0.0, "high": 1.0}},
}

# A profiled bat, contact by distance from the barrel end and impact parameter.
PROFILED = {
    "study": {"name": "profiled", "samples": 1000},
    "ball": {"preset": "baseball"},
    "bat": {"preset": "r161"},
    "contact": {
        "from_barrel_end": {"dist": "uniform", "low": 5, "high": 50, "unit": "cm"},
        "impact_parameter": {"dist": "uniform", "low": -1.5, "high": 1.5, "unit": "in"},
        "approach_azimuth": {"dist": "uniform", "low": -30, "high": 30, "unit": "deg"},
    },
    "ball_velocity": {"x": {"dist": "uniform", "low": -40, "high": -10}},
    "friction": {"mu": 0.5},
}


def study(data=ALL_KINDS, **changes):
    data = copy.deepcopy(data)
    for dotted, value in changes.items():
        section, key = dotted.split("__")
        data.setdefault(section, {})[key] = value
    return Study.from_dict(data, source="test.toml")


@pytest.fixture(scope="module")
def all_kinds():
    return Study.from_dict(ALL_KINDS)


@pytest.fixture(scope="module")
def all_kinds_sample(all_kinds):
    return all_kinds.sample(0, 200_000)


# ---------------------------------------------------------------- determinism


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


def test_sample_returns_every_column_float64(all_kinds):
    cols = all_kinds.sample(5, 17)
    assert tuple(cols) == COLUMNS
    assert COLUMNS[:len(INPUT_FIELDS)] == INPUT_FIELDS
    for name, values in cols.items():
        assert values.dtype == np.float64 and values.shape == (12,), name
        assert np.all(np.isfinite(values)), name
    assert all(v.size == 0 for v in all_kinds.sample(3, 3).values())
    with pytest.raises(ValueError):
        all_kinds.sample(5, 4)


# ---------------------------------------------------------------- statistics


def _close(value, expected, sigma, n, k=5.0):
    assert abs(value - expected) < k * sigma / math.sqrt(n), (value, expected)


def test_uniform_statistics(all_kinds_sample):
    x = all_kinds_sample["axial"]
    n = x.size
    assert x.min() >= 0.05 and x.max() < 0.20
    width = 0.15
    _close(x.mean(), 0.125, width / math.sqrt(12), n)
    assert abs(x.std() - width / math.sqrt(12)) < 0.01 * width / math.sqrt(12)
    counts, _ = np.histogram(x, bins=10, range=(0.05, 0.20))
    assert np.all(np.abs(counts - n / 10) < 5 * math.sqrt(n / 10))


def test_normal_statistics(all_kinds_sample):
    x = all_kinds_sample["ball_vx_in"]
    _close(x.mean(), -20.0, 2.0, x.size)
    assert abs(x.std() - 2.0) < 0.02
    assert stats.kstest(x, "norm", args=(-20.0, 2.0)).pvalue > 1e-4


@pytest.mark.parametrize("column, low, high", [("ball_vy_in", -0.5, 2.0),
                                               ("ball_vz_in", 3.0, 5.0)])  # an upper tail
def test_truncnormal_statistics(all_kinds_sample, column, low, high):
    x = all_kinds_sample[column]
    assert x.min() >= low and x.max() <= high
    ref = stats.truncnorm(low, high)  # mean 0, std 1
    _close(x.mean(), ref.mean(), ref.std(), x.size)
    assert abs(x.std() - ref.std()) < 0.02 * ref.std()
    assert stats.kstest(x, ref.cdf).pvalue > 1e-4


def test_choice_frequencies(all_kinds_sample):
    x = all_kinds_sample["ball_wx_in"]
    n = x.size
    assert set(np.unique(x)) == {-1.0, 0.0, 2.0}
    for value, p in ((-1.0, 1 / 8), (0.0, 2 / 8), (2.0, 5 / 8)):
        _close(np.mean(x == value), p, math.sqrt(p * (1 - p)), n)


def test_choice_zero_weight_never_drawn():
    s = study(friction__mu={"dist": "choice", "values": [0.1, 0.2, 0.3], "weights": [0, 1, 0]})
    assert np.all(s.sample(0, 70_000)["mu"] == 0.2)


def test_mixture_statistics(all_kinds_sample):
    x = all_kinds_sample["bat_vx_in"]
    n = x.size
    fixed = x == 5.0
    _close(fixed.mean(), 0.25, math.sqrt(0.25 * 0.75), n)
    rest = x[~fixed]
    assert rest.min() >= 0.0 and rest.max() < 1.0
    _close(rest.mean(), 0.5, 1 / math.sqrt(12), rest.size)


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


def test_loss_fraction_becomes_energetic_e(all_kinds_sample):
    e = all_kinds_sample["e"]
    assert e.min() >= 0.0 and e.max() <= 1.0
    # loss_fraction ~ U(0, 1) so e* = sqrt(1 - lf) has P(e* <= x) = x^2, mean 2/3.
    _close(e.mean(), 2 / 3, math.sqrt(1 / 2 - 4 / 9), e.size)
    fixed = study(restitution__loss_fraction=0.6183822).sample(0, 3)["e"]
    assert np.all(fixed == math.sqrt(1.0 - 0.6183822))
    data = copy.deepcopy(ALL_KINDS)
    del data["restitution"]
    assert np.all(Study.from_dict(data).sample(0, 3)["e"] == 1.0)


def test_restitution_e_and_default_zero_vectors():
    data = copy.deepcopy(ALL_KINDS)
    data["restitution"] = {"e": 0.25}
    cols = Study.from_dict(data).sample(0, 4)
    assert np.all(cols["e"] == 0.25)
    assert np.all(cols["bat_wx_in"] == 0.0) and np.all(cols["bat_wz_in"] == 0.0)
    assert np.all(cols["bat_vz_in"] == 0.5)
    assert np.all(cols["e_x"] == 0.0)  # no tangential compliance unless asked for


def test_tangential_restitution_e_x():
    data = copy.deepcopy(ALL_KINDS)
    data["restitution"] = {"e": 0.6, "e_x": {"dist": "uniform", "low": 0.1, "high": 0.2}}
    cols = Study.from_dict(data).sample(0, 1000)
    assert np.all(cols["e"] == 0.6)
    assert 0.1 <= cols["e_x"].min() and cols["e_x"].max() <= 0.2 and cols["e_x"].std() > 0
    data["restitution"] = {"e_x": 0.16}  # alone: e* = 1
    cols = Study.from_dict(data).sample(0, 3)
    assert np.all(cols["e"] == 1.0) and np.all(cols["e_x"] == 0.16)


# ---------------------------------------------------------------- units


def test_unit_conversions_exact():
    assert to_si(1, "mph", "speed") == 0.44704
    assert to_si(-90.0, "mph", "speed") == -40.2336
    assert to_si(0.1, "mm", "length") == 1e-4
    assert to_si(1, "in", "length") == 0.0254
    assert to_si(1.5, "in", "length") == 0.0381
    assert to_si(15, "cm", "length") == 0.15
    assert to_si(100, "cm", "length") == 1.0
    assert to_si(1, "ft", "length") == 0.3048
    assert to_si(36, "km/h", "speed") == 10.0
    assert to_si(1, "rpm", "spin") == 2 * math.pi / 60
    assert to_si(60, "rpm", "spin") == pytest.approx(2 * math.pi, rel=1e-15)
    assert to_si(1, "rps", "spin") == 2 * math.pi
    assert to_si(180, "deg", "angle") == pytest.approx(math.pi, rel=1e-15)
    assert to_si(2.0, None, "speed") == 2.0
    assert np.array_equal(to_si([1, 2], "cm", "length"), [0.01, 0.02])
    assert set(UNITS["length"]) == {"m", "cm", "mm", "in", "ft"}
    assert set(UNITS["speed"]) == {"m/s", "km/h", "mph", "ft/s"}
    assert set(UNITS["spin"]) == {"rad/s", "rpm", "rps"}
    assert set(UNITS["angle"]) == {"rad", "deg"}


def test_unit_errors_name_the_field():
    with pytest.raises(InputError, match=r"^ball_spin\.z: unit 'mph' is a speed unit"):
        to_si(1, "mph", "spin", "ball_spin.z")
    with pytest.raises(InputError, match=r"^contact\.axial: unknown unit 'furlong'"):
        to_si(1, "furlong", "length", "contact.axial")


def test_units_in_study():
    s = study(ball_velocity__x={"value": -90, "unit": "mph"},
              ball_spin__z={"dist": "choice", "values": [1800, -1200], "unit": "rpm"},
              contact__axial={"value": 15, "unit": "cm"},
              bat_velocity__y={"dist": "uniform", "low": 1, "high": 2, "unit": "ft/s"})
    cols = s.sample(0, 2000)
    assert np.all(cols["ball_vx_in"] == -40.2336)
    spins = np.unique(cols["ball_wz_in"])
    assert spins.size == 2
    assert spins == pytest.approx([-40 * math.pi, 60 * math.pi], rel=1e-15)
    assert np.all(cols["axial"] == 0.15)
    assert cols["bat_vy_in"].min() >= 0.3048 and cols["bat_vy_in"].max() < 0.6096
    cfg = {i["name"]: i for i in s.config()["inputs"]}
    assert cfg["ball_velocity.x"] == {"name": "ball_velocity.x", "quantity": "speed",
                                      "unit": "m/s", "dist": "fixed", "value": -40.2336}


# ---------------------------------------------------------------- derived inputs


def _reach(ball_radius, radius, slope):
    return radius + ball_radius / np.sqrt(1.0 + slope * slope)


def test_impact_parameter_angle_round_trip():
    s = Study.from_dict(PROFILED)
    cols = s.sample(0, 5000)
    reach = _reach(cols["ball_radius"], cols["bat_radius"], cols["bat_slope"])
    b = cols["impact_parameter"]
    assert b.min() >= -0.0381 and b.max() < 0.0381
    # angle = psi + asin(b / reach), psi in [-30, 30] deg.
    psi = cols["angle"] - np.arcsin(b / reach)
    assert psi.min() >= math.radians(-30) - 1e-12 and psi.max() < math.radians(30) + 1e-12
    assert np.allclose(reach * np.sin(cols["angle"] - psi), b, rtol=0, atol=1e-15)
    # The other direction: declare those angles and azimuths, get the impact parameters back.
    data = copy.deepcopy(PROFILED)
    data["contact"] = {"from_barrel_end": {"value": 20, "unit": "cm"},
                       "angle": {"dist": "uniform", "low": -0.6, "high": 0.6},
                       "approach_azimuth": 0.25}
    cols2 = Study.from_dict(data).sample(0, 5000)
    reach2 = _reach(0.036, cols2["bat_radius"], cols2["bat_slope"])
    assert np.allclose(cols2["impact_parameter"], reach2 * np.sin(cols2["angle"] - 0.25),
                       rtol=0, atol=1e-15)
    back = 0.25 + np.arcsin(cols2["impact_parameter"] / reach2)
    assert np.allclose(back, cols2["angle"], rtol=0, atol=1e-12)


def test_from_barrel_end_cylinder_matches_api():
    data = copy.deepcopy(PROFILED)
    data["bat"] = {"preset": "cross_nathan_2006"}
    data["contact"] = {"from_barrel_end": {"value": 15, "unit": "cm"},
                       "impact_parameter": {"value": 0.5, "unit": "in"}}
    cols = Study.from_dict(data).sample(0, 3)
    assert cols["axial"][0] == pytest.approx(0.115, abs=1e-15)
    assert np.all(cols["bat_radius"] == 0.03335) and np.all(cols["bat_slope"] == 0.0)
    assert np.all(cols["bat_mass"] == 0.989) and np.all(cols["bat_transverse_inertia"] == 0.046)
    bat = Bat(mass=0.989, radius=0.03335, transverse_inertia=0.046, axial_inertia=4.39e-4)
    contact = Contact.from_impact_parameter(0.115, 0.0127, Ball(0.145, 0.036), bat)
    assert cols["angle"][0] == pytest.approx(contact.angle, abs=1e-14)
    assert cols["impact_parameter"][0] == pytest.approx(0.0127, abs=1e-16)


def test_from_barrel_end_r161_profile():
    profile = r161_profile()
    s = Study.from_dict(PROFILED)
    cols = s.sample(0, 20_000)
    d = profile.barrel_end - cols["axial"]
    assert d.min() >= 0.05 - 1e-12 and d.max() < 0.50
    assert np.array_equal(cols["bat_radius"], profile.radius(cols["axial"]))
    assert np.array_equal(cols["bat_slope"], profile.slope(cols["axial"]))
    taper = (d > 0.25) & (d < 0.40)
    assert np.all(cols["bat_slope"][taper] > 0.01)  # the taper tilts the normal
    assert np.all(cols["bat_mass"] == profile.mass)
    assert np.all(cols["bat_transverse_inertia"] == profile.transverse_inertia)
    assert np.all(cols["bat_axial_inertia"] == profile.axial_inertia)
    assert s.bat.cm_from_barrel_end == profile.barrel_end
    # A fixed contact on the taper: radius and slope from the profile there.
    data = copy.deepcopy(PROFILED)
    data["contact"] = {"from_barrel_end": {"value": 30, "unit": "cm"}, "angle": 0.0}
    one = Study.from_dict(data).sample(0, 2)
    z = profile.barrel_end - 0.30
    assert one["axial"][0] == pytest.approx(z, abs=1e-15)
    assert one["bat_radius"][0] == pytest.approx(profile.radius(z), rel=1e-14)
    assert one["bat_slope"][0] == pytest.approx(profile.slope(z), rel=1e-12)
    assert one["bat_slope"][0] > 0.05


def test_whole_bat_length_allowed_on_profile():
    data = copy.deepcopy(PROFILED)
    data["contact"] = {"from_barrel_end": {"dist": "choice", "values": [0, 84], "unit": "cm"},
                       "angle": 0.0}
    cols = Study.from_dict(data).sample(0, 200)
    profile = r161_profile()
    assert set(np.unique(cols["axial"])) <= {profile.knob_end, profile.barrel_end}
    assert np.all(np.isfinite(cols["bat_radius"])) and np.all(np.isfinite(cols["bat_slope"]))


# ---------------------------------------------------------------- config


def test_config_canonical_and_hash():
    a = Study.from_dict(ALL_KINDS)
    b = Study.from_dict(copy.deepcopy(ALL_KINDS))
    assert a.config_hash() == b.config_hash()
    assert len(a.config_hash()) == 64
    text = json.dumps(a.config(), sort_keys=True)
    assert json.loads(text) == a.config()
    names = [i["name"] for i in a.config()["inputs"]]
    assert names[:3] == ["contact.axial", "contact.angle", "contact.approach_azimuth"]
    assert study(friction__mu=0.3).config_hash() != a.config_hash()
    over = a.with_overrides(samples=10, seed=99, chunk_size=5)
    assert (over.samples, over.seed, over.chunk_size) == (10, 99, 5)
    assert (a.samples, a.seed, a.chunk_size) == (200_000, 7, None)
    assert over.config_hash() != a.config_hash()
    assert np.array_equal(over.sample(0, 10)["mu"], a.sample(0, 10, seed=99)["mu"])
    with pytest.raises(InputError, match="seed"):
        a.with_overrides(seed=-1)
    assert a.solver == {"steps": DEFAULT_STEPS, "tolerance": DEFAULT_TOLERANCE,
                        "max_steps": DEFAULT_MAX_STEPS}
    a.solver["steps"] = 1  # a copy: the study is not changed
    assert a.solver["steps"] == DEFAULT_STEPS
    tuned = study(solver__steps=4, solver__tolerance=1e-10)
    assert tuned.solver == {"steps": 4, "tolerance": 1e-10, "max_steps": DEFAULT_MAX_STEPS}


@pytest.mark.parametrize("path", ["example.toml", "throughput.toml", "cross_nathan_2006.toml"])
def test_definition_rebuilds_an_equal_study(path):
    # What the Dask engine ships to a worker: plain data that rebuilds the same study,
    # overrides included, and samples identically.
    original = load_study(STUDIES / path)
    for s in (original, original.with_overrides(samples=123, seed=9, chunk_size=50)):
        data = s.definition()
        assert pickle.loads(pickle.dumps(data)) == data
        rebuilt = Study.from_dict(data)
        assert rebuilt.config() == s.config()
        a, b = rebuilt.sample(65_000, 66_000), s.sample(65_000, 66_000)
        assert all(np.array_equal(a[k], b[k]) for k in a)
    # The copy is deep: changing it leaves the study alone.
    original.definition()["study"]["samples"] = 1
    assert original.definition()["study"]["samples"] == original.samples


def test_a_tolerance_override_is_the_solver_tolerance_and_travels_with_the_study():
    original = load_study(STUDIES / "example.toml")
    tight = original.with_overrides(tolerance=1e-11)
    assert tight.solver == {**original.solver, "tolerance": 1e-11}
    assert original.solver["tolerance"] == DEFAULT_TOLERANCE  # the original is unchanged
    assert tight.config()["solver"]["tolerance"] == 1e-11
    assert tight.config_hash() != original.config_hash()
    # What a Dask worker rebuilds has the override (not the file's default tolerance).
    rebuilt = Study.from_dict(tight.definition())
    assert rebuilt.solver == tight.solver and rebuilt.config() == tight.config()
    assert "solver" not in original.definition()  # without an override: the file as it is
    data = tomllib.loads((STUDIES / "example.toml").read_text())
    data["solver"] = {"tolerance": 1e-11}
    assert Study.from_dict(data).config() == tight.config()
    for bad, words in ((0, "> 0 and < 1"), (1.0, "> 0 and < 1"), (-1e-9, "> 0 and < 1"),
                       (math.nan, "finite"), (math.inf, "finite"), ("1e-9", "number")):
        with pytest.raises(InputError, match=words) as info:
            original.with_overrides(tolerance=bad)
        assert info.value.field == "tolerance"


# ---------------------------------------------------------------- bad files


BASE_TOML = """\
[study]
name = "bad"
samples = 10

[ball]
preset = "baseball"

[bat]
preset = "cross_nathan_2006"

[contact]
from_barrel_end = { dist = "uniform", low = 14, high = 16, unit = "cm" }
impact_parameter = { dist = "uniform", low = -1.5, high = 1.5, unit = "in" }

[ball_velocity]
x = -4.0

[friction]
mu = 0.5

[restitution]
e = 0.6
"""

BAD = [
    # (replace, with, key named in the error, text in the message)
    ('samples = 10', 'samples = 10\nsampels = 3', "study.sampels", "unknown key"),
    ('x = -4.0', 'x = -4.0\nw = 1', "ball_velocity.w", "unknown key"),
    ('x = -4.0', 'x = { dist = "uniform", low = -5, high = -3, spread = 1 }',
     "ball_velocity.x.spread", "unknown key"),
    ('e = 0.6', 'e = 0.6\n[solvers]\nsteps = 3', "solvers",
     "unknown key"),
    ('mu = 0.5', 'mu = { dist = "gaussian", mean = 0.5, std = 0.1 }', "friction.mu.dist",
     "'gaussian'"),
    ('low = 14, high = 16', 'low = 16, high = 14', "contact.from_barrel_end.low",
     "low = 16 >= high = 14"),
    ('mu = 0.5', 'mu = { dist = "normal", mean = 0.5, std = -0.1 }', "friction.mu.std",
     "-0.1"),
    ('mu = 0.5', 'mu = { dist = "uniform", low = -0.2, high = 0.5 }', "friction.mu.low",
     "-0.2"),
    ('mu = 0.5', 'mu = -0.5', "friction.mu", "-0.5"),
    ('mu = 0.5', 'mu = { dist = "normal", mean = 0.5, std = 0.1 }', "friction.mu",
     "truncnormal with low >= 0"),
    ('e = 0.6', 'e = 1.2', "restitution.e", "1.2"),
    ('e = 0.6', 'e = 0.6\ne_x = -0.1', "restitution.e_x", "-0.1"),
    ('e = 0.6', 'e = 0.6\ne_x = { dist = "uniform", low = 0.5, high = 1.5 }',
     "restitution.e_x.high", "1.5"),
    ('e = 0.6', 'e = 0.6\nloss_fraction = 0.3\ne_x = 0.1', "restitution.loss_fraction",
     "not both"),
    ('e = 0.6', 'e = { dist = "choice", values = [0.5, -0.1] }', "restitution.e.values[1]",
     "-0.1"),
    ('e = 0.6', 'loss_fraction = { dist = "uniform", low = 0.5, high = 1.5 }',
     "restitution.loss_fraction.high", "1.5"),
    ('x = -4.0', 'x = { value = -4.0, unit = "rpm" }', "ball_velocity.x.unit", "'rpm'"),
    ('unit = "in"', 'unit = "parsec"', "contact.impact_parameter.unit", "'parsec'"),
    ('low = -1.5, high = 1.5, unit = "in"', 'low = -1.5, high = 3.0, unit = "in"',
     "contact.impact_parameter.high", "3.0 in"),
    ('impact_parameter = { dist = "uniform", low = -1.5, high = 1.5, unit = "in" }', '',
     "contact", "'angle' or 'impact_parameter'"),
    ('mu = 0.5', '', "friction.mu", "missing required key"),
    ('x = -4.0', 'x = "fast"', "ball_velocity.x", "'fast'"),
    ('mu = 0.5', 'mu = { dist = "choice", values = [0.1, 0.2], weights = [1, 2, 3] }',
     "friction.mu.weights", "one weight per value"),
    ('mu = 0.5', 'mu = { dist = "choice", values = [0.1, 0.2], weights = [1, -2] }',
     "friction.mu.weights[1]", "-2"),
    ('x = -4.0', 'x = { dist = "grid", start = 0, stop = 1, num = 0 }', "ball_velocity.x.num",
     "got 0"),
    ('low = 14, high = 16', 'low = 14, high = 90', "contact.from_barrel_end.high", "90 cm"),
    ('preset = "baseball"', 'mass = { dist = "uniform", low = 0.1, high = 0.2 }\nradius = 0.036',
     "ball.mass", "fixed number"),
    ('preset = "baseball"', 'mass = -0.145\nradius = 0.036', "ball.mass", "-0.145"),
    ('preset = "cross_nathan_2006"', 'preset = "louisville"', "bat.preset", "'louisville'"),
    ('samples = 10', 'samples = 10.5', "study.samples", "10.5"),
    ('e = 0.6', 'e = 0.6\n[solver]\ntolerance = 0', "solver.tolerance", "0"),
]


@pytest.mark.parametrize("old, new, key, text", BAD, ids=[b[2] for b in BAD])
def test_bad_study_files(tmp_path, old, new, key, text):
    assert old in BASE_TOML
    path = tmp_path / "bad_study.toml"
    path.write_text(BASE_TOML.replace(old, new, 1))
    with pytest.raises(InputError) as info:
        load_study(path)
    message = str(info.value)
    assert message.startswith(f"{path}: {key}: "), message
    assert text in message, message
    assert info.value.field == key and info.value.source == str(path)


def test_base_toml_is_valid(tmp_path):
    path = tmp_path / "ok.toml"
    path.write_text(BASE_TOML)
    s = load_study(path)
    assert s.source_text == BASE_TOML and s.name == "bad" and s.seed == 0
    assert s.chunk_size is None and s.grid_size is None


def test_toml_syntax_error_names_file_and_line(tmp_path):
    path = tmp_path / "syntax.toml"
    path.write_text(BASE_TOML.replace("mu = 0.5", "mu = = 0.5"))
    line = BASE_TOML.splitlines().index("mu = 0.5") + 1
    with pytest.raises(InputError) as info:
        load_study(path)
    assert str(info.value).startswith(f"{path}: line {line}, column ")
    assert "invalid TOML" in str(info.value)


def test_missing_file(tmp_path):
    with pytest.raises(InputError, match="cannot read the study file"):
        load_study(tmp_path / "nope.toml")


def test_impact_parameter_reach_on_profile_uses_thinnest_contact():
    data = copy.deepcopy(PROFILED)
    # 1.9 in = 48 mm fits on the barrel (reach ~68 mm) but not on the handle (~49.5 mm at
    # 60-70 cm from the barrel end): allowed up to 50 cm, refused up to 70 cm.
    data["contact"]["impact_parameter"] = {"dist": "uniform", "low": -1.9, "high": 1.9,
                                           "unit": "in"}
    Study.from_dict(data)
    data["contact"]["impact_parameter"] = {"dist": "uniform", "low": -1.9, "high": 1.95,
                                           "unit": "in"}
    data["contact"]["from_barrel_end"]["high"] = 70
    with pytest.raises(InputError, match=r"contact\.impact_parameter\.high: .*1\.95 in"):
        Study.from_dict(data)


# ---------------------------------------------------------------- shipped studies


def test_example_study_loads_and_solves():
    s = load_study(STUDIES / "example.toml")
    assert s.name == "example" and s.samples == 20_000 and s.seed == 2012
    cols = s.sample(0, 2000)
    assert np.all(cols["axial"] > 0.105 - 1e-12) and np.all(cols["axial"] < 0.125)
    assert set(np.unique(cols["ball_wz_in"])) == {79.0, 0.0, -72.0}
    inputs = np.stack([cols[f] for f in INPUT_FIELDS])
    out, st, es = allocate_outputs(inputs.shape[1])
    solve_batch(inputs, s.solver["steps"], s.solver["tolerance"], s.solver["max_steps"],
                out, st, es)
    assert np.all(st == status.OK)


def test_throughput_study_covers_every_end_state():
    s = load_study(STUDIES / "throughput.toml")
    assert s.samples == 2_000_000
    cols = s.sample(0, 200_000)
    assert np.any(np.abs(cols["bat_slope"]) > 0.05)  # tapered contacts
    for name in ("ball_wx_in", "ball_wy_in", "ball_wz_in", "bat_vx_in", "bat_wy_in"):
        assert np.any(cols[name] != 0.0), name
    assert cols["e"].min() < 0.01 and cols["e"].max() > 0.99
    inputs = np.stack([cols[f] for f in INPUT_FIELDS])
    out, st, es = allocate_outputs(inputs.shape[1])
    solve_batch(inputs, s.solver["steps"], s.solver["tolerance"], s.solver["max_steps"],
                out, st, es)
    ok = st == status.OK
    assert ok.mean() > 0.99
    stick = out[OUTPUT_FIELDS.index("stick_impulse")]
    stuck = ok & (es == status.STUCK)
    sliding = ok & (es == status.SLIDING) & np.isnan(stick)
    reslip = ok & (es == status.SLIDING) & np.isfinite(stick)
    assert stuck.sum() > 10_000 and sliding.sum() > 10_000
    assert reslip.sum() >= 50  # ~0.1 % of the mix


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


def test_shipped_studies_parse_as_plain_toml():
    for name in ("example.toml", "throughput.toml"):
        with open(STUDIES / name, "rb") as f:
            data = tomllib.load(f)
        assert Study.from_dict(data).config_hash() == load_study(STUDIES / name).config_hash()


def test_contact_range_reaching_the_knob_flare_is_refused():
    """A study whose contacts reach R161's knob flare (ball overlapping the bat) fails
    validation, naming the contact key; the throughput study's 0-70 cm passes."""
    from mcbat.errors import InputError

    data = {"study": {"name": "flare", "samples": 10}, "ball": {"preset": "baseball"},
            "bat": {"preset": "r161"},
            "contact": {"from_barrel_end": {"dist": "uniform", "low": 60, "high": 81,
                                            "unit": "cm"}, "angle": 0.0},
            "ball_velocity": {"x": -20.0, "y": 0.0, "z": 0.0}, "friction": {"mu": 0.3},
            "restitution": {"e": 0.5}}
    with pytest.raises(InputError) as info:
        Study.from_dict(data, source="flare.toml")
    assert info.value.field == "contact.from_barrel_end" and "overlap" in info.value.message
    data["contact"]["from_barrel_end"]["high"] = 70
    Study.from_dict(data, source="flare.toml")
