"""Tangential compliance: Cross & Nathan's tangential restitution ``e_x``, in 3D.

R. Cross and A. M. Nathan, "Scattering of a baseball by a bat", Am. J. Phys. 74, 896
(2006). See ``README.md`` for the model and how it extends the rigid solution.
"""

from mcbat.core.cross_nathan2006.tangential import tangential_rebound

__all__ = ["tangential_rebound"]
