"""The flight of the scan's batted balls (adapter to :mod:`mcbat.core.flight`)."""

FLIGHT_SETTINGS = {}


def fly(v, w):
    raise NotImplementedError
