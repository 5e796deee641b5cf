"""The flight model's draw model: measured distances of batted balls against the flight
kernel, for ``mcbat.stats.fit.likelihood.Likelihood``.

A row of the table is one batted ball: its launch (``launch_speed`` mph, ``launch_angle``,
``spray_angle`` deg), the spin it is flown with (``backspin``, ``sidespin`` rpm: a spin
model's, since tracking data publish none), the park's ``elevation`` (ft), the height at
which the measurement was taken (``landing_height`` ft: 0 for the ground, a catch height
for a caught ball) and the measured ``hit_distance_sc`` (ft) with its ``hit_distance_sc_err``
(1 sigma, ft: the per-ball scatter about the model, ``docs/flight.md`` says how it is set).

The free parameters scale the model's drag and lift (``drag_scale`` multiplies the
spin-free ``C_D0``, ``lift_scale`` the lift coefficient; ``mcbat/core/flight/README.md``).
The prediction of a row has no nuisance scatter (the launch is taken as measured), so the
draws of a row are identical: two per row, and the model's covariance is zero; the whole
scatter is the row's ``hit_distance_sc_err``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from mcbat.bodies import BALL_PRESETS, DEFAULT_BALL
from mcbat.core.units import M_PER_FT, M_S_PER_MPH, RAD_PER_DEG, RAD_S_PER_RPM
from mcbat.errors import InputError
from mcbat.stats.columns import column_roles
from mcbat.stats.models.draws import DrawModel
from mcbat.study.flight import FlightSettings, fly_launches

__all__ = ["AIR_COLUMNS", "FLIGHT_TABLE_COLUMNS", "FlightFitSetup", "FlightModel"]


FLIGHT_TABLE_COLUMNS = column_roles(
    input={"launch_speed": "mph", "launch_angle": "deg", "spray_angle": "deg",
           "backspin": "rpm", "sidespin": "rpm", "elevation": "ft", "landing_height": "ft"},
    observable={"hit_distance_sc": "ft"},
    optional={"temperature": "degF", "pressure": "inHg", "relative_humidity": "%",
              "wind_x": "m/s", "wind_y": "m/s"})
"""Columns of a flight measurement table (Statcast's names and units). The optional ones
are each ball's air (game-time temperature, barometric pressure corrected to sea level,
relative humidity, wind in the field frame); where absent, the settings'."""
AIR_COLUMNS = tuple(c for c, (_, role) in FLIGHT_TABLE_COLUMNS.items() if role == "optional")


@dataclasses.dataclass(frozen=True)
class FlightFitSetup:
    """What a flight fit holds fixed: the flight settings (atmosphere other than the
    elevation, model, launch point, spin decay) and the ball. Plays the part of a study
    for ``mcbat.stats.fit.likelihood.Likelihood``."""

    settings: FlightSettings = FlightSettings()
    mass: float = BALL_PRESETS[DEFAULT_BALL].mass
    radius: float = BALL_PRESETS[DEFAULT_BALL].radius
    name: str = "flight"
    kind: str = "flight"
    inputs: dict = dataclasses.field(default_factory=dict)


class FlightModel(DrawModel):
    """The flight kernel on a table of batted balls with measured distances (module doc)."""

    COLUMNS = FLIGHT_TABLE_COLUMNS
    KIND = "flight"
    PARAMETERS = {"drag_scale": "drag_scale", "lift_scale": "lift_scale"}
    DEFAULT_DRAWS = 2
    """The prediction of a row is deterministic: two identical draws (the least the
    likelihood takes), zero model covariance."""
    SEARCH = {"drag_scale": (0.5, 1.5), "lift_scale": (0.0, 2.0)}
    """The coarse grid: drag within +-50 % of the calculator's, lift from none to twice."""
    FAILURE_HINTS = {}

    def __init__(self, study, table, draws, seed, fixed=None):
        super().__init__(study, table, draws, seed, fixed)
        missing = [c for c, (_, role) in self.COLUMNS.items()
                   if role == "input" and c not in table.columns]
        if missing:
            raise InputError(missing[0], "missing required column", self.source)
        if "hit_distance_sc_err" not in table.columns:
            raise InputError("hit_distance_sc_err", "missing required column: the per-ball "
                             "scatter of the distances about the model (ft)", self.source)
        si = {"launch_speed": M_S_PER_MPH, "launch_angle": RAD_PER_DEG,
              "spray_angle": RAD_PER_DEG, "backspin": RAD_S_PER_RPM,
              "sidespin": RAD_S_PER_RPM, "elevation": M_PER_FT, "landing_height": M_PER_FT}
        self._launch = {c: table[c].to_numpy(float) * k for c, k in si.items()}
        self._air = {}
        if "temperature" in table.columns:
            self._air["temperature"] = (table["temperature"].to_numpy(float) - 32.0) / 1.8 \
                + 273.15
        if "pressure" in table.columns:
            self._air["pressure"] = table["pressure"].to_numpy(float) * 3386.389
        for column in ("relative_humidity", "wind_x", "wind_y"):
            if column in table.columns:
                self._air[column] = table[column].to_numpy(float)
        self.parameters = {"drag_scale": study.settings.drag_scale,
                           "lift_scale": study.settings.lift_scale}
        self.set_parameters(fixed or {})

    def set_parameters(self, values):
        """Set ``drag_scale`` and ``lift_scale``."""
        for name, value in values.items():
            self.parameters[self.PARAMETERS[name]] = float(value)

    def solve(self):
        """Fly every row once (its draws are identical): ``{"hit_distance_sc": ft}`` per
        draw and the kernel's status."""
        settings = dataclasses.replace(self.study.settings, **self.parameters)
        launch = self._launch
        out, status = fly_launches(settings, self.study.mass, self.study.radius,
                                   launch["launch_speed"], launch["launch_angle"],
                                   launch["spray_angle"], launch["backspin"],
                                   launch["sidespin"], elevation=launch["elevation"],
                                   landing_height=launch["landing_height"],
                                   per_ball=self._air)
        return ({"hit_distance_sc": np.repeat(out["hit_distance"] / M_PER_FT, self.draws)},
                np.repeat(status, self.draws))
