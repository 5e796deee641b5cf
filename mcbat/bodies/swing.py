"""Defaults of the swing that stand for the batter's body: the rotation centre of the bat
(the swing model is ``mcbat.core.swing``)."""

__all__ = ["DEFAULT_PIVOT"]

#: Distance of the swing's rotation centre from the knob (m): 6 in. The bat-performance
#: standards pivot the bat 6 in from the knob (NCAA BBCOR, ASTM F2844), and Nathan et al.,
#: Sports Eng. 13, 153 (2011) find the swing close to a rotation about a point near the
#: knob.
DEFAULT_PIVOT = 0.1524
