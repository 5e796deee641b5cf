"""Cabo, Soler & González, "Scattering solution of a ball by a bat", Rev. Mex. Fís. 58
(2012): the Sec. V configuration (``mcbat.papers.cabo2012.sec5``, the one source of
its numbers), the calibration of ``e*``, the figures, the summary, and ``mcbat reproduce``.
"""

__all__ = []
