"""Measured Statcast distances against the flight model: ``mcbat reproduce statcast``
(``docs/flight.md``)."""
