"""The data fingerprint's check: every column bit for bit in the environment it was
recorded in; elsewhere the columns derived with numpy's arctan2 by their definition and
within a few ulps, the others still bit for bit."""

import numpy as np
import pytest

from validation import data_fingerprint

FP = data_fingerprint


@pytest.fixture
def columns():
    rng = np.random.default_rng(5)
    n = 3 * FP.SAMPLE_EVERY + 7
    vx, vy = rng.normal(size=n), rng.normal(size=n)
    vx[0] = vy[0] = np.nan  # a failed row, among the recorded ones
    angle = np.degrees(np.arctan2(vy, vx))
    return {"sample_id": np.arange(n), "ball_vx": vx, "ball_vy": vy,
            "scattering_angle": angle,
            "scattering_angle_measured": angle + rng.normal(0.0, 3.0, n),
            "exit_speed": np.hypot(vx, vy)}


def _moved(values, ulps):
    """``values`` moved ``ulps`` ulps up, row by row."""
    out = values.copy()
    for _ in range(ulps):
        out = np.nextafter(out, np.inf)
    return out


def test_unchanged_data_passes_in_either_environment(columns):
    record = FP.fingerprint(columns)
    assert FP.compare("d", record, columns, same_environment=True) == []
    assert FP.compare("d", record, columns, same_environment=False) == []


def test_a_bit_of_an_ordinary_column_fails_in_either_environment(columns):
    record = FP.fingerprint(columns)
    columns["exit_speed"] = _moved(columns["exit_speed"], 1)
    for same in (True, False):
        assert [line.split(":")[1].strip() for line in
                FP.compare("d", record, columns, same)] == ["exit_speed"]


def test_arctan2_columns_a_few_ulps_off_pass_only_in_another_environment(columns):
    """As if recorded on a CPU whose arctan2 (numpy's AVX-512 kernels) rounds otherwise."""
    there = dict(columns, scattering_angle=_moved(columns["scattering_angle"], 3),
                 scattering_angle_measured=_moved(columns["scattering_angle_measured"], 2))
    record = FP.fingerprint(there)
    assert len(FP.compare("d", record, columns, same_environment=True)) == 2
    assert FP.compare("d", record, columns, same_environment=False) == []


def test_arctan2_columns_beyond_the_tolerance_fail(columns):
    there = dict(columns, scattering_angle_measured=_moved(
        columns["scattering_angle_measured"], 4 * FP.ULPS))
    record = FP.fingerprint(there)
    lines = FP.compare("d", record, columns, same_environment=False)
    assert len(lines) == 1 and "scattering_angle_measured" in lines[0] and "ulps" in lines[0]


def test_a_scattering_angle_off_its_definition_fails(columns):
    """Within the ulps at the recorded rows, but not what its inputs give."""
    record = FP.fingerprint(columns)
    changed = dict(columns, scattering_angle=columns["scattering_angle"].copy())
    changed["scattering_angle"][1] += 1.0  # not a recorded row (every SAMPLE_EVERY-th)
    lines = FP.compare("d", record, changed, same_environment=False)
    assert lines == ["d: scattering_angle: not its definition of unchanged inputs"]


def test_the_record_names_its_environment():
    env = FP.environment()
    assert {"numpy", "numba", "python", "machine", "cpu", "numpy_simd"} <= set(env)
    assert env["numpy"] == np.__version__


def test_the_shipped_studies_datasets_are_as_recorded(capsys):
    """Every column of every shipped study's dataset, bit for bit as recorded in
    ``validation/data_fingerprint.json``: a change that is meant to leave behaviour alone
    (a refactor) must leave these hashes alone; a change of the data re-records them
    (``python -m validation data_fingerprint --record``) and says why in its commit."""
    import json

    record = json.loads((FP.ROOT / "validation" / "data_fingerprint.json").read_text())
    if {k: record["environment"].get(k) for k in FP.environment()} != FP.environment():
        pytest.skip("recorded in another environment (CPU, numpy or numba): bit identity "
                    "is checked where the record was made")
    assert set(record["datasets"]) == set(FP.DATASETS)
    assert FP.main(["--check", str(FP.ROOT / "validation" / "data_fingerprint.json")]) == 0, \
        capsys.readouterr().out
