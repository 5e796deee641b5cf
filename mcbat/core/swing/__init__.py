"""The game situation: field frame <-> bat frame, and the game kernel around
``mcbat.core.cabo2012.solve_impact`` (equations and sources in ``README.md``).

The modules are the interface: ``frames`` (the bodies, the pitch, the swing and the
frames) and ``game`` (the game kernel and its rows). Above the core, ``mcbat.solving``
calls them.
"""

__all__ = []  # the modules are the interface
