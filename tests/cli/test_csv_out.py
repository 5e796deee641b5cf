"""Tables written as CSV wherever a command writes one: the units in the column header,
the same numbers as the Parquet table."""

from pathlib import Path

import numpy as np
import pandas as pd

from mcbat.cli import main
from mcbat.dataset.tables import read_table

DATA = Path(__file__).resolve().parents[2] / "data" / "statcast_2020-09-03.csv"


def test_statcast_writes_its_tidy_table_as_csv_with_units(tmp_path, capsys):
    csv, parquet = tmp_path / "tidy.csv", tmp_path / "tidy.parquet"
    assert main(["statcast", str(DATA), "--out", str(csv)]) == 0
    assert main(["statcast", str(DATA), "--out", str(parquet)]) == 0
    capsys.readouterr()
    header = csv.read_text().splitlines()[0]
    assert "launch_speed [mph]" in header and "spray_angle [deg]" in header
    table = read_table(csv)
    assert table.attrs["units"]["hit_distance_sc"] == "ft"
    tidy = pd.read_parquet(parquet)
    assert len(table) == len(tidy) == 2507
    np.testing.assert_allclose(table["launch_speed"], tidy["launch_speed"], equal_nan=True)


def test_infer_writes_csv_with_units(tmp_path, capsys):
    csv = tmp_path / "spin.csv"
    assert main(["infer", str(DATA), "--out", str(csv)]) == 0
    assert "written" in capsys.readouterr().out
    table = read_table(csv)
    assert table.attrs["units"]["backspin"] == "rpm"
    converged = table["inference_status"] == "converged"
    assert converged.mean() > 0.8 and np.isfinite(table.loc[converged, "backspin"]).all()


def test_an_unknown_suffix_is_refused_naming_the_flag(tmp_path, capsys):
    assert main(["statcast", str(DATA), "--out", str(tmp_path / "x.txt")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--out" in err
