"""The per-row fit of a measurement table (``mcbat fit``): ``estimate`` (the fit itself:
``estimate.fit``, ``FitResult``), ``likelihood``, ``search``, ``intervals`` and the
one-sided limits of ``selective``, the unit guard, model comparison (``model_choice``),
the calibration of one parameter on one measured number (``calibrate``) and the residual
figure (``figure``)."""

__all__ = []
