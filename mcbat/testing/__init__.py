"""Slow, independent reference solvers for tests and benchmarks (scipy ``solve_ivp`` with
event location). They import nothing from the jitted kernel."""

__all__ = []
