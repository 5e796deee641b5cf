"""Calibrate the restitution on one measured number, as the paper did, with a root finder.

The paper fixed its one free parameter by trial and error: the loss fraction ``e^2`` such
that the ball leaves at 1.44629 m/s after a drop at 4 m/s with no spin and a nearly
vanishing impact parameter (theta = pi/400). Here the same condition is solved for the
energetic coefficient ``e*`` with Brent's method; ``e^2 = 1 - e*^2``.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

from scipy.optimize import brentq, minimize_scalar

from mcbat.api import SolverSettings, solve
from mcbat.errors import InputError
from mcbat.papers.cabo2012 import sec5

__all__ = ["Calibration", "calibrate_restitution", "exit_speed"]


@dataclass(frozen=True)
class Calibration:
    """Result of ``calibrate_restitution`` (SI units)."""

    target_speed: float
    e_star: float
    loss_fraction: float
    exit_speed: float
    iterations: int
    theta: float
    w0: float

    def to_dict(self) -> dict:
        """The fields as a plain (JSON-serialisable) dict."""
        return asdict(self)


def exit_speed(e_star: float, theta: float = sec5.THETA_NEAR_ZERO, w0: float = 0.0,
               settings: SolverSettings | None = None) -> float:
    """Exit speed (m/s) of the Sec. V impact for an energetic coefficient ``e_star``.

    ``settings`` defaults to ``SolverSettings()``.
    """
    settings = SolverSettings() if settings is None else settings
    return solve(sec5.case(theta, w0, e=e_star), settings).exit_speed


def calibrate_restitution(target_speed: float = sec5.TARGET_SPEED,
                          theta: float = sec5.THETA_NEAR_ZERO, w0: float = 0.0,
                          xtol: float = 1e-13,
                          settings: SolverSettings | None = None) -> Calibration:
    """Find e* such that the Sec. V exit speed equals ``target_speed`` (m/s).

    The ball's exit speed is not monotonic in e*: at e* = 0 it leaves with the bat's
    contact point, and as e* grows its velocity passes through a minimum (near e* = 0.1 for
    Sec. V) before rising to the friction-only value at e* = 1. The rebound branch beyond
    the minimum is increasing, so the root is unique there and bracketed for Brent's
    method; a target outside that branch's range is an error. ``settings`` defaults to
    ``SolverSettings()``.
    """
    settings = SolverSettings() if settings is None else settings

    def speed(e):
        return exit_speed(e, theta, w0, settings)

    lowest = minimize_scalar(speed, bounds=(0.0, 1.0), method="bounded",
                             options={"xatol": 1e-10})
    e_low, lo_speed = float(lowest.x), float(lowest.fun)
    hi_speed = speed(1.0)
    if not lo_speed <= target_speed <= hi_speed:
        raise InputError("target_speed", f"must lie between {lo_speed:.6g} (the slowest "
                         f"rebound, e* = {e_low:.3g}) and {hi_speed:.6g} m/s (e* = 1), got "
                         f"{target_speed!r}")
    e_star, info = brentq(lambda e: speed(e) - target_speed, e_low, 1.0, xtol=xtol,
                          full_output=True)
    return Calibration(target_speed=float(target_speed), e_star=float(e_star),
                       loss_fraction=float(1.0 - e_star * e_star),
                       exit_speed=exit_speed(e_star, theta, w0, settings),
                       iterations=int(info.iterations), theta=float(theta), w0=float(w0))
