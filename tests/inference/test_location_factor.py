"""The inference kernel's restitution location factor is ``np.interp``'s value, bit for
bit, at every kind of point: inside, on the nodes, beyond both ends, NaN."""

import numpy as np

from mcbat.bodies.restitution import LOCATION_TABLES, location_table
from mcbat.core.contact_inference.solver import _location_factor


def test_the_location_factor_is_np_interp_bit_for_bit():
    rng = np.random.default_rng(4)
    for name in LOCATION_TABLES:
        z, f = location_table(name)
        points = np.concatenate([rng.uniform(z[0] - 0.05, z[-1] + 0.05, 2000), z,
                                 np.nextafter(z, -np.inf), np.nextafter(z, np.inf)])
        got = np.array([_location_factor(p, z, f) for p in points])
        assert np.array_equal(got.view(np.int64), np.interp(points, z, f).view(np.int64))
        assert np.isnan(_location_factor(np.nan, z, f))
    one_node = (np.array([0.1]), np.array([0.8]))
    assert _location_factor(0.5, *one_node) == 0.8
    assert _location_factor(0.3, np.empty(0), np.empty(0)) == 1.0
