"""mcbat.solve_frame: a DataFrame of inputs -> the rows mcbat run writes, in memory."""

import numpy as np
import pandas as pd
import pytest

import mcbat
from mcbat.core.batch import INPUT_FIELDS
from mcbat.dataset.schema import COLUMNS, UNITS
from mcbat.errors import InputError
from tests.conftest import ROOT


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    out = tmp_path_factory.mktemp("frame") / "throughput"
    # The wide mix: every end state, tapered contacts, failed rows (not approaching).
    mcbat.run(ROOT / "studies" / "throughput.toml", out, samples=20_000, seed=3,
              chunk_size=7_000, progress=False)
    return mcbat.load(out)


def test_solve_frame_returns_exactly_the_rows_mcbat_run_writes(dataset):
    assert (dataset["status"] != 0).any() and dataset["end_state"].nunique() == 2
    inputs = dataset[[c for c in dataset.columns if c in INPUT_FIELDS or
                      c in ("impact_parameter", "from_barrel_end", "sample_id")]]
    frame = mcbat.solve_frame(inputs)
    expected = dataset.drop(columns="chunk")
    assert list(frame.columns) == [c for c in COLUMNS if c != "chunk"]
    pd.testing.assert_frame_equal(frame, expected[frame.columns], check_exact=True,
                                  check_like=False)
    assert frame.attrs["units"] == {c: UNITS[c] for c in frame.columns}


def test_solve_frame_without_impact_parameter_or_ids_and_any_thread_count(dataset):
    inputs = dataset[list(INPUT_FIELDS)].iloc[::-1]  # reversed rows, shuffled index
    one = mcbat.solve_frame(inputs, threads=1)
    two = mcbat.solve_frame(inputs, threads=2)
    pd.testing.assert_frame_equal(one, two, check_exact=True)
    assert list(one.index) == list(inputs.index)
    assert (one["sample_id"].to_numpy() == np.arange(len(inputs))).all()
    expected = dataset.iloc[::-1]
    for column in ("ball_vx", "ball_wz", "stick_impulse", "exit_speed", "status"):
        assert np.array_equal(one[column].to_numpy(), expected[column].to_numpy(),
                              equal_nan=column != "status")
    # The impact parameter computed from the angle agrees with the study's to rounding.
    assert np.allclose(one["impact_parameter"], expected["impact_parameter"], rtol=0,
                       atol=1e-15)


def test_solve_frame_names_a_missing_input_column(dataset):
    with pytest.raises(InputError) as info:
        mcbat.solve_frame(dataset.drop(columns="mu"))
    assert info.value.field == "mu" and "missing column" in str(info.value)
    with pytest.raises(InputError) as info:
        mcbat.solve_frame(dataset, tolerance=-1.0)
    assert info.value.field == "tolerance"


def test_load_puts_the_units_of_every_column_in_attrs(dataset):
    assert dataset.attrs["units"]["exit_speed"] == "m/s"
    assert dataset.attrs["units"]["scattering_angle"] == "deg"
    assert set(dataset.attrs["units"]) == set(dataset.columns)
