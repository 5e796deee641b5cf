"""Slow, independent reference solvers for tests and benchmarks (scipy ``solve_ivp`` with
event location). They import nothing from the jitted kernel; the harnesses that run the
kernel and the fit against them are in the top-level ``harness/`` package."""

__all__ = []
