"""What a fit solves: the draw models of a measurement table's rows (``draws``: bat-frame
and game; ``flight``: measured distances against the flight kernel), the priors of the
measured inputs (``input_priors``) and a study's samples solved at given parameters
(``simulate``)."""

__all__ = []
