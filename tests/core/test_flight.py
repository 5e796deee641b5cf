"""The flight kernel against the scipy reference, the sheet's published case, and
invariants."""

import math
from dataclasses import replace

import numpy as np
import pytest

from mcbat.core.flight.aero import Aero
from mcbat.core.flight.trajectory import (
    GRAVITY,
    FlightParams,
    allocate_flight_outputs,
    fly,
    fly_batch,
    pack_params,
)
from mcbat.solving.derived import launch_vectors
from mcbat.solving.settings import SolverSettings
from mcbat.study.flight import FlightSettings
from mcbat.testing.flight_reference import reference_flight

FT, MPH, RPM, DEG = 0.3048, 0.44704, 2 * math.pi / 60, math.pi / 180
SHEET = FlightSettings(temperature=(70 - 32) * 5 / 9 + 273.15, pressure=29.92 * 3386.389,
                       relative_humidity=50.0, elevation=15 * FT, spin_decay_time=None)
SHEET_BALL = (5.125 * 0.028349523125, 9.125 * 0.0254 / (2 * math.pi))  # mass, radius


def _vectors(speed_mph, angle_deg, spray_deg, back_rpm, side_rpm):
    v, w = launch_vectors(speed_mph * MPH, angle_deg * DEG, spray_deg * DEG, back_rpm * RPM,
                          side_rpm * RPM, 0.0)
    return tuple(float(x) for x in v), tuple(float(x) for x in w)


def test_air_density_of_the_sheet_conditions():
    assert SHEET.density == pytest.approx(1.194, abs=5e-4)  # BATTING.md's printed value


def test_the_sheet_published_case_and_the_converged_value():
    v, w = _vectors(100, 27.5, 0, 2537, 849)
    start = (0.0, 2 * FT, 3 * FT)
    sheet = fly(SHEET.__class__(**{**SHEET.__dict__, "scheme": "sheet"}).params(*SHEET_BALL),
                start, v, w)
    assert sheet.distance / FT == pytest.approx(400.5, abs=0.1)  # the sheet prints 400.5 ft
    converged = fly(SHEET.params(*SHEET_BALL), start, v, w)
    ref = reference_flight(start, v, w, density=SHEET.density, mass=SHEET_BALL[0],
                           radius=SHEET_BALL[1], decay_time=None)
    assert abs(converged.distance - ref["hit_distance"]) / FT < 0.05
    # a converged integration lands about a foot farther than the sheet's Euler steps
    assert 0.3 < (converged.distance - sheet.distance) / FT < 2.0


def _random_launches(n, seed=15):
    rng = np.random.default_rng(seed)
    return [_vectors(rng.uniform(60, 120), rng.uniform(-10, 60), rng.uniform(-45, 45),
                     rng.uniform(0, 4000), rng.uniform(-4000, 4000)) for _ in range(n)]


def test_default_accuracy_on_200_random_launches():
    settings = FlightSettings()  # nathan, 30 s spin decay, standard conditions
    ball = (0.145, 0.036)
    p = settings.params(*ball)
    worst_d = worst_t = 0.0
    for v, w in _random_launches(200):
        f = fly(p, settings.start, v, w)
        r = reference_flight(settings.start, v, w, density=settings.density, mass=ball[0],
                             radius=ball[1], decay_time=30.0)
        worst_d = max(worst_d, abs(f.distance - r["hit_distance"]) / FT)
        worst_t = max(worst_t, abs(f.hang_time - r["hang_time"]))
        assert abs(f.apex - r["apex"]) < 0.05 * FT
    assert worst_d < 0.05 and worst_t < 1e-3


def test_tightening_the_tolerance_converges():
    v, w = _vectors(103, 27, 10, 2000, -500)
    start = FlightSettings().start
    settings = FlightSettings()
    ref = reference_flight(start, v, w, density=settings.density, mass=0.145, radius=0.036)
    errors = [abs(fly(replace(settings, solver=SolverSettings(flight_tolerance=tol))
                      .params(0.145, 0.036), start, v, w).distance - ref["hit_distance"])
              for tol in (1e-4, 1e-6, 1e-8)]
    assert errors[2] < errors[1] < errors[0]


def test_without_air_the_flight_is_the_vacuum_parabola():
    p = FlightParams(0.0, 0.036, Aero(0, 0.0, 0.0, 1.0, 1.0), 0.0, GRAVITY, 0.0, 0.0, 0.0, 1e-6,
                     0.0)
    v, w = _vectors(90, 35, 20, 3000, 1000)
    z0 = 1.0
    f = fly(p, (0.0, 0.0, z0), v, w)
    t = (v[2] + math.sqrt(v[2] ** 2 + 2 * GRAVITY * z0)) / GRAVITY
    assert f.hang_time == pytest.approx(t, rel=1e-12)
    assert f.distance == pytest.approx(math.hypot(v[0], v[1]) * t, rel=1e-12)
    assert f.apex == pytest.approx(z0 + v[2] ** 2 / (2 * GRAVITY), rel=1e-12)


def test_mirror_symmetry_of_spray_and_sidespin():
    p = FlightSettings().params(0.145, 0.036)
    start = (0.0, 0.6, 0.9)
    for speed, angle, spray, back, side in ((100, 25, 15, 2000, 800), (80, 40, -30, 500, -1500)):
        a = fly(p, start, *_vectors(speed, angle, spray, back, side))
        b = fly(p, start, *_vectors(speed, angle, -spray, back, -side))
        assert b.landing_x == pytest.approx(-a.landing_x, abs=1e-9)
        assert b.landing_y == pytest.approx(a.landing_y, abs=1e-9)
        assert b.hang_time == pytest.approx(a.hang_time, abs=1e-12)


def test_denser_air_carries_shorter_and_backspin_carries_longer():
    v, w = _vectors(103, 27, 0, 2000, 0)
    start = FlightSettings().start

    def carry(**kw):
        s = FlightSettings(**kw)
        return fly(s.params(0.145, 0.036), start, v, w).distance

    assert carry(temperature=273.15) < carry() < carry(temperature=310.0)
    assert carry(elevation=1600.0) > carry()
    none = fly(FlightSettings().params(0.145, 0.036), start, *_vectors(103, 27, 0, 0, 0))
    assert none.distance < carry()


def test_batch_kernel_equals_single_flights_and_flags_bad_rows():
    launches = _random_launches(50, seed=3)
    n = len(launches) + 2
    start = np.tile(np.array([0.0, 0.6, 0.9])[:, None], (1, n))
    v = np.array([x[0] for x in launches] + [(30.0, 0.0, 10.0)] * 2).T.copy()
    w = np.array([x[1] for x in launches] + [(0.0, 0.0, 0.0)] * 2).T.copy()
    start[2, -1] = -0.5          # below the ground
    v[0, -2] = math.nan
    p = FlightSettings().params(0.145, 0.036)
    out, status = allocate_flight_outputs(n)
    fly_batch(pack_params(p), start, v, w, out, status)
    assert list(status[-2:]) == [1, 1] and (status[:-2] == 0).all()
    for i in range(n - 2):
        f = fly(p, tuple(start[:, i]), tuple(v[:, i]), tuple(w[:, i]))
        assert out[0, i] == f.distance and out[3, i] == f.hang_time


@pytest.mark.parametrize("model,kw", [("sawicki2003", {}), ("constant",
                                                          {"drag": 0.35, "lift": 0.2})])
def test_other_models_with_wind_and_gyrospin_match_the_reference(model, kw):
    import dataclasses

    settings = dataclasses.replace(FlightSettings(), model=model, spin_decay_time=None,
                                   wind=(2.0, -4.0, 0.5), drag=kw.get("drag", 0.0),
                                   lift=kw.get("lift", 0.0))
    p = settings.params(0.145, 0.036)
    rng = np.random.default_rng(7)
    for _ in range(20):
        v, w = launch_vectors(rng.uniform(60, 120) * MPH, rng.uniform(-5, 60) * DEG,
                              rng.uniform(-45, 45) * DEG, rng.uniform(0, 4000) * RPM,
                              rng.uniform(-3000, 3000) * RPM, rng.uniform(-1000, 1000) * RPM)
        v, w = tuple(float(x) for x in v), tuple(float(x) for x in w)
        f = fly(p, settings.start, v, w)
        r = reference_flight(settings.start, v, w, density=settings.density, mass=0.145,
                             radius=0.036, model=model, decay_time=None, wind=settings.wind,
                             **kw)
        assert abs(f.distance - r["hit_distance"]) / FT < 0.05
        assert abs(f.hang_time - r["hang_time"]) < 1e-3


def test_landing_height_and_calibration_scales_against_the_reference():
    # A catch height above the launch point (the ball must first rise through it) and
    # scaled drag and lift: the kernel against the scipy reference on 40 launches.
    rng = np.random.default_rng(7)
    for drag_scale, lift_scale, height in ((0.8, 1.3, 6 * FT), (1.25, 0.6, 6 * FT),
                                           (1.1, 0.0, 0.0)):
        settings = FlightSettings(drag_scale=drag_scale, lift_scale=lift_scale,
                                  landing_height=height)
        p = settings.params(0.145, 0.036)
        compared = 0
        for _ in range(40):
            v, w = _vectors(rng.uniform(60, 115), rng.uniform(5, 60), rng.uniform(-45, 45),
                            rng.uniform(0, 3500), rng.uniform(-3000, 3000))
            f = fly(p, settings.start, v, w)
            r = reference_flight(settings.start, v, w, density=settings.density, mass=0.145,
                                 radius=0.036, drag_scale=drag_scale, lift_scale=lift_scale,
                                 landing_height=height)
            if r is None:  # never rose to the catch height
                assert f.status == 3 and math.isnan(f.distance)
                continue
            compared += 1
            assert f.status == 0
            assert abs(f.distance - r["hit_distance"]) / FT < 0.05
            assert abs(f.hang_time - r["hang_time"]) < 1e-3
        assert compared >= 35


def test_scales_of_one_are_the_published_model_bit_for_bit():
    v, w = _vectors(103, 27, 10, 2000, -500)
    base = FlightSettings()
    scaled = FlightSettings(drag_scale=1.0, lift_scale=1.0, landing_height=0.0)
    assert fly(base.params(0.145, 0.036), base.start, v, w) == fly(
        scaled.params(0.145, 0.036), scaled.start, v, w)


def test_catch_height_in_a_vacuum():
    # Without air the descending crossing of z = h is analytic, also when the apex lies
    # just above h (the crossing is then inside the step that holds the apex).
    z0, h = 0.9144, 6 * FT
    for vz in (25.0, math.sqrt(2 * GRAVITY * (h - z0)) * 1.0005):
        p = FlightParams(0.0, 0.036, Aero(0, 0.0, 0.0, 1.0, 1.0), 0.0, GRAVITY, 0.0, 0.0, 0.0,
                         1e-6, h)
        f = fly(p, (0.0, 0.0, z0), (3.0, 30.0, vz), (0.0, 0.0, 0.0))
        t = (vz + math.sqrt(vz * vz - 2 * GRAVITY * (h - z0))) / GRAVITY
        assert f.status == 0
        assert f.hang_time == pytest.approx(t, rel=1e-9)
        assert f.distance == pytest.approx(math.hypot(3.0, 30.0) * t, rel=1e-9)
    # a ball that never rises to h: no crossing, status 3
    low = fly(p, (0.0, 0.0, z0), (0.0, 30.0, 0.9 * math.sqrt(2 * GRAVITY * (h - z0))),
              (0.0, 0.0, 0.0))
    assert low.status == 3 and math.isnan(low.distance)
