"""Batted-ball flight in the field frame (Nathan's trajectory calculator's model and
others): air density, aerodynamic coefficients, the integrator (``README.md``).

The modules are the interface: ``atmosphere`` (air density), ``aero`` (the
coefficients) and ``trajectory`` (the integrator and the batch kernels). Above the core,
``mcbat.solving`` calls them.
"""

__all__ = []  # the modules are the interface
