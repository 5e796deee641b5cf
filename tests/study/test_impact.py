"""Bat-frame studies (mcbat.study.impact, mcbat.study.impact_inputs): the solver columns
and the inputs derived from the declared ones, the contact's range checks, the canonical
config, the definition a worker rebuilds, and overrides."""

import copy
import json
import math
import pickle
import subprocess
import sys
import tomllib

import numpy as np
import pytest

from mcbat.api import Ball, Bat, Contact
from mcbat.bodies.tables import r161_profile
from mcbat.core.batch import INPUT_FIELDS
from mcbat.core.cabo2012.contact import DEFAULT_MAX_STEPS, DEFAULT_STEPS, DEFAULT_TOLERANCE
from mcbat.errors import InputError
from mcbat.study import COLUMNS, Study, load_study
from tests.conftest import ROOT
from tests.study.cases import ALL_KINDS, PROFILED, STUDIES, close, study


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


def test_loss_fraction_becomes_energetic_e(all_kinds_sample):
    e = all_kinds_sample["e"]
    assert e.min() >= 0.0 and e.max() <= 1.0
    # loss_fraction ~ U(0, 1) so e* = sqrt(1 - lf) has P(e* <= x) = x^2, mean 2/3.
    close(e.mean(), 2 / 3, math.sqrt(1 / 2 - 4 / 9), e.size)
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


def test_from_dict_builds_a_game_study_from_game_sections_whatever_was_imported():
    # Study.from_dict finds GameStudy in a registry that importing any module of
    # mcbat.study fills (the package imports every kind of study), with no import of
    # mcbat.study.game by mcbat.study.impact.
    code = ("import tomllib\n"
            "from mcbat.study.impact import Study\n"
            f"data = tomllib.loads(open({str(STUDIES / 'game_fastball.toml')!r}).read())\n"
            "print(type(Study.from_dict(data)).__name__)\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, cwd=ROOT)
    assert proc.stdout.strip() == "GameStudy"
    assert type(Study.from_dict(ALL_KINDS)) is Study
