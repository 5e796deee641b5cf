"""Units of study values (mcbat.study.units): exact conversion to SI, errors naming the key."""

import math

import numpy as np
import pytest

from mcbat.errors import InputError
from mcbat.study.units import UNITS, to_si
from tests.study.cases import study


def test_unit_conversions_exact():
    assert to_si(1, "mph", "speed") == 0.44704
    assert to_si(-90.0, "mph", "speed") == -40.2336
    assert to_si(0.1, "mm", "length") == 1e-4
    assert to_si(1, "in", "length") == 0.0254
    assert to_si(1.5, "in", "length") == 0.0381
    assert to_si(15, "cm", "length") == 0.15
    assert to_si(100, "cm", "length") == 1.0
    assert to_si(1, "ft", "length") == 0.3048
    assert to_si(36, "km/h", "speed") == 10.0
    assert to_si(1, "rpm", "spin") == 2 * math.pi / 60
    assert to_si(60, "rpm", "spin") == pytest.approx(2 * math.pi, rel=1e-15)
    assert to_si(1, "rps", "spin") == 2 * math.pi
    assert to_si(180, "deg", "angle") == pytest.approx(math.pi, rel=1e-15)
    assert to_si(2.0, None, "speed") == 2.0
    assert np.array_equal(to_si([1, 2], "cm", "length"), [0.01, 0.02])
    assert set(UNITS["length"]) == {"m", "cm", "mm", "in", "ft"}
    assert set(UNITS["speed"]) == {"m/s", "km/h", "mph", "ft/s"}
    assert set(UNITS["spin"]) == {"rad/s", "rpm", "rps"}
    assert set(UNITS["angle"]) == {"rad", "deg"}


def test_unit_errors_name_the_field():
    with pytest.raises(InputError, match=r"^ball_spin\.z: unit 'mph' is a speed unit"):
        to_si(1, "mph", "spin", "ball_spin.z")
    with pytest.raises(InputError, match=r"^contact\.axial: unknown unit 'furlong'"):
        to_si(1, "furlong", "length", "contact.axial")


def test_units_in_study():
    s = study(ball_velocity__x={"value": -90, "unit": "mph"},
              ball_spin__z={"dist": "choice", "values": [1800, -1200], "unit": "rpm"},
              contact__axial={"value": 15, "unit": "cm"},
              bat_velocity__y={"dist": "uniform", "low": 1, "high": 2, "unit": "ft/s"})
    cols = s.sample(0, 2000)
    assert np.all(cols["ball_vx_in"] == -40.2336)
    spins = np.unique(cols["ball_wz_in"])
    assert spins.size == 2
    assert spins == pytest.approx([-40 * math.pi, 60 * math.pi], rel=1e-15)
    assert np.all(cols["axial"] == 0.15)
    assert cols["bat_vy_in"].min() >= 0.3048 and cols["bat_vy_in"].max() < 0.6096
    cfg = {i["name"]: i for i in s.config()["inputs"]}
    assert cfg["ball_velocity.x"] == {"name": "ball_velocity.x", "quantity": "speed",
                                      "unit": "m/s", "dist": "fixed", "value": -40.2336}
