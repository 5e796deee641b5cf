import dataclasses
import json

import pytest

from mcbat.stats.fit.intervals import Interval, _entry


def test_an_interval_reads_as_the_mapping_it_writes():
    iv = Interval(lower_error=0.01, upper_error=0.02, status="measured", open_at_95=1e-3)
    assert iv.to_dict() == {"lower_error": 0.01, "upper_error": 0.02, "status": "measured",
                            "limit": None, "at_bound": None, "open_at_95": 1e-3}
    assert list(iv) == list(iv.to_dict()) and dict(iv) == iv.to_dict()
    assert iv["upper_error"] == 0.02 and iv.get("limit_kind") is None and "limit_kind" not in iv
    with pytest.raises(KeyError):
        iv["limit_kind"]
    with pytest.raises(dataclasses.FrozenInstanceError):
        iv.status = "unidentified"


def test_a_one_sided_entry_keeps_its_keys_and_their_order():
    bounded = {"error": 0.05, "physical": False, "edge": 1e-3, "root": 0.55}
    flat = {"error": None, "physical": False, "edge": 2.0, "root": None}
    iv = _entry(bounded, flat, lambda sign, side: 0.52)
    assert isinstance(iv, Interval)
    assert (iv.status, iv.limit, iv.lower_error, iv.upper_error) == ("lower_limit", 0.52,
                                                                     0.05, None)
    assert json.dumps(iv.to_dict()) == ('{"lower_error": 0.05, "upper_error": null, '
                                        '"status": "lower_limit", "limit": 0.52, '
                                        '"at_bound": null}')
