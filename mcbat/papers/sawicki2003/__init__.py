"""Sawicki, Hubbard & Stronge, "How to hit home runs: Optimum baseball bat swing parameters
for maximum range trajectories", Am. J. Phys. 71, 1152 (2003): the optimal-swing scan
(``mcbat.papers.sawicki2003.scan``) and ``mcbat reproduce sawicki2003``."""

__all__ = []
