"""Python API and kernel status codes: tapered bats, bad states, no exceptions in the kernel."""

import math

import numpy as np
import pytest

from mcbat.api import Ball, Bat, Contact, ImpactCase, SolverSettings, solve
from mcbat.bodies.tables import r161_profile
from mcbat.core import status as st
from mcbat.errors import InputError
from tests.conftest import kernel

BALL = Ball(mass=0.145, radius=0.036)
CYLINDER = Bat(mass=0.989, radius=0.03335, transverse_inertia=0.046, axial_inertia=4.39e-4)


def _case(**kw):
    base = dict(ball=BALL, bat=CYLINDER, contact=Contact(axial=0.115, angle=0.1),
                ball_velocity=(-4.0, 0.0, 0.0), ball_spin=(0.0, 0.0, 79.0), mu=0.5, e=0.62)
    return ImpactCase(**{**base, **kw})


def test_result_dict_and_properties():
    r = solve(_case())
    d = r.to_dict()
    assert d["exit_speed"] == pytest.approx(math.hypot(*r.ball_velocity), rel=1e-15)
    assert d["scattering_angle"] == pytest.approx(
        math.degrees(math.atan2(r.ball_velocity[1], r.ball_velocity[0])), rel=1e-15)
    assert d["impact_parameter"] == pytest.approx((0.036 + 0.03335) * math.sin(0.1), rel=1e-12)
    assert d["restitution_loss"] == pytest.approx(-d["normal_work"])
    assert d["end_state"] in ("stuck", "sliding") and d["status"] == "ok"


def test_loss_fraction_maps_to_energetic_coefficient():
    assert ImpactCase.e_from_loss_fraction(0.6183822) == pytest.approx(math.sqrt(1 - 0.6183822))
    with pytest.raises(InputError, match="loss_fraction"):
        ImpactCase.e_from_loss_fraction(1.5)


def test_tapered_profile_bat_tilts_the_normal_and_conserves_momentum():
    profile = r161_profile()
    bat = Bat.from_profile(profile)
    axial = profile.barrel_end - 0.15
    case = _case(bat=bat, contact=Contact(axial=axial, angle=0.0))
    radius, slope = case.contact_surface()
    assert slope > 0.005  # the R161 barrel still tapers 15 cm from its end
    result = solve(case)
    m, mb = BALL.mass, bat.mass
    p_in = m * np.array(case.ball_velocity)
    p_out = m * np.array(result.ball_velocity) + mb * np.array(result.bat_velocity)
    assert np.allclose(p_out, p_in, rtol=0, atol=1e-12 * np.abs(p_in).max())
    # Same bat as a cylinder of the same local radius: the tapered normal tilts towards the
    # knob (-z) by ~slope, so the ball leaves with an extra axial velocity ~ -slope * dv_n.
    flat = Bat(mass=bat.mass, radius=radius, transverse_inertia=bat.transverse_inertia,
               axial_inertia=bat.axial_inertia)
    flat_result = solve(_case(bat=flat, contact=Contact(axial=axial, angle=0.0)))
    dv_n = result.ball_velocity[0] - case.ball_velocity[0]
    extra = result.ball_velocity[2] - flat_result.ball_velocity[2]
    assert extra < 0.0
    assert extra == pytest.approx(-slope * dv_n, rel=0.3)


def test_contact_off_the_profile_is_rejected():
    bat = Bat.from_profile(r161_profile())
    with pytest.raises(InputError, match="contact.axial"):
        _case(bat=bat, contact=Contact(axial=bat.profile.barrel_end + 0.01, angle=0.0))


def test_not_approaching_is_an_input_error():
    with pytest.raises(InputError, match="not approaching"):
        solve(_case(ball_velocity=(4.0, 0.0, 0.0)))


def test_kernel_status_codes_never_raise():
    assert kernel(ball_v=(4.0, 0.0, 0.0))["status"] == st.NOT_APPROACHING
    bad = kernel(ball_v=(math.nan, 0.0, 0.0))
    assert bad["status"] == st.INVALID_INPUT and math.isnan(bad["ball_vx"])
    assert kernel(mu=-0.1)["status"] == st.INVALID_INPUT
    assert kernel(e=1.5)["status"] == st.INVALID_INPUT
    assert kernel(ball_mass=0.0)["status"] == st.INVALID_INPUT
    assert kernel(bat_axial_inertia=-1.0)["status"] == st.INVALID_INPUT
    assert kernel(radius=math.inf)["status"] == st.INVALID_INPUT
    # Finite but overflowing inputs: flagged, not an "ok" row full of NaN/inf.
    huge = kernel(ball_v=(-1e155, 0.0, 0.0))
    assert huge["status"] == st.INVALID_INPUT and math.isnan(huge["ball_vx"])
    assert kernel(ball_radius=1e-160)["status"] == st.INVALID_INPUT
    # A step budget too small for the slip phase is reported, not looped on.
    capped = kernel(ball_w=(0.0, 200.0, 300.0), mu=0.3, settings=(8, 3e-9, 2))
    assert capped["status"] == st.MAX_STEPS and math.isnan(capped["ball_vx"])


def test_solver_failure_is_an_input_error_naming_the_status():
    # a failure status of the user's case (here: too few steps allowed) is the user's to
    # fix: an InputError (exit 2 from the CLI), never an internal error
    with pytest.raises(InputError, match="status 'max_steps'"):
        solve(_case(ball_spin=(0.0, 200.0, 300.0)), SolverSettings(max_steps=2))


def test_solver_settings_check_the_tolerance():
    assert SolverSettings(tolerance=1e-11).tolerance == 1e-11
    assert type(SolverSettings(tolerance=np.float32(1e-6)).tolerance) is float
    for bad, words in ((0.0, "> 0 and < 1"), (1.0, "> 0 and < 1"), (-5e-9, "> 0 and < 1"),
                       (math.nan, "finite"), (math.inf, "finite"), ("5e-9", "number"),
                       (True, "number")):
        with pytest.raises(InputError, match=words) as info:
            SolverSettings(tolerance=bad)
        assert info.value.field == "tolerance"


def test_reprs_are_short():
    import mcbat

    result = mcbat.solve(_case())
    text = repr(result)
    assert text.startswith("ImpactResult(status='ok'") and len(text) < 400
    assert text.count("\n") <= 4
    bat = Bat.from_profile(r161_profile())
    assert len(repr(bat)) < 120 and "profile" in repr(bat)
    assert len(repr(Ball(mass=0.145, radius=0.036))) < 80


def test_contact_where_the_ball_overlaps_a_tapered_bat_is_refused():
    """R161's knob flare: a ball touching 80-81.5 cm from the barrel end reaches 1-6 mm
    into the bat elsewhere; the API refuses it, naming contact.axial. Along the barrel
    and handle (0-79.5 cm) nothing overlaps."""
    from mcbat.api import Contact, ImpactCase, solve
    from mcbat.bodies import Ball, bat_preset
    from mcbat.errors import InputError

    bat = bat_preset("r161")
    ball = Ball(mass=0.145, radius=0.0366, inertia_factor=0.4)

    def case(distance):
        axial = bat.axial_from_barrel_end(distance)
        return ImpactCase(ball=ball, bat=bat, contact=Contact(axial=axial, angle=0.0),
                          ball_velocity=(-20.0, 0.0, 0.0), mu=0.3, e=0.5)

    for distance in (0.805, 0.81, 0.815):
        with pytest.raises(InputError) as info:
            solve(case(distance))
        assert info.value.field == "contact.axial" and "overlap" in info.value.message
    assert bat.overlap(ball.radius, bat.axial_from_barrel_end(0.81)) > 1e-3
    for distance in (0.0, 0.15, 0.4, 0.6, 0.79):
        assert bat.overlap(ball.radius, bat.axial_from_barrel_end(distance)) == 0.0
        assert solve(case(distance)).status == "ok"


def _case_dict():
    return {"ball": {"mass": 0.145, "radius": 0.036},
            "bat": {"mass": 0.989, "radius": 0.03335, "transverse_inertia": 0.046,
                    "axial_inertia": 4.39e-4},
            "contact": {"axial": 0.115, "angle": 0.1}, "ball_velocity": [-4.0, 0.0, 0.0],
            "ball_spin": [0.0, 0.0, 79.0], "mu": 0.5, "restitution": {"e": 0.62}}


def test_front_door_solves_an_impact_as_object_dict_and_file(tmp_path):
    import json

    import mcbat
    from mcbat.api import ImpactResult

    expected = solve(_case())
    by_object = mcbat.solve(_case())
    by_dict = mcbat.solve(_case_dict())
    path = tmp_path / "impact.json"
    path.write_text(json.dumps(_case_dict()))
    by_file = mcbat.solve(path)
    by_name = mcbat.solve(str(path))
    for result in (by_object, by_dict, by_file, by_name):
        assert type(result) is ImpactResult
        assert result.to_dict() == expected.to_dict()
    settings = SolverSettings(max_steps=2)  # the settings reach the solver
    with pytest.raises(InputError, match="max_steps"):
        mcbat.solve(_case(ball_spin=(0.0, 200.0, 300.0)), settings=settings)


def test_front_door_reads_an_array_and_names_the_file_of_a_bad_case(tmp_path):
    import json

    import mcbat

    path = tmp_path / "cases.json"
    path.write_text(json.dumps([_case_dict(), _case_dict()]))
    assert [r.to_dict() for r in mcbat.solve(path)] == [solve(_case()).to_dict()] * 2
    bad = _case_dict()
    bad["ball"]["mass"] = -1.0
    path.write_text(json.dumps(bad))
    with pytest.raises(InputError) as info:
        mcbat.solve(path)
    assert info.value.field == "ball.mass" and info.value.source == str(path)
    path.write_text('{"mu": NaN}')
    with pytest.raises(InputError, match="NaN"):
        mcbat.solve(path)
    with pytest.raises(InputError) as info:
        mcbat.solve(42)
    assert info.value.field == "case" and "int" in info.value.message


def test_every_impact_quantity_has_its_unit_in_the_json_answer():
    d = solve(_case()).to_dict()
    units = d.pop("units")
    numeric = {k for k, v in d.items() if not isinstance(v, str)}
    assert numeric == set(units)
    assert units["ball_velocity"] == "m/s" and units["ball_spin"] == "rad/s"
    assert units["normal_impulse"] == "kg m/s" and units["energy_in"] == "J"
    assert units["scattering_angle"] == "deg" and units["impact_parameter"] == "m"


def test_one_tolerance_rule_for_settings_frames_and_studies():
    import pandas as pd

    import mcbat
    from mcbat.core.batch import INPUT_FIELDS
    from mcbat.study.spec import check_tolerance

    frame = pd.DataFrame({name: [0.0] for name in INPUT_FIELDS})
    for bad in (1.0, 0.0, -1e-9, 2.5, math.inf):
        with pytest.raises(InputError) as rule:
            check_tolerance(bad, "tolerance")
        with pytest.raises(InputError) as settings:
            SolverSettings(tolerance=bad)
        with pytest.raises(InputError) as frame_error:
            mcbat.solve_frame(frame, tolerance=bad)
        assert str(settings.value) == str(frame_error.value) == str(rule.value)
