"""Measured Statcast distances against the flight model: ``mcbat reproduce statcast``
and ``mcbat fit --flight`` (``docs/flight.md``)."""

__all__ = []
