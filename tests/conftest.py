"""Shared test helpers: the paper's Sec. V configuration and a dict view of the kernel."""

import functools
import os
from pathlib import Path

import numba
import pytest
from hypothesis import settings

# CI replays the same examples every run; `--hypothesis-profile=explore` searches afresh.
settings.register_profile("ci", derandomize=True)
settings.register_profile("explore", max_examples=2000)
settings.load_profile("ci")

from mcbat.core.cabo2012 import IMPACT_FIELDS, solve_impact  # noqa: E402
from mcbat.core.cabo2012.contact import DEFAULT_ACCURACY, Accuracy  # noqa: E402
from mcbat.core.cabo2012.impact import ImpactInputs  # noqa: E402
from mcbat.papers.cabo2012 import sec5  # noqa: E402

#: The repository's root (studies/, data/, benchmarks/).
ROOT = Path(__file__).resolve().parent.parent

# Sec. V of Cabo, Soler & Gonzalez (docs/physics.md): Cross & Nathan's drop test, from the
# package's one source of its numbers.
SEC5 = dict(
    ball_mass=sec5.BALL.mass, ball_radius=sec5.BALL.radius,
    ball_inertia_factor=sec5.BALL.inertia_factor, bat_mass=sec5.BAT.mass,
    bat_transverse_inertia=sec5.BAT.transverse_inertia,
    bat_axial_inertia=sec5.BAT.axial_inertia, axial=sec5.AXIAL, radius=sec5.BAT.radius,
    slope=0.0,
)
SEC5_THETA = sec5.THETA_NEAR_ZERO
SEC5_LOSS_FRACTION = sec5.LOSS_FRACTION  # the paper's calibrated e^2


def kernel(ball_v=(-4.0, 0.0, 0.0), ball_w=(0.0, 0.0, 0.0), bat_v=(0.0, 0.0, 0.0),
           bat_w=(0.0, 0.0, 0.0), angle=SEC5_THETA, mu=0.5, e=1.0, e_x=0.0, settings=(),
           **overrides):
    """Run ``solve_impact`` on the Sec. V bodies (with overrides); return a dict."""
    p = {**SEC5, **overrides}
    out = solve_impact(ImpactInputs(
        p["ball_mass"], p["ball_radius"], p["ball_inertia_factor"],
        p["bat_mass"], p["bat_transverse_inertia"], p["bat_axial_inertia"],
        p["axial"], angle, p["radius"], p["slope"],
        *ball_v, *ball_w, *bat_v, *bat_w, mu, e, e_x),
        Accuracy(*settings) if settings else DEFAULT_ACCURACY)
    return dict(zip(IMPACT_FIELDS, out))


@pytest.fixture
def sec5():
    return dict(SEC5)


@pytest.fixture
def cli(capsys, monkeypatch):
    """Run ``mcbat`` in this process (tests/cli_runner.py):
    ``cli("run", path, "--quiet", stdin=b"...", cwd=tmp_path)`` -> code, stdout, stderr."""
    from tests.cli_runner import run_in_process

    return functools.partial(run_in_process, capsys, monkeypatch)


# pytest-xdist's workers share the machine's cores: each gives numba's parallel loops its
# share of them (one on CI's two cores with two workers), not all of them. The kernels'
# threads wait for each other at the end of every parallel loop, so oversubscribed cores
# slow down most what the fits do thousands of times: small batches.
WORKER_THREADS = max(1, numba.config.NUMBA_NUM_THREADS
                     // int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")))


@pytest.fixture(autouse=True)
def _numba_threads_of_this_worker():
    """Every test starts with :data:`WORKER_THREADS` numba threads (a test that sets
    another count explicitly keeps it for its own duration)."""
    numba.set_num_threads(WORKER_THREADS)
