"""The measured table an inference reads (mcbat.inference.columns): a missing column or a
bad value refused with one line naming the column (and the row)."""

import numpy as np
import pytest

from mcbat.errors import InputError
from mcbat.inference import infer_spin
from tests.inference.known_contacts import simulate_balls as _simulate


def test_missing_column_names_it():
    balls, _ = _simulate(1, seed=9, measured_swing=False)
    with pytest.raises(InputError, match="^spray_angle: missing column"):
        infer_spin(balls.drop(columns="spray_angle"))


@pytest.mark.parametrize("column, value, message", [
    ("launch_speed", np.inf, "^launch_speed: must be finite"),
    ("pitch_speed", -3.0, "^pitch_speed: must be > 0 mph, got -3.0 in row 0"),
    ("launch_angle", 95.0, "^launch_angle: must lie within"),
    ("handedness", "S", '^handedness: must be "R" or "L"'),
    ("spin_rate", "fast", "^spin_rate: must be numbers"),
])
def test_bad_values_name_the_field(column, value, message):
    balls, _ = _simulate(2, seed=10, measured_swing=False)
    balls[column] = balls[column].astype(object)
    balls.loc[0, column] = value
    with pytest.raises(InputError, match=message):
        infer_spin(balls)
