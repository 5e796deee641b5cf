"""Restitution that depends on the impact speed and on where the ball hits the bat."""

from mcbat.core.restitution.forms import energetic_restitution

__all__ = ["energetic_restitution"]
