"""The game layer: pitch + swing + contact in the field frame, end to end."""

import dataclasses
import json
import math

import numpy as np
import pytest

import mcbat
from mcbat.api import GameCase, case_from_dict, solve, solve_game
from mcbat.bodies import Ball, Bat, bat_preset
from mcbat.bodies.restitution import Restitution
from mcbat.errors import InputError
from mcbat.testing.cabo2012_reference import reference_impact
from tests.conftest import ROOT

MPH, RPM, DEG, IN = 0.44704, 2 * math.pi / 60, math.pi / 180, 0.0254
BALL = Ball(mass=0.145, radius=0.036)
CYLINDER = Bat(mass=0.9, radius=0.033, transverse_inertia=0.048, axial_inertia=4e-4,
               length=0.84, cm_from_barrel_end=0.84 - 0.56)
R161 = bat_preset("r161")


def level(**kw):
    base = dict(ball=BALL, bat=CYLINDER, pitch_speed=94 * MPH, bat_speed=72 * MPH, mu=0.0,
                restitution=Restitution(e_ref=0.5))
    base.update(kw)
    return GameCase(**base)


def general(**kw):
    base = dict(ball=BALL, bat=R161, pitch_speed=93 * MPH, bat_speed=73 * MPH, mu=0.5,
                vertical_approach_angle=-5 * DEG, horizontal_approach_angle=1.5 * DEG,
                spin_rate=2300 * RPM, spin_axis=215 * DEG, spin_efficiency=0.9,
                attack_angle=9 * DEG, attack_direction=4 * DEG, vertical_bat_angle=-28 * DEG,
                from_barrel_end=5 * IN, undercut=0.6 * IN)
    base.update(kw)
    return GameCase(**base)


@pytest.mark.parametrize("from_barrel_end", [6 * IN, 3 * IN, 9 * IN])
@pytest.mark.parametrize("bat", [CYLINDER, dataclasses.replace(CYLINDER, mass=1.1)])
def test_exact_1d_limit(from_barrel_end, bat):
    # a cylinder: on a tapered barrel the normal tilts by r'(z) and the hit is not 1D
    case = level(bat=bat, from_barrel_end=from_barrel_end)
    res = solve_game(case)
    d = bat.cm_from_barrel_end - from_barrel_end
    r = BALL.mass * (1 / bat.mass + d * d / bat.transverse_inertia)
    q = (0.5 - r) / (1 + r)
    lever = bat.length - 6 * IN - case.pivot          # pivot -> sweet spot
    v_bat = case.bat_speed * (bat.length - from_barrel_end - case.pivot) / lever
    expected = q * case.pitch_speed + (1 + q) * v_bat
    assert res.launch_speed * MPH == pytest.approx(expected, rel=1e-9)
    assert abs(res.launch_angle) < 1e-12 and abs(res.spray_angle) < 1e-12
    assert res.collision_efficiency == pytest.approx(q, rel=1e-9)


def _by_hand_bat_frame(case):
    """Level right-handed swing, level pitch: i = y, j = z, k = x (written out)."""
    lever = case.bat.length - 6 * IN - case.pivot
    cm_from_knob = case.bat.length - case.bat.cm_from_barrel_end
    omega = case.bat_speed / lever
    v_cm = case.bat_speed * (cm_from_knob - case.pivot) / lever
    th, eff, rate = case.spin_axis, case.spin_efficiency, case.spin_rate
    gyro = case.gyro_sign * rate * math.sqrt(1 - eff * eff)
    w_pitch = np.array([rate * eff * math.cos(th), -gyro, rate * eff * math.sin(th)])
    v_pitch = np.array([0.0, -case.pitch_speed, 0.0])

    def to_bat(f):
        return np.array([f[1], f[2], f[0]])

    radius, slope = case.bat.surface_at(case.axial)
    reach = radius + case.ball.radius / math.sqrt(1 + slope * slope)
    angle = math.asin(case.undercut / reach)
    return dict(axial=case.axial, angle=angle, radius=radius, slope=slope,
                ball_v=to_bat(v_pitch), ball_w=to_bat(w_pitch),
                bat_v=to_bat([0.0, v_cm, 0.0]), bat_w=to_bat([0.0, 0.0, omega]))


@pytest.mark.parametrize("undercut,spin_axis,mu,bat", [
    (0.8 * IN, 180 * DEG, 0.5, CYLINDER), (-0.5 * IN, 210 * DEG, 0.3, CYLINDER),
    (1.2 * IN, 30 * DEG, 0.15, R161), (0.3 * IN, 120 * DEG, 0.05, R161)])
def test_frames_agree_with_the_reference(undercut, spin_axis, mu, bat):
    case = level(bat=bat, undercut=undercut, spin_rate=2300 * RPM, spin_axis=spin_axis,
                 spin_efficiency=0.85, mu=mu, restitution=Restitution(e_ref=0.47, e_x=0.0))
    res = solve_game(case)
    hand = _by_hand_bat_frame(case)
    ref = reference_impact(BALL.mass, BALL.radius, BALL.inertia_factor, bat.mass,
                           bat.transverse_inertia, bat.axial_inertia, mu=mu, e=0.47, **hand)

    def to_field(b):
        return np.array([b[2], b[0], b[1]])

    scale_v = case.pitch_speed + case.bat_speed
    np.testing.assert_allclose(res.ball_velocity, to_field(ref["ball_v"]), rtol=0,
                               atol=1e-8 * scale_v)
    np.testing.assert_allclose(res.ball_spin, to_field(ref["ball_w"]), rtol=0,
                               atol=1e-8 * scale_v / BALL.radius)


def _mirror_v(v):
    return np.array([-v[0], v[1], v[2]])


def _mirror_w(w):
    return np.array([w[0], -w[1], -w[2]])


@pytest.mark.parametrize("spin_axis", [180 * DEG, 0.0])
def test_left_handed_batter_mirrors_a_symmetric_pitch(spin_axis):
    right = solve_game(general(horizontal_approach_angle=0.0, spin_axis=spin_axis,
                               spin_efficiency=1.0))
    left = solve_game(general(horizontal_approach_angle=0.0, spin_axis=spin_axis,
                              spin_efficiency=1.0, handedness="L"))
    for name in ("launch_speed", "launch_angle", "backspin"):
        assert getattr(left, name) == pytest.approx(getattr(right, name), rel=1e-12, abs=1e-9)
    for name in ("spray_angle", "sidespin"):
        assert getattr(left, name) == pytest.approx(-getattr(right, name), rel=1e-12,
                                                    abs=1e-9)
    assert abs(right.spray_angle) > 1.0 and abs(right.sidespin) > 10.0  # not trivially 0


def test_mirroring_the_pitch_too_mirrors_the_result():
    case = general()
    a, b = solve_game(case), solve_game(case.mirrored())
    np.testing.assert_allclose(b.ball_velocity, _mirror_v(a.ball_velocity), rtol=1e-12,
                               atol=1e-12 * 50)
    np.testing.assert_allclose(b.ball_spin, _mirror_w(a.ball_spin), rtol=1e-12, atol=1e-9)
    assert b.spray_angle == pytest.approx(-a.spray_angle, rel=1e-12)
    assert b.gyrospin == pytest.approx(-a.gyrospin, rel=1e-9, abs=1e-9)


@pytest.mark.parametrize("case", [general(), general(handedness="L", mu=0.2),
                                  level(undercut=1 * IN, spin_rate=2000 * RPM, mu=0.5)])
def test_linear_momentum_is_conserved_in_the_field_frame(case):
    res = solve_game(case)
    m, big_m = case.ball.mass, case.bat.mass
    before = m * np.array(res.pitch_velocity) + big_m * np.array(res.bat_velocity_in)
    after = m * np.array(res.ball_velocity) + big_m * np.array(res.bat_velocity)
    scale = m * case.pitch_speed + big_m * case.bat_speed
    np.testing.assert_allclose(after, before, rtol=0, atol=1e-12 * scale)


def test_positive_undercut_launches_up_with_backspin():
    for undercut in (0.3 * IN, 0.8 * IN, 1.5 * IN):
        res = solve_game(level(undercut=undercut, mu=0.5))
        assert res.launch_angle > 0 and res.backspin > 0
        res = solve_game(level(undercut=-undercut, mu=0.5))
        assert res.launch_angle < 0 and res.backspin < 0


def test_square_hit_on_a_backspinning_fastball_leaves_with_topspin():
    case = level(spin_rate=2300 * RPM, spin_axis=180 * DEG, mu=0.5, undercut=0.0)
    res = solve_game(case)
    assert res.pitch_spin[0] < 0            # backspin on the pitch: w along -x
    assert res.backspin < 0                 # topspin in the batted ball's own sense
    # friction on the pitch's spin also turns the ball a little downward (~ -2.4 deg here)
    assert -5 < res.launch_angle < 0
    frictionless = solve_game(dataclasses.replace(case, mu=0.0))
    assert frictionless.backspin == pytest.approx(-2300, rel=1e-12)   # spin unchanged


def test_spin_axis_90_and_270_move_the_pitch_sideways():
    # Statcast: 90 deg -> Magnus movement towards +x (first base), 270 -> towards -x
    for axis, sign in ((90 * DEG, 1), (270 * DEG, -1), (210 * DEG, -1)):
        res = solve_game(level(spin_rate=2300 * RPM, spin_axis=axis))
        w, v = np.array(res.pitch_spin), np.array(res.pitch_velocity)
        magnus = np.cross(w, v)
        assert np.sign(magnus[0]) == sign


def test_the_bat_frame_case_re_solves_bit_for_bit():
    res = solve_game(general())
    again = solve(case_from_dict(json.loads(json.dumps(res.to_dict()["bat_frame_case"]))))
    assert again.ball_velocity == res.impact.ball_velocity
    assert again.ball_spin == res.impact.ball_spin


@pytest.mark.parametrize("change,field", [
    (dict(attack_angle=50 * DEG, vertical_bat_angle=-45 * DEG), "vertical_bat_angle"),
    (dict(undercut=3 * IN), "undercut"),
    (dict(from_barrel_end=40 * IN), "from_barrel_end"),
    (dict(horizontal_approach_angle=120 * DEG), "horizontal_approach_angle"),
])
def test_bad_game_inputs_name_the_parameter(change, field):
    with pytest.raises(InputError) as err:
        general(**change)
    assert err.value.field == field


def test_game_study_end_to_end(tmp_path):
    study = mcbat.load_study(ROOT / "studies" / "game_fastball.toml")
    summary = mcbat.run(study, tmp_path / "g", samples=600, progress=False)
    assert summary.status_counts == {"ok": 600}
    df = mcbat.load(tmp_path / "g")
    from mcbat.dataset.schema import FLIGHT_COLUMNS, GAME_COLUMNS, si_units
    assert list(df.columns) == list(GAME_COLUMNS + FLIGHT_COLUMNS)  # the preset flies
    assert (df["flight_status"] == 0).all() and df["hit_distance"].between(0, 600).all()
    np.testing.assert_allclose(df["hit_distance_m"], df["hit_distance"] * 0.3048, rtol=1e-15)
    again = mcbat.solve_frame(df)        # every row re-solves in the bat frame alone
    for name in ("ball_vx", "ball_vy", "ball_wz", "normal_impulse"):
        np.testing.assert_array_equal(again[name].to_numpy(), df[name].to_numpy())
    # The pitch and the swing are stored in Statcast's units (the batted balls too)
    assert df.attrs["units"]["bat_speed"] == "mph" and df.attrs["units"]["attack_angle"] == "deg"
    # (in m/s they would lie near 30 and 40)
    assert df["bat_speed"].between(40, 110).all() and df["pitch_speed"].between(60, 110).all()
    # one row through the API (SI, by si_units) gives the same numbers, to the rounding of
    # the units' round trip
    row = si_units(df.iloc[7].to_dict())
    case = GameCase(ball=study.ball, bat=study.bat, pitch_speed=row["pitch_speed"],
                    bat_speed=row["bat_speed"], mu=row["mu"],
                    vertical_approach_angle=row["pitch_vertical_approach_angle"],
                    horizontal_approach_angle=row["pitch_horizontal_approach_angle"],
                    spin_rate=row["pitch_spin_rate"], spin_axis=row["pitch_spin_axis"],
                    spin_efficiency=row["pitch_spin_efficiency"],
                    attack_angle=row["attack_angle"], attack_direction=row["attack_direction"],
                    vertical_bat_angle=row["vertical_bat_angle"], pivot=row["pivot"],
                    from_barrel_end=row["from_barrel_end"], undercut=row["undercut"],
                    restitution=Restitution(e_ref=row["e_ref"], e_slope=row["e_slope"],
                                            e_speed_ref=row["e_speed_ref"], e_x=row["e_x"],
                                            location=study.restitution.location))
    res = solve_game(case)
    assert res.launch_speed == pytest.approx(row["launch_speed"], rel=1e-12)
    assert res.backspin == pytest.approx(row["backspin"], rel=1e-9, abs=1e-6)


def test_each_game_input_row_is_named_by_its_field():
    # The kernel reads its inputs by name (GAME_INPUT.mu): each name is its field's row in
    # GAME_INPUT_FIELDS, the order the samplers, the inference and the API write.
    from mcbat.core.swing.game import GAME_INPUT, GAME_INPUT_FIELDS

    assert GAME_INPUT._fields == GAME_INPUT_FIELDS
    for position, name in enumerate(GAME_INPUT_FIELDS):
        assert getattr(GAME_INPUT, name) == position, name
