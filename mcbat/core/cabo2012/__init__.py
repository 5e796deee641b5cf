"""Rigid ball-bat impact with Coulomb friction, integrated in the normal impulse.

Cabo, Soler & Gonzalez, "Scattering solution of a ball by a bat" (Rev. Mex. Fis. 58, 2012),
in the consistent matrix form of ``README.md`` (the paper's printing errors corrected).
"""

from mcbat.core.cabo2012.contact import solve_contact, stick_impulse_rate
from mcbat.core.cabo2012.impact import IMPACT_FIELDS, solve_impact

__all__ = ["IMPACT_FIELDS", "solve_contact", "solve_impact", "stick_impulse_rate"]
