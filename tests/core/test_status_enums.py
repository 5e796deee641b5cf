import numpy as np

from mcbat.core import status
from mcbat.core.contact_inference import solver
from mcbat.core.flight import trajectory
from mcbat.core.flight.trajectory import FlightStatus


def test_the_named_codes_hold_the_kernels_values():
    for member in status.ImpactStatus:
        assert getattr(status, member.name) == member.value
        assert type(getattr(status, member.name)) is int
    assert set(status.STATUS_NAMES) == {m.value for m in status.ImpactStatus}
    assert set(status.END_STATE_NAMES) == {m.value for m in status.EndState}
    for member in FlightStatus:
        assert type(getattr(trajectory, member.name)) is int
        assert getattr(trajectory, member.name) == member.value
    for member in solver.InferenceStatus:
        assert type(getattr(solver, member.name)) is int
        assert getattr(solver, member.name) == member.value
    assert set(solver.INFERENCE_STATUS_NAMES) == {m.value for m in solver.InferenceStatus}


def test_a_member_compares_with_a_status_array():
    codes = np.array([0, 1, 3], np.int8)
    assert (codes == FlightStatus.OK).tolist() == [True, False, False]
    assert (codes != status.ImpactStatus.OK).sum() == 2
