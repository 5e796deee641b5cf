"""`mcbat reproduce`: its closing table states one e*, the dataset's, and labels the
re-derived calibration as a check of the paper's (the whole run is in
tests/papers/cabo2012/test_reproduce.py)."""

import math

from mcbat.papers.cabo2012 import sec5, summary


def test_the_table_states_one_e_star_the_datasets():
    e_star = sec5.e_star_paper()
    headline = {"spins": {}, "rows": 10, "rows_ok": 10, "e_star": e_star,
                "calibration": {"e_star": 0.6178247, "loss_fraction": 0.6182926,
                                "target_speed": sec5.TARGET_SPEED, "exit_speed": 1.44629,
                                "theta": sec5.THETA_NEAR_ZERO, "w0": 0.0}}
    text = summary.format_table(headline)
    assert text.count("e* =") == 1 and "0.6178247" not in text
    line = next(line for line in text.splitlines() if "e* =" in line)
    assert line.startswith(f"e* = {e_star:.7f} (loss fraction e^2 = {sec5.LOSS_FRACTION:.7f})")
    assert "dataset" in line
    check = next(line for line in text.splitlines() if "0.6182926" in line)
    assert check.startswith("check of the paper's calibration: e^2 = 0.6182926")
    assert math.isclose(1 - e_star ** 2, sec5.LOSS_FRACTION, rel_tol=1e-12)
