"""Bat profiles (solids of revolution) and their uniform-density mass properties.

Analytic checks (cylinder, truncated cone), an independent brute-force integration of a
many-segment profile, frame invariances, the R161 preset, continuity of the slope r'(z),
and error messages for bad input.
"""

import math

import numpy as np
import pytest

from mcbat.bodies.profile import BatProfile, mass_properties
from mcbat.bodies.tables import data_file, load_profile_tsv, r161_profile, read_profile_tsv

RHO = 649.0


def _brute_force(z, r, density, n=2_000_001):
    """Mass properties by the trapezoid rule on a very fine grid (piecewise-linear r)."""
    zz = np.linspace(z[0], z[-1], n)
    rr = np.interp(zz, z, r)
    area = density * np.pi * rr**2
    mass = np.trapezoid(area, zz)
    z_cm = np.trapezoid(area * zz, zz) / mass
    transverse = np.trapezoid(area * (rr**2 / 4 + (zz - z_cm) ** 2), zz)
    axial = np.trapezoid(area * rr**2 / 2, zz)
    return mass, z_cm, transverse, axial


# --- analytic solids ------------------------------------------------------------------

def test_cylinder():
    radius, length, z0 = 0.03, 0.8, -0.1
    mass, z_cm, transverse, axial = mass_properties([z0, z0 + length], [radius, radius], RHO)
    m = RHO * math.pi * radius**2 * length
    assert mass == pytest.approx(m, rel=1e-14)
    assert z_cm == pytest.approx(z0 + length / 2, rel=1e-14)
    assert transverse == pytest.approx(m * (3 * radius**2 + length**2) / 12, rel=1e-13)
    assert axial == pytest.approx(m * radius**2 / 2, rel=1e-14)


def test_cylinder_split_into_many_nodes_is_unchanged():
    z = np.linspace(0.0, 0.8, 57)
    one = mass_properties([0.0, 0.8], [0.03, 0.03], RHO)
    many = mass_properties(z, np.full_like(z, 0.03), RHO)
    np.testing.assert_allclose(many, one, rtol=1e-13)


def _frustum(r1, r2, h, density):
    """Closed forms for a truncated cone from z=0 (radius r1) to z=h (radius r2)."""
    k = (r2 - r1) / h
    # int_0^h r^n dz = (r2^(n+1) - r1^(n+1)) / ((n+1) k), and the z-weighted moments by parts.
    def p(n):
        return (r2 ** (n + 1) - r1 ** (n + 1)) / ((n + 1) * k)

    mass = density * math.pi * p(2)
    # int z r^2 dz with z = (r - r1)/k:  (p(3) - r1 p(2)) / k
    first = density * math.pi * (p(3) - r1 * p(2)) / k
    z_cm = first / mass
    # int z^2 r^2 dz = (p(4) - 2 r1 p(3) + r1^2 p(2)) / k^2
    second = density * math.pi * (p(4) - 2 * r1 * p(3) + r1**2 * p(2)) / k**2
    transverse = density * math.pi * p(4) / 4 + second - mass * z_cm**2
    axial = density * math.pi * p(4) / 2
    return mass, z_cm, transverse, axial


def test_truncated_cone_closed_form():
    r1, r2, h = 0.012, 0.032, 0.5
    got = mass_properties([0.0, h], [r1, r2], RHO)
    want = _frustum(r1, r2, h, RHO)
    np.testing.assert_allclose(got, want, rtol=1e-12)
    # Textbook frustum values as a further anchor.
    assert got[0] == pytest.approx(RHO * math.pi * h * (r1**2 + r1 * r2 + r2**2) / 3, rel=1e-13)
    assert got[1] == pytest.approx(
        h * (r1**2 + 2 * r1 * r2 + 3 * r2**2) / (4 * (r1**2 + r1 * r2 + r2**2)), rel=1e-13)
    # The CM sits towards the wide end.
    assert got[1] > h / 2


def test_full_cone_closed_form():
    radius, h = 0.03, 0.4
    mass, z_cm, transverse, axial = mass_properties([0.0, h], [0.0, radius], RHO)
    m = RHO * math.pi * radius**2 * h / 3
    assert mass == pytest.approx(m, rel=1e-13)
    assert z_cm == pytest.approx(3 * h / 4, rel=1e-13)
    assert transverse == pytest.approx(m * (3 * radius**2 / 20 + 3 * h**2 / 80), rel=1e-12)
    assert axial == pytest.approx(3 * m * radius**2 / 10, rel=1e-13)


def test_many_segments_against_brute_force():
    rng = np.random.default_rng(7)
    z = np.cumsum(rng.uniform(0.005, 0.04, size=40)) - 0.3
    r = rng.uniform(0.0, 0.035, size=40)
    got = mass_properties(z, r, RHO)
    want = _brute_force(z, r, RHO)
    np.testing.assert_allclose(got[0], want[0], rtol=1e-7)
    np.testing.assert_allclose(got[1], want[1], atol=1e-9)
    np.testing.assert_allclose(got[2:], want[2:], rtol=1e-7)


def test_density_scales_linearly():
    z, r = [0.0, 0.3, 0.8], [0.01, 0.02, 0.03]
    a = mass_properties(z, r, 500.0)
    b = mass_properties(z, r, 1000.0)
    assert b[0] == pytest.approx(2 * a[0], rel=1e-14)
    assert b[1] == pytest.approx(a[1], rel=1e-14)
    assert b[2] == pytest.approx(2 * a[2], rel=1e-14)
    assert b[3] == pytest.approx(2 * a[3], rel=1e-14)


# --- frame invariance ------------------------------------------------------------------

PROFILE_Z = np.array([0.0, 0.05, 0.2, 0.45, 0.6, 0.84])
PROFILE_R = np.array([0.025, 0.013, 0.014, 0.025, 0.032, 0.032])


def test_shift_invariance():
    base = mass_properties(PROFILE_Z, PROFILE_R, RHO)
    shifted = mass_properties(PROFILE_Z + 1.234, PROFILE_R, RHO)
    assert shifted[0] == pytest.approx(base[0], rel=1e-13)
    assert shifted[1] == pytest.approx(base[1] + 1.234, rel=1e-13)
    assert shifted[2] == pytest.approx(base[2], rel=1e-10)
    assert shifted[3] == pytest.approx(base[3], rel=1e-13)


def test_flip_invariance():
    base = mass_properties(PROFILE_Z, PROFILE_R, RHO)
    flipped = mass_properties(-PROFILE_Z[::-1], PROFILE_R[::-1], RHO)
    assert flipped[0] == pytest.approx(base[0], rel=1e-13)
    assert flipped[1] == pytest.approx(-base[1], rel=1e-13)
    assert flipped[2] == pytest.approx(base[2], rel=1e-12)
    assert flipped[3] == pytest.approx(base[3], rel=1e-13)


def test_from_knob_table_puts_origin_at_cm_and_barrel_at_plus_z():
    bat = BatProfile.from_knob_table(PROFILE_Z, 2 * PROFILE_R, RHO)
    mass, z_cm, transverse, axial = mass_properties(PROFILE_Z, PROFILE_R, RHO)
    assert mass_properties(bat.z, bat.r, RHO)[1] == pytest.approx(0.0, abs=1e-15)
    assert bat.cm_from_knob == pytest.approx(z_cm, rel=1e-14)
    assert bat.knob_end == pytest.approx(-z_cm, rel=1e-14)
    assert bat.barrel_end == pytest.approx(0.84 - z_cm, rel=1e-14)
    assert bat.cm_from_barrel == pytest.approx(0.84 - z_cm, rel=1e-14)
    assert bat.length == pytest.approx(0.84, rel=1e-14)
    # The barrel (wide end, r = 0.032) is at +z, the handle/knob at -z.
    assert bat.radius(bat.barrel_end) == pytest.approx(0.032, rel=1e-14)
    assert bat.radius(bat.knob_end) == pytest.approx(0.025, rel=1e-14)
    assert bat.mass == pytest.approx(mass, rel=1e-14)
    assert bat.transverse_inertia == pytest.approx(transverse, rel=1e-12)
    assert bat.axial_inertia == pytest.approx(axial, rel=1e-14)
    assert bat.mass_properties() == (bat.mass, bat.transverse_inertia, bat.axial_inertia)
    assert bat.density == RHO


def test_from_knob_table_accepts_a_table_listed_from_the_barrel():
    forward = BatProfile.from_knob_table(PROFILE_Z, 2 * PROFILE_R, RHO)
    backward = BatProfile.from_knob_table(PROFILE_Z[::-1], 2 * PROFILE_R[::-1], RHO)
    np.testing.assert_allclose(backward.z, forward.z, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(backward.r, forward.r)


def test_profile_is_frozen_and_read_only():
    bat = BatProfile.from_knob_table(PROFILE_Z, 2 * PROFILE_R, RHO)
    with pytest.raises(AttributeError):
        bat.mass = 1.0
    with pytest.raises(ValueError):
        bat.r[0] = 1.0


def test_direct_construction_requires_cm_at_origin():
    BatProfile(z=[-0.4, 0.4], r=[0.03, 0.03], density=RHO)  # a centred cylinder is fine
    with pytest.raises(ValueError, match="centre of mass"):
        BatProfile(z=[0.0, 0.8], r=[0.03, 0.03], density=RHO)


# --- interpolation ---------------------------------------------------------------------

def test_radius_interpolates_nodes_and_is_nan_outside():
    bat = r161_profile()
    np.testing.assert_allclose(bat.radius(bat.z), bat.r, rtol=1e-14, atol=0)
    assert math.isnan(bat.radius(bat.barrel_end + 1e-3))
    assert math.isnan(bat.slope(bat.knob_end - 1e-3))
    assert isinstance(bat.radius(0.1), float)
    assert bat.radius(np.array([0.0, 0.1])).shape == (2,)


def test_slope_is_continuous_at_nodes():
    bat = r161_profile()
    eps = 1e-9
    interior = bat.z[1:-1]
    left = bat.slope(interior - eps)
    right = bat.slope(interior + eps)
    # PCHIP is C^1: no jump at the nodes (a piecewise-linear r would jump by up to ~0.75).
    np.testing.assert_allclose(left, right, rtol=0, atol=1e-5)
    linear_jumps = np.abs(np.diff(np.diff(bat.r) / np.diff(bat.z)))
    assert linear_jumps.max() > 0.5


def test_slope_matches_finite_difference_and_sign():
    bat = r161_profile()
    z = np.linspace(bat.knob_end + 0.01, bat.barrel_end - 0.01, 301)
    h = 1e-6
    fd = (bat.radius(z + h) - bat.radius(z - h)) / (2 * h)
    np.testing.assert_allclose(bat.slope(z), fd, rtol=0, atol=1e-5)
    # The profile widens towards +z on the barrel taper, 0.25 m from the barrel end...
    assert bat.slope(bat.barrel_end - 0.25) > 0.0
    # ...and a cylinder has zero slope everywhere.
    cyl = BatProfile(z=[-0.4, 0.0, 0.4], r=[0.03, 0.03, 0.03], density=RHO)
    np.testing.assert_allclose(cyl.slope(np.linspace(-0.4, 0.4, 9)), 0.0, atol=1e-15)


def test_pchip_preserves_monotonicity_between_nodes():
    # Shape preservation: no overshoot on the barrel taper, where the data are monotonic.
    bat = r161_profile()
    sel = (bat.z > -0.20) & (bat.z < 0.20)
    z = np.linspace(bat.z[sel][0], bat.z[sel][-1], 2001)
    assert np.all(np.diff(bat.r[sel]) > 0)
    assert np.all(np.diff(bat.radius(z)) >= 0)


# --- the R161 preset ------------------------------------------------------------------

def test_r161_preset(capsys):
    bat = r161_profile()
    with capsys.disabled():
        print(
            f"\nR161 at {bat.density:g} kg/m^3: mass {bat.mass:.4f} kg, "
            f"CM {bat.cm_from_knob:.4f} m from knob / {bat.cm_from_barrel:.4f} m from barrel, "
            f"I_t {bat.transverse_inertia:.5f} kg m^2, I_3 {bat.axial_inertia:.4e} kg m^2"
        )
    assert bat.length == pytest.approx(0.84, abs=1e-12)
    assert 0.7 <= bat.mass <= 1.1
    assert 0.50 <= bat.cm_from_knob <= 0.65
    assert bat.cm_from_knob + bat.cm_from_barrel == pytest.approx(0.84, abs=1e-12)
    # Same ballpark as the Sec. V bat of the paper (I_t = 0.046, I_3 = 4.39e-4 kg m^2).
    assert 0.035 <= bat.transverse_inertia <= 0.06
    assert 2e-4 <= bat.axial_inertia <= 6e-4
    # Barrel radius 64.3 mm / 2 at the barrel end, knob 50.5 mm / 2.
    assert bat.radius(bat.barrel_end) == pytest.approx(0.03215, rel=1e-12)
    assert bat.radius(bat.knob_end) == pytest.approx(0.02525, rel=1e-12)
    # The exact integration agrees with a brute-force one on the same nodes.
    want = _brute_force(bat.z, bat.r, bat.density)
    assert bat.mass == pytest.approx(want[0], rel=1e-8)
    assert bat.transverse_inertia == pytest.approx(want[2], rel=1e-8)
    assert bat.axial_inertia == pytest.approx(want[3], rel=1e-8)


def test_r161_density_scales_mass_not_geometry():
    light, heavy = r161_profile(600.0), r161_profile(700.0)
    assert heavy.mass / light.mass == pytest.approx(700 / 600, rel=1e-13)
    np.testing.assert_allclose(heavy.z, light.z, rtol=0, atol=1e-15)


def test_loader_reads_the_table_as_given():
    distance, diameter = read_profile_tsv(data_file("r161_profile.tsv"))
    assert distance.size == 84
    assert distance[0] == pytest.approx(0.01) and distance[-1] == pytest.approx(0.84)
    assert diameter[0] == pytest.approx(0.0505) and diameter[-1] == pytest.approx(0.0643)
    bat = load_profile_tsv(data_file("r161_profile.tsv"))
    # Without the preset's knob face (0-1 cm) the bat spans the tabulated 0.83 m.
    assert bat.length == pytest.approx(0.83, abs=1e-12)
    assert bat.mass < r161_profile().mass


# --- bad input --------------------------------------------------------------------------

@pytest.mark.parametrize(
    "z, r, density, name",
    [
        ([0.0, 0.5, 0.4], [0.01, 0.02, 0.03], RHO, "z"),       # not increasing
        ([0.0, 0.5, 0.5], [0.01, 0.02, 0.03], RHO, "z"),       # repeated node
        ([0.0, 0.5, 0.8], [0.01, -0.02, 0.03], RHO, "r"),      # negative radius
        ([0.0, 0.5, 0.8], [0.01, 0.02], RHO, "z and r"),       # mismatched lengths
        ([0.0, 0.5], [0.01, 0.02], 0.0, "density"),            # zero density
        ([0.0, 0.5], [0.01, 0.02], -649.0, "density"),         # negative density
        ([0.0, 0.5], [0.01, 0.02], math.nan, "density"),       # NaN density
        ([0.0, math.nan], [0.01, 0.02], RHO, "z"),             # NaN node
        ([0.0], [0.01], RHO, "z"),                             # a single node
        ([0.0, 0.5], [0.0, 0.0], RHO, "r"),                    # no volume
        ([[0.0, 0.5]], [[0.01, 0.02]], RHO, "z"),              # not 1-D
    ],
)
def test_bad_input_names_the_argument(z, r, density, name):
    with pytest.raises(ValueError, match=rf"^{name}:"):
        mass_properties(z, r, density)


def test_from_knob_table_bad_input():
    with pytest.raises(ValueError, match="^distance_from_knob_m"):
        BatProfile.from_knob_table([0.0, 0.3, 0.2], [0.05, 0.03, 0.06], RHO)
    with pytest.raises(ValueError, match="^diameter_m"):
        BatProfile.from_knob_table([0.0, 0.3, 0.6], [0.05, -0.03, 0.06], RHO)
    with pytest.raises(ValueError, match="lengths differ"):
        BatProfile.from_knob_table([0.0, 0.3, 0.6], [0.05, 0.03], RHO)
    with pytest.raises(ValueError, match="^density"):
        BatProfile.from_knob_table([0.0, 0.3, 0.6], [0.05, 0.03, 0.06], -1.0)


@pytest.mark.parametrize(
    "body, where",
    [
        ("# c\n1\t50\n2\tabc\n", r"line 3: column 2 \(diameter \(mm\)\): not a number: 'abc'"),
        ("1\t50\nx\t50\n", r"line 2: column 1 \(distance from knob \(cm\)\): not a number"),
        ("1\t50\n2\t50\t7\n", r"line 2: expected 2 columns"),
        ("1\t50\n2\t-5\n", r"line 2: column 2 \(diameter \(mm\)\): must be >= 0"),
        ("1\t50\n3\t50\n2\t50\n", r"line 3: column 1 .*must increase.*line 2"),
        ("1\t50\n2\tnan\n", r"line 2: column 2 .*must be finite"),
        ("# only a comment\n1\t50\n", r"needs at least 2 data rows, got 1"),
    ],
)
def test_loader_errors_name_file_line_and_column(tmp_path, body, where):
    path = tmp_path / "bad_profile.tsv"
    path.write_text(body)
    with pytest.raises(ValueError, match=rf"bad_profile\.tsv: {where}"):
        load_profile_tsv(path)


def test_loader_skips_comments_and_blank_lines(tmp_path):
    path = tmp_path / "cyl.tsv"
    path.write_text("# a 60 cm cylinder\n\n0\t60\n  # indented comment\n60\t60\n")
    bat = load_profile_tsv(path, density=RHO)
    assert bat.length == pytest.approx(0.6)
    assert bat.mass == pytest.approx(RHO * math.pi * 0.03**2 * 0.6, rel=1e-13)


def test_loader_bad_density_names_file(tmp_path):
    path = tmp_path / "cyl.tsv"
    path.write_text("0\t60\n60\t60\n")
    with pytest.raises(ValueError, match=r"cyl\.tsv: density"):
        load_profile_tsv(path, density=0.0)


def test_surfaces_are_bit_identical_to_scipys_pchip():
    """The profile's own PCHIP (coefficients in numpy, evaluation jitted and parallel, no
    scipy at start-up) gives exactly scipy's PchipInterpolator values: at the nodes,
    between them, at the ends and off them (NaN)."""
    from scipy.interpolate import PchipInterpolator

    p = r161_profile()
    spline = PchipInterpolator(p.z, p.r, extrapolate=False)
    z = np.concatenate([np.linspace(p.knob_end - 0.01, p.barrel_end + 0.01, 20_001), p.z,
                        np.nextafter(p.z, np.inf), np.nextafter(p.z, -np.inf)])
    radius, slope = p.surfaces(z)
    assert np.array_equal(radius, spline(z), equal_nan=True)
    assert np.array_equal(slope, spline.derivative()(z), equal_nan=True)
    assert np.array_equal(p.radius(z), radius, equal_nan=True)
    assert p.radius(float(p.z[3])) == float(spline(p.z[3]))
    inside = (z >= p.knob_end) & (z <= p.barrel_end)
    assert not np.isnan(radius[inside]).any() and np.isnan(radius[~inside]).all()


@pytest.mark.parametrize("seed", range(40))
def test_pchip_coefficients_are_scipys(seed):
    """Random node sets, with flat stretches, turns and two-node tables."""
    from scipy.interpolate import PchipInterpolator

    from mcbat.bodies.profile import pchip_coefficients

    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 25))
    z = np.sort(rng.random(n)) + np.arange(n)
    r = np.where(rng.random(n) < 0.3, 0.5, rng.random(n))
    assert np.array_equal(pchip_coefficients(z, r), PchipInterpolator(z, r).c)


@pytest.mark.parametrize("seed", range(6))
def test_surfaces_on_uneven_nodes_are_scipys(seed):
    """The interval lookup (a cell table, then steps) on tables whose nodes cluster: dense
    runs of nodes share a cell, long gaps span many cells."""
    from scipy.interpolate import PchipInterpolator

    rng = np.random.default_rng(seed)
    gaps = np.where(rng.random(60) < 0.7, rng.random(60) * 1e-4, rng.random(60) * 0.05)
    distance = np.concatenate([[0.0], np.cumsum(gaps + 1e-6)])
    diameter = 0.03 + 0.04 * rng.random(distance.size)
    p = BatProfile.from_knob_table(distance, diameter, density=700.0)
    spline = PchipInterpolator(p.z, p.r, extrapolate=False)
    z = np.concatenate([rng.uniform(p.knob_end, p.barrel_end, 50_000), p.z,
                        np.nextafter(p.z, np.inf), np.nextafter(p.z, -np.inf)])
    radius, slope = p.surfaces(z)
    assert np.array_equal(radius, spline(z), equal_nan=True)
    assert np.array_equal(slope, spline.derivative()(z), equal_nan=True)
    few = p.surfaces(z[-500:])  # (a few positions: the one-thread loop)
    assert np.array_equal(few[0], radius[-500:], equal_nan=True)
    assert np.array_equal(few[1], slope[-500:], equal_nan=True)
