"""The hard mix of impacts the kernel's accuracy is stated on (harness.impact_mix):
deterministic, every mode, creeping slip at ``|f|/mu ~ 1``, re-slip that the reference
confirms, bats of 5 g to 5000 kg, spins up to 3000 rad/s, ``mu`` from 0 to 1."""

import math

import numpy as np
import pytest

from harness.accuracy_mix import reference_for
from harness.impact_mix import (
    CREEP_RATIO_OFFSET,
    DEFAULT_SEED,
    MAX_SPIN,
    MODES,
    contact_problem,
    draw_mix,
)

N_MIX = 520  # the benchmark's mix
N_SUBSET = 40  # its first cases: 5 per mode


@pytest.fixture(scope="module")
def mix():
    return draw_mix(N_MIX, DEFAULT_SEED)


def _independent_k(case):
    """Delassus matrix in the contact basis, from the rigid-body formula in numpy (1/kg)."""
    basis, r_c, _, _ = contact_problem(case)
    t3 = basis[2]
    rho = -case["ball_radius"] * t3

    def skew(a):
        return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])

    i_p = case["ball_inertia_factor"] * case["ball_mass"] * case["ball_radius"] ** 2
    i_b_inv = np.diag(1.0 / np.array([case["bat_transverse_inertia"]] * 2
                                     + [case["bat_axial_inertia"]]))
    k_lab = ((1.0 / case["ball_mass"] + 1.0 / case["bat_mass"]) * np.eye(3)
             - skew(rho) @ skew(rho) / i_p - skew(r_c) @ i_b_inv @ skew(r_c))
    return basis @ k_lab @ basis.T


def _ratio(case):
    """``|f| / mu`` with ``f = -K_tt^-1 K_tn``."""
    k = _independent_k(case)
    return np.linalg.norm(np.linalg.solve(k[:2, :2], k[:2, 2])) / case["mu"]


def test_mix_is_deterministic_and_cycles_every_mode(mix):
    again = draw_mix(N_MIX, DEFAULT_SEED)
    assert again == mix
    assert draw_mix(N_SUBSET, DEFAULT_SEED) == mix[:N_SUBSET]  # the subset is the prefix
    assert draw_mix(N_SUBSET, DEFAULT_SEED + 1) != mix[:N_SUBSET]
    assert [c["mode"] for c in mix] == [MODES[i % len(MODES)] for i in range(N_MIX)]
    assert {c["slip"] for c in mix} == {"free", "small", "zero", "reslip", "creep"}
    for mode in ("light_bat", "heavy_bat"):  # any slip style on light and heavy bats
        assert {c["slip"] for c in mix if c["mode"] == mode} == {
            "free", "small", "zero", "reslip", "creep"}


def test_mix_covers_the_specified_ranges(mix):
    light = [c["bat_mass"] for c in mix if c["mode"] == "light_bat"]
    heavy = [c["bat_mass"] for c in mix if c["mode"] == "heavy_bat"]
    assert 0.005 <= min(light) < 0.01 and 0.2 < max(light) <= 0.3
    assert 5.0 <= min(heavy) < 10.0 and 2000.0 < max(heavy) <= 5000.0
    for c in mix:
        if c["mode"] in ("light_bat", "heavy_bat"):
            # A rod: I_t = m L^2 / 12 with L in 0.3-0.9 m, I_3 = m r^2 / 2, r 25-35 mm.
            length = math.sqrt(12.0 * c["bat_transverse_inertia"] / c["bat_mass"])
            rod_radius = math.sqrt(2.0 * c["bat_axial_inertia"] / c["bat_mass"])
            assert 0.3 - 1e-12 <= length <= 0.9 + 1e-12
            assert 0.025 - 1e-12 <= rod_radius <= 0.035 + 1e-12

    spins = [max(np.linalg.norm([c[f"{body}_w{a}_in"] for a in "xyz"])
                 for body in ("ball", "bat")) for c in mix if c["mode"] == "high_spin"]
    assert 2500.0 < max(spins) <= MAX_SPIN * (1.0 + 1e-12)
    assert np.median(spins) > 500.0

    mus = np.array([c["mu"] for c in mix])
    assert mus.min() == 0.0 and np.sum(mus == 0.0) >= 5 and 0.95 < mus.max() <= 1.0
    assert all(0.0 <= c["e"] <= 1.0 for c in mix)
    assert sum(c["bat_slope"] != 0.0 for c in mix) > 0.2 * N_MIX  # tapered contacts
    assert all(0.025 <= c["bat_radius"] <= 0.035 and abs(c["bat_slope"]) <= 0.1 for c in mix)
    for c in mix:
        _, _, _, v0 = contact_problem(c)
        assert -40.0 - 1e-9 <= v0[2] <= -2.0 + 1e-9  # approaching at 2-40 m/s
        if c["slip"] == "zero":
            assert np.linalg.norm(v0[:2]) <= 1e-13 * np.linalg.norm(v0)


def test_creeping_cases_sit_at_the_stick_slide_boundary(mix):
    creep = [c for c in mix if c["slip"] == "creep"]
    assert len(creep) >= 65
    ratios = np.array([_ratio(c) for c in creep])
    low, high = CREEP_RATIO_OFFSET
    assert np.all((np.abs(ratios - 1.0) >= low * 0.99) & (np.abs(ratios - 1.0) <= high * 1.01))
    assert np.sum(ratios < 1.0) >= 20 and np.sum(ratios > 1.0) >= 20  # both sides


def test_reference_confirms_creep_and_reslip(mix):
    """In the reference, re-slip cases stop and re-slip; creeping slip below the boundary
    creeps to a stick, above it never sticks (it re-slips or turns without stopping)."""
    # The first 160 cases (20 per mode) keep this fast.
    checked = {"reslip": 0, "creep below": 0, "creep above": 0, "zero reslip": 0}
    for c in mix[:160]:
        if c["slip"] not in ("reslip", "creep") and c["mode"] != "zero":
            continue
        r = reference_for(c)
        assert r["status"] == "ok", r["message"]
        if c["slip"] == "reslip":
            assert r["phases"] == ["slip", "reslip"], r["phases"]
            checked["reslip"] += 1
        elif c["slip"] == "creep" and _ratio(c) < 1.0:
            assert r["phases"] == ["slip", "stick"], r["phases"]
            # It creeps: the stop is well inside the impact, not at its start.
            assert 0.01 * r["normal_impulse"] < r["stick_impulse"]
            checked["creep below"] += 1
        elif c["slip"] == "creep":
            assert "stick" not in r["phases"], r["phases"]
            checked["creep above"] += 1
        elif "reslip" in r["phases"]:
            assert r["phases"] == ["reslip"] and r["stick_impulse"] == 0.0
            checked["zero reslip"] += 1
    assert checked["reslip"] >= 20 and checked["creep below"] >= 5
    assert checked["creep above"] >= 5 and checked["zero reslip"] >= 2
