"""Three-vectors as plain tuples, for allocation-free jitted kernels."""

import math

from mcbat.core.jit import njit

__all__ = ["add", "combine", "cross", "dot", "norm", "scale", "sub"]


@njit(inline="always")
def dot(a, b):
    """``a . b``."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(inline="always")
def cross(a, b):
    """``a x b``."""
    return (
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    )


@njit(inline="always")
def add(a, b):
    """``a + b``."""
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


@njit(inline="always")
def sub(a, b):
    """``a - b``."""
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


@njit(inline="always")
def scale(c, a):
    """``c a`` for a scalar ``c``."""
    return (c * a[0], c * a[1], c * a[2])


@njit(inline="always")
def norm(a):
    """``|a|``."""
    return math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])


@njit(inline="always")
def combine(c1, t1, c2, t2, c3, t3):
    """``c1 t1 + c2 t2 + c3 t3``: contact-frame components back to the lab frame."""
    return (
        c1 * t1[0] + c2 * t2[0] + c3 * t3[0],
        c1 * t1[1] + c2 * t2[1] + c3 * t3[1],
        c1 * t1[2] + c2 * t2[2] + c3 * t3[2],
    )
