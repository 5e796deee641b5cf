"""The contact behind a measured batted ball: the game model run backwards by a damped
Newton iteration (equations, identification and assumptions in ``README.md``).

The modules are the interface: ``solver`` (the batch kernel, its settings and status
codes). Above the core, ``mcbat.solving`` calls it.
"""

__all__ = []  # the modules are the interface
