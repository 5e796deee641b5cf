"""Shared test helpers: the paper's Sec. V configuration and a dict view of the kernel."""

import math

import pytest
from hypothesis import settings

# CI replays the same examples every run; `--hypothesis-profile=explore` searches afresh.
settings.register_profile("ci", derandomize=True)
settings.register_profile("explore", max_examples=2000)
settings.load_profile("ci")

from mcbat.core.cabo2012 import IMPACT_FIELDS, solve_impact

# Sec. V of Cabo, Soler & Gonzalez (PHYSICS.md): Cross & Nathan's drop test.
SEC5 = dict(
    ball_mass=0.145, ball_radius=0.036, ball_inertia_factor=0.4,
    bat_mass=0.989, bat_transverse_inertia=0.0460, bat_axial_inertia=4.39e-4,
    axial=0.115, radius=0.03335, slope=0.0,
)
SEC5_THETA = math.pi / 400
SEC5_LOSS_FRACTION = 0.6183822  # the paper's calibrated e^2


def kernel(ball_v=(-4.0, 0.0, 0.0), ball_w=(0.0, 0.0, 0.0), bat_v=(0.0, 0.0, 0.0),
           bat_w=(0.0, 0.0, 0.0), angle=SEC5_THETA, mu=0.5, e=1.0, e_x=0.0, settings=(), **overrides):
    """Run ``solve_impact`` on the Sec. V bodies (with overrides); return a dict."""
    p = {**SEC5, **overrides}
    out = solve_impact(
        p["ball_mass"], p["ball_radius"], p["ball_inertia_factor"],
        p["bat_mass"], p["bat_transverse_inertia"], p["bat_axial_inertia"],
        p["axial"], angle, p["radius"], p["slope"],
        *ball_v, *ball_w, *bat_v, *bat_w, mu, e, e_x, *settings)
    return dict(zip(IMPACT_FIELDS, out))


@pytest.fixture
def sec5():
    return dict(SEC5)
