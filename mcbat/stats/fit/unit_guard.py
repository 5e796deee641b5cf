"""The unit guard: a fit refuses an observable in a unit other than its column's.

A column in another unit (launch speeds in m/s instead of mph, spins in rad/s instead of
rpm) is a scaled copy of the right one, and a fit would otherwise find parameters that
make it fit (``e*`` of 0.08 for speeds in m/s). Over the coarse grid that starts a fit the
model's predictions span what the study can give; a column whose median or whose rows lie
far outside that span is refused with a hint about its unit (``UNITS_HINT``).
"""

from __future__ import annotations

import math

import numpy as np

from mcbat.errors import InputError
from mcbat.stats.columns import UNITS_HINT
from mcbat.stats.models.draws import OUTLIER_SIGMA, rows_text

__all__ = ["MAGNITUDES", "MEDIAN_FACTOR", "MEDIAN_MAXIMUM", "SIGN_CONVENTION", "UNIT_SIGMA",
           "check_units"]

UNIT_SIGMA = 3.0
"""When half the rows of an observable or more lie this many sigma beyond every model
prediction over the search ranges, the column is refused with a hint about its unit (a
correct table has ~0.3 % of its rows that far from the true model)."""
MAGNITUDES = ("exit_speed", "launch_speed", "spin_rate")
"""Observables that are magnitudes: a wrong unit scales them, which the median shows."""
MEDIAN_FACTOR = 1.25
"""A magnitude column whose median lies beyond the model's medians over the search grid by
more than this factor is refused (m/s instead of mph: 2.24; km/h: 1.61; rpm/rad/s: 9.55)."""
MEDIAN_MAXIMUM = {"launch_speed": 125.0}
"""A magnitude column whose median lies above this (its unit) is in another unit whatever
the model gives: the fastest batted balls Statcast has measured are near 122 mph, so no
table of real balls has a median near 125 mph (km/h would put a typical 90 mph at 145)."""

SIGN_CONVENTION = {
    "scattering_angle": "atan2(v_y, v_x) of the outgoing ball in degrees, positive towards "
                        "+y (docs/physics.md)",
    "spin_out": "the spin about the bat's axis +z in rad/s (docs/physics.md)",
    "launch_angle": "the elevation in degrees, positive upwards",
    "spray_angle": "in degrees, positive towards right field (docs/batting.md)",
    "backspin": "in rpm, positive for backspin (docs/batting.md)",
    "sidespin": "in rpm, positive curving towards left field (docs/batting.md)",
}
"""The sign convention of each observable that can be negative, named when a column's
negatives fit where the column does not."""


def check_units(like):
    """Refuse an observable far outside anything the model predicted over the search grid.

    Parameters
    ----------
    like : mcbat.stats.fit.likelihood.Likelihood
        Evaluated over the search grid with ``like.envelope`` set (the range of its
        predictions, ``mcbat.stats.fit.search.search``).

    Raises
    ------
    InputError
        Naming the column: its median beyond the model's medians (a magnitude in another
        unit), half its rows far outside the predictions, or a row beyond
        ``mcbat.stats.models.draws.OUTLIER_SIGMA`` (a typo).
    """
    lo, hi, sd, med_lo, med_hi = like.envelope
    for j, col in enumerate(like.observables):
        y = like.y[:, j]
        if col in MAGNITUDES:
            # A column in another unit is a scaled copy of the right one: its median
            # lies outside the span of the model's medians over the whole search grid
            # by more than the model can stretch. The rows' own spread (nuisance
            # scatter of a game, ~10 mph) hides that from the row-by-row test below
            # when the table is small or the unit is close (m/s against mph).
            median = float(np.median(y))
            low, high = med_lo[j] / MEDIAN_FACTOR, med_hi[j] * MEDIAN_FACTOR
            if median > MEDIAN_MAXIMUM.get(col, math.inf):
                raise InputError(col, f"the measured median {median:.3g} "
                                 f"{like.units[col]} is faster than any batted ball "
                                 f"measured (about 122 mph): {UNITS_HINT[col]}",
                                 like.source)
            if not low <= median <= high:
                raise InputError(col, f"the measured median {median:.3g} "
                                 f"{like.units[col]} lies outside anything the model "
                                 f"gives for this study over the search grid (medians "
                                 f"{med_lo[j]:.3g}..{med_hi[j]:.3g} {like.units[col]}): "
                                 f"{UNITS_HINT[col]}", like.source)
        beyond = np.maximum(lo[:, j] - y, y - hi[:, j]) / sd[:, j]
        far = beyond > OUTLIER_SIGMA
        many = beyond > UNIT_SIGMA
        span = f"{np.min(lo[:, j]):.3g}..{np.max(hi[:, j]):.3g} {like.units[col]}"
        if many.sum() >= 0.5 * like.rows:
            # A column of the opposite sign convention is a mirror image, not a scaled
            # copy: its negatives fit where it does not, and the unit is not the fault.
            flipped = np.maximum(lo[:, j] + y, -y - hi[:, j]) / sd[:, j]
            hint = UNITS_HINT[col]
            if (flipped > UNIT_SIGMA).sum() < 0.5 * like.rows:
                hint = (f"their negatives would fit: the sign flipped? {col} is "
                        f"{SIGN_CONVENTION.get(col, 'as docs/fitting.md defines it')}")
            raise InputError(col, f"{int(many.sum())} of {like.rows} rows lie far outside "
                             f"anything the model gives for this study (model "
                             f"{span}, measured median {np.median(y):.3g}): "
                             f"{hint}", like.source)
        if not far.any():
            continue
        raise InputError(col, f"{rows_text(far, y)}: more than {OUTLIER_SIGMA:g} sigma "
                         f"beyond anything the model gives for this study (model {span}): "
                         f"a typo or another unit? Fix or remove the row", like.source)
