"""The independent game tables (harness/game_tables.py): their kinematics against
mcbat's game kernel, physical invariants, and the game fit on tables it did not simulate."""

import math
from pathlib import Path

import numpy as np
import pytest

from harness import game_tables as gt
from validation.game_fit_validation import kernel_solver

STUDY_FILE = Path(__file__).resolve().parents[1] / "stats" / "data" / "game_fit_independent.toml"
TRUTH = {"e": 0.5, "e_x": 0.3}
CYLINDER = (gt.BODIES["bat_radius"], 0.0)


def _r161():
    """The R161 preset's mass properties and profile, as a bat of gt.bat_bodies."""
    from mcbat.bodies import bat_preset

    bat = bat_preset("r161")
    return dict(gt.BODIES, bat_mass=bat.mass, bat_transverse_inertia=bat.transverse_inertia,
                bat_axial_inertia=bat.axial_inertia, bat_length=bat.length,
                bat_cm_from_barrel_end=bat.cm_from_barrel_end, preset="r161",
                surface=lambda d: bat.surface_at(bat.cm_from_barrel_end - d))


def _row(inputs, k=0):
    return {name: float(values[k]) for name, values in inputs.items()}


def _kernel_case(row, e, e_x, handedness="R"):
    """The row as mcbat's public game case (the cylinder bat and the speed form of e*)."""
    from mcbat.api import GameCase
    from mcbat.bodies import Ball, Bat
    from mcbat.bodies.restitution import Restitution

    b = gt.BODIES
    return GameCase(
        ball=Ball(mass=b["ball_mass"], radius=b["ball_radius"],
                  inertia_factor=b["ball_inertia_factor"]),
        bat=Bat(mass=b["bat_mass"], radius=b["bat_radius"],
                transverse_inertia=b["bat_transverse_inertia"],
                axial_inertia=b["bat_axial_inertia"], length=b["bat_length"],
                cm_from_barrel_end=b["bat_cm_from_barrel_end"]),
        restitution=Restitution(e_ref=e, e_slope=gt.RESTITUTION["e_slope"],
                                e_speed_ref=gt.RESTITUTION["e_speed_ref"], e_x=e_x),
        pivot=b["pivot"], handedness=handedness, **row)


def test_study_file_matches_the_simulator():
    """The study the fit reads has the simulator's bodies, restitution and distributions."""
    from mcbat.study import load_study

    study = load_study(STUDY_FILE)
    b = gt.BODIES
    assert study.ball.mass == b["ball_mass"] and study.ball.radius == b["ball_radius"]
    assert study.ball.inertia_factor == b["ball_inertia_factor"]
    assert study.bat.mass == b["bat_mass"] and study.bat.radius == b["bat_radius"]
    assert study.bat.transverse_inertia == b["bat_transverse_inertia"]
    assert study.bat.axial_inertia == b["bat_axial_inertia"]
    assert study.bat.length == b["bat_length"]
    assert study.bat.cm_from_barrel_end == b["bat_cm_from_barrel_end"]
    keys = {"pitch_speed": "pitch.speed", "bat_speed": "swing.bat_speed", "mu": "friction.mu"}
    for section in ("pitch", "swing", "contact"):
        for name in gt.DISTRIBUTIONS:
            if f"{section}.{name}" in study.inputs:
                keys[name] = f"{section}.{name}"
    assert set(keys) == set(gt.DISTRIBUTIONS)
    for name, key in keys.items():
        kind, *args = gt.DISTRIBUTIONS[name]
        dist = study.inputs[key]
        fields = {"truncnormal": ("mean", "std", "low", "high"), "uniform": ("low", "high"),
                  "fixed": ("value",)}[kind]
        assert type(dist).__name__.lower() == kind, key
        assert np.allclose([getattr(dist, f) for f in fields], args, rtol=1e-12), key
    assert math.isclose(study.inputs["swing.pivot"].value, b["pivot"])
    assert study.inputs["restitution.e_slope"].value == gt.RESTITUTION["e_slope"]
    assert math.isclose(study.inputs["restitution.e_speed_ref"].value,
                        gt.RESTITUTION["e_speed_ref"])
    assert "restitution.location" not in study.inputs
    assert study.handedness == "R"


def test_game_table_has_the_columns_the_fit_reads():
    from mcbat.stats.columns import GAME_TABLE_COLUMNS

    table = gt.game_table(6, 3)
    assert set(table.columns) == {"pitch_speed", "bat_speed", "attack_angle", "undercut",
                                  "undercut_err", "launch_speed", "launch_speed_err",
                                  "launch_angle", "launch_angle_err", "spray_angle",
                                  "spray_angle_err", "spin_rate", "spin_rate_err"}
    assert {c.removesuffix("_err") for c in table.columns} <= set(GAME_TABLE_COLUMNS)
    truth = table.attrs["truth"]
    assert truth["e"] == 0.5 and truth["e_x"] == 0.3
    # the exact measured inputs are the true ones, in mph and deg
    assert np.allclose(table["pitch_speed"], truth["inputs"]["pitch_speed"] / gt.MPH)
    assert np.allclose(table["attack_angle"], np.degrees(truth["inputs"]["attack_angle"]))
    assert not np.allclose(table["undercut"], truth["inputs"]["undercut"])
    assert (78 <= table["pitch_speed"]).all() and (table["pitch_speed"] <= 94).all()
    assert 60 < table["launch_speed"].mean() < 120
    # one error per column, as stated
    assert table["launch_speed_err"].nunique() == 1 and table["spin_rate_err"].min() >= 50
    again = gt.game_table(6, 3)
    assert again.equals(table)
    # a measured contact place, with an error; the other inputs stay as they were
    placed = gt.game_table(6, 3, measured=tuple(gt.MEASURED),
                           input_errors={"undercut": 0.002, "from_barrel_end": 0.01})
    assert {"from_barrel_end", "from_barrel_end_err"} <= set(placed.columns)
    assert placed[list(table.columns)].equals(table)
    with pytest.raises(ValueError, match="spin_axis"):
        gt.game_table(2, 3, measured=("spin_axis",))


def test_bat_frame_case_agrees_with_the_kernel():
    """Every step of the transform to the bat frame: e*, the impact parameter, the contact
    and the bat-frame velocities and spins, against what mcbat's game kernel solved."""
    from mcbat.api import solve_game

    inputs = gt.draw_inputs(4, np.random.default_rng(21))
    for k in range(4):
        row = _row(inputs, k)
        for hand, sign in (("R", 1.0), ("L", -1.0)):
            mine = gt.bat_frame_case(row, gt.BODIES, lambda _: CYLINDER, 0.5, sign)
            result = solve_game(_kernel_case(row, 0.5, 0.3, hand))
            case = result.impact.case
            assert math.isclose(case.e, mine["e_star"], abs_tol=1e-12)
            assert math.isclose(result.undercut_impact_parameter, mine["impact_parameter"],
                                abs_tol=1e-12)
            assert math.isclose(case.contact.angle, mine["angle"], abs_tol=1e-12)
            assert math.isclose(case.contact.axial, mine["axial"], abs_tol=1e-12)
            for theirs, ours in ((case.ball_velocity, "ball_v"), (case.ball_spin, "ball_w"),
                                 (case.bat_velocity, "bat_v"), (case.bat_spin, "bat_w"),
                                 (result.pitch_spin, "pitch_w"),
                                 (result.bat_spin_in, "bat_w_field")):
                assert np.allclose(theirs, mine[ours], rtol=0, atol=1e-9), ours


@pytest.mark.parametrize(("bat", "handedness"), [("cylinder", 1.0), ("cylinder", -1.0),
                                                 ("r161", 1.0)])
def test_reference_table_agrees_with_the_kernel(bat, handedness):
    """Ten rows simulated independently (reference solver) and by mcbat's game kernel
    (through mcbat.api.solve_game) from the same random numbers: they agree to a small
    fraction of the stated measurement errors."""
    name = bat
    bat = _r161() if bat == "r161" else bat
    kw = dict(bat=bat, handedness=handedness, **TRUTH)
    ref = gt.game_table(10, 31, solver=gt.reference_solver, **kw)
    ker = gt.game_table(10, 31, solver=kernel_solver, **kw)
    ratios = {c: float(np.max(np.abs(ref[c] - ker[c]) / ref[f"{c}_err"]))
              for c in gt.OBSERVABLES}
    print(f"\n{name} {handedness:+.0f}: worst |reference - kernel| / error: "
          + ", ".join(f"{c} {r:.1e}" for c, r in ratios.items()))
    assert max(ratios.values()) < 0.05, ratios
    # the rows are real batted balls: a spread of launch angles and spins
    assert ref["launch_angle"].max() - ref["launch_angle"].min() > 20
    assert (ref["spin_rate"] > 0).all()


def test_head_on_frictionless_hit_gives_the_effective_mass_formula():
    """A level, square swing meeting a level pitch head on (no undercut, mu = 0), its
    direction rotated 10 deg about z: the ball leaves along the swing at
    q P + (1 + q) V with q = (e* - r) / (1 + r), r = m (1/M + d^2/I_t) (Nathan, Am. J. Phys.
    71, 134 (2003)), with its spin unchanged: the rigid-body result, not the README's."""
    b = gt.BODIES
    turn = math.radians(10.0)
    row = {name: 0.0 for name in gt.INPUT_NAMES}
    row.update(pitch_speed=38.0, spin_rate=230.0, spin_axis=math.radians(200.0),
               spin_efficiency=0.9, gyro_sign=1.0, bat_speed=32.0, attack_direction=turn,
               horizontal_approach_angle=-turn, from_barrel_end=0.1)
    result = gt.solve_row(row, 0.5, 0.3)
    lever = b["bat_length"] - gt.SWEET_SPOT - b["pivot"]
    speed_v = row["bat_speed"] * (b["bat_length"] - row["from_barrel_end"] - b["pivot"]) / lever
    d = b["bat_cm_from_barrel_end"] - row["from_barrel_end"]
    r = b["ball_mass"] * (1 / b["bat_mass"] + d * d / b["bat_transverse_inertia"])
    e_star = 0.5 - gt.RESTITUTION["e_slope"] * (row["pitch_speed"] + speed_v
                                                 - gt.RESTITUTION["e_speed_ref"])
    q = (e_star - r) / (1 + r)
    expected = (q * row["pitch_speed"] + (1 + q) * speed_v) / gt.MPH
    assert math.isclose(result["e_star"], e_star, rel_tol=1e-12)
    assert math.isclose(result["launch_speed"], expected, rel_tol=1e-7)
    assert abs(result["launch_angle"]) < 1e-6
    assert math.isclose(result["spray_angle"], 10.0, abs_tol=1e-6)
    assert math.isclose(result["spin_rate"], row["spin_rate"] / gt.RPM, rel_tol=1e-7)


def test_left_handed_batter_is_the_mirror_image():
    """A left-handed batter facing the mirrored pitch hits the mirrored ball: the same
    launch speed, launch angle and spin rate, the spray angle negated."""
    inputs = gt.draw_inputs(4, np.random.default_rng(8))
    right = gt.reference_solver(inputs, **TRUTH)
    left = gt.reference_solver(gt.mirrored(inputs), **TRUTH, handedness=-1.0)
    assert np.allclose(left[:, [0, 1, 3]], right[:, [0, 1, 3]], rtol=1e-7, atol=1e-6)
    assert np.allclose(left[:, 2], -right[:, 2], atol=1e-6)
    assert np.abs(right[:, 2]).max() > 1  # the spray angle is not 0 by accident
    # without the mirrored pitch the left-handed batter's ball is not the mirror image
    plain = gt.reference_solver(inputs, **TRUTH, handedness=-1.0)
    assert not np.allclose(plain[:, 2], -right[:, 2], atol=0.01)


def test_undercut_lifts_the_ball_with_backspin():
    """Hit below its centre (undercut > 0) the ball leaves higher and with backspin
    (spin . unit(v x z) > 0, docs/batting.md), above it lower and with topspin."""
    row = _row(gt.draw_inputs(1, np.random.default_rng(2)))
    angles, backspins = [], []
    for undercut in (-0.02, 0.0, 0.02):
        result = gt.solve_row(dict(row, undercut=undercut), **TRUTH)
        v, w = result["ball_velocity"], result["ball_spin"]
        horizontal = np.cross(v, [0.0, 0.0, 1.0])
        angles.append(result["launch_angle"])
        backspins.append(float(w @ horizontal / np.linalg.norm(horizontal)))
    assert angles[0] < angles[1] < angles[2]
    assert backspins[0] < 0 < backspins[2]


def test_game_fit_recovers_e_and_e_x_from_an_independent_table():
    """100 rows simulated independently, fitted as a user would: e* and e_x come back
    within two of their stated errors."""
    from mcbat.stats.fit.estimate import fit
    from mcbat.study import load_study

    table = gt.game_table(100, 11, **TRUTH)
    result = fit(load_study(STUDY_FILE), table, tuple(TRUTH), seed=11)
    for name, value in TRUTH.items():
        iv = result.intervals[name]
        assert iv["status"] == "measured"
        err = iv["upper_error"] if value > result.params[name] else iv["lower_error"]
        assert 0 < err < 0.05
        assert abs(result.params[name] - value) < 2 * err, (name, result.params[name], err)
    assert result.dof == 4 * len(table) - 2
    assert 0.001 < result.p_value
