"""The bodies: the ball, the bat (a cylinder at the contact, or a tapered profile), the
profiles and their tables, and the presets. One body model serves the single-impact API
(``mcbat.api``) and the studies (``mcbat.study``)."""

from mcbat.bodies.ball import Ball
from mcbat.bodies.bat import Bat
from mcbat.bodies.presets import BALL_PRESETS, BAT_PRESETS, DEFAULT_BALL, ball_preset, bat_preset
from mcbat.bodies.profile import BatProfile
from mcbat.bodies.tables import load_profile_tsv, r161_profile

__all__ = ["BALL_PRESETS", "BAT_PRESETS", "DEFAULT_BALL", "Ball", "Bat", "BatProfile",
           "ball_preset", "bat_preset", "load_profile_tsv", "r161_profile"]
