"""The drop-test tables' onset of sticking (harness.drop_tables)."""

import numpy as np
import pytest

from harness.drop_tables import (
    design_stick_onset,
    drop_table,
    kernel_solver,
    reference_solver,
    stick_onset,
)


def _design(rows, seed):
    drawn = {}

    def record(b, spin_in, axial, *_):
        drawn.update(b=b, spin_in=spin_in, axial=axial)
        return np.zeros((len(b), 3))

    drop_table(rows, seed, solver=record)
    return drawn["b"], drawn["spin_in"], drawn["axial"]


@pytest.mark.parametrize("solver", [kernel_solver, reference_solver])
def test_drops_stick_above_their_onset_and_slide_below_it(solver):
    b, spin_in, axial = (x[:3] for x in _design(60, 1000))
    onset = stick_onset(b, spin_in, axial, 0.6, 0.0, solver=solver, iterations=16)
    stuck = solver(b, spin_in, axial, 0.6, 2.0, 0.0)
    for i in range(3):
        one = (b[i:i + 1], spin_in[i:i + 1], axial[i:i + 1], 0.6)
        above = solver(*one, onset[i] * 1.01, 0.0)[0]
        below = solver(*one, onset[i] * 0.99, 0.0)[0]
        # Above the onset the spin is friction's no more, and the exit speed and angle
        # are within a hundredth of their measurement errors (3 %, 2 deg) of a sticking
        # drop's; one per cent below it the drop slides on and its spin differs.
        assert abs(above[2] - stuck[i, 2]) <= 1e-6
        assert abs(above[0] - stuck[i, 0]) < 1e-2 * 0.03 * stuck[i, 0]
        assert abs(above[1] - stuck[i, 1]) < 1e-2 * 2.0
        assert abs(below[2] - stuck[i, 2]) > 1e-3


def test_the_kernel_and_the_reference_find_the_same_onset():
    b, spin_in, axial = (x[:2] for x in _design(60, 1001))
    kernel = stick_onset(b, spin_in, axial, 0.6, 0.0, solver=kernel_solver, iterations=14)
    reference = stick_onset(b, spin_in, axial, 0.6, 0.0, solver=reference_solver,
                            iterations=14)
    np.testing.assert_allclose(kernel, reference, atol=2 * 2.0 / 2 ** 14)


def test_a_tables_onset_is_its_last_drops_and_does_not_depend_on_mu():
    b, spin_in, axial = _design(60, 1002)
    onset = stick_onset(b, spin_in, axial, 0.6, 0.0)
    assert design_stick_onset(60, 1002) == onset.max()
    # The drops' spins (79, 0 and -72 rad/s) and impact parameters in +-1 in put the onset
    # of a 60-drop table near 0.2, where the slowest-to-stick drop is the most oblique
    # against its spin.
    assert 0.17 < onset.max() < 0.24
    table = drop_table(60, 1002, mu=onset.max(), solver=kernel_solver)
    assert table.attrs["truth"]["mu"] == onset.max()
    np.testing.assert_array_equal(table.attrs["truth"]["impact_parameter"], b)


def test_stated_errors_follow_the_truth_the_measurement_or_a_constant():
    tables = {how: drop_table(300, 7, solver=kernel_solver, stated_errors=how)
              for how in ("truth", "measured", "constant")}
    truth, measured, constant = tables["truth"], tables["measured"], tables["constant"]
    exact = truth.attrs["truth"]
    true_speed = kernel_solver(exact["impact_parameter"], truth["spin_in"].to_numpy(),
                               exact["axial"], 0.6, 0.18, 0.0)[:, 0]
    # The same drops and noise; a lab states the error from what it measured.
    np.testing.assert_array_equal(truth["exit_speed"], measured["exit_speed"])
    np.testing.assert_allclose(truth["exit_speed_err"], 0.03 * true_speed)
    np.testing.assert_allclose(measured["exit_speed_err"], 0.03 * measured["exit_speed"].abs())
    np.testing.assert_allclose(measured["spin_out_err"],
                               np.maximum(0.08 * measured["spin_out"].abs(), 2.0))
    # Constant errors, drawn as stated: the normalised residuals have unit spread (its
    # standard error on 300 rows is 0.04).
    for column in ("exit_speed_err", "spin_out_err"):
        assert constant[column].nunique() == 1
    residual = (constant["exit_speed"] - true_speed) / constant["exit_speed_err"]
    assert abs(np.std(residual) - 1.0) < 0.15
    with pytest.raises(ValueError, match="stated_errors"):
        drop_table(3, 7, solver=kernel_solver, stated_errors="guessed")
