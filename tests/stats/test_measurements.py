"""Measurement tables: validation with clear errors, and synthetic tables from the model."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mcbat.errors import InputError
from mcbat.stats.measurements import read_measurements, synthesize, write_table_atomic
from mcbat.study import load_study

ROOT = Path(__file__).resolve().parents[2]
STUDY = ROOT / "studies" / "cross_nathan_2006.toml"
GOOD = "impact_parameter,spin_in,exit_speed,exit_speed_err\n0.01,0,1.5,0.07\n-0.02,79,1.6,0.08\n"


def _table(tmp_path, text, name="m.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_good_table_reads_as_floats(tmp_path):
    df = read_measurements(_table(tmp_path, "# a comment\n" + GOOD),
                           required=("impact_parameter", "exit_speed"))
    assert list(df.columns) == ["impact_parameter", "spin_in", "exit_speed", "exit_speed_err"]
    assert df["exit_speed"].tolist() == [1.5, 1.6] and df.dtypes.unique().tolist() == [float]


@pytest.mark.parametrize("text, required, words", [
    (GOOD, ("spin_out",), "spin_out: missing required column"),
    (GOOD.replace("1.6", "fast"), (), "exit_speed: row 2: not a number: 'fast'"),
    (GOOD.replace("0.08", "-0.08"), (), "exit_speed_err: row 2: an uncertainty must be > 0"),
    (GOOD.replace("0.07", "0"), (), "exit_speed_err: row 1: an uncertainty must be > 0"),
    (GOOD.replace("1.5", "nan"), (), "exit_speed: row 1: must be finite"),
    (GOOD.replace("spin_in", "spin_inn"), (), "spin_inn: unknown column"),
    ("spin_out_err\n0.1\n", (), "spin_out_err: uncertainty without its value column"),
    ("exit_speed\n", (), "the table has no data rows"),
    (GOOD.replace("spin_in", "exit_speed"), (),
     "exit_speed: duplicate column: appears 2 times in the header"),
    ("# measured 2026-11-01\n" + GOOD.replace("spin_in,", "spin_in, spin_in ,"), (),
     "spin_in: duplicate column: appears 2 times"),
])
def test_malformed_tables_give_clear_errors(tmp_path, text, required, words):
    path = _table(tmp_path, text)
    with pytest.raises(InputError) as info:
        read_measurements(path, required=required)
    message = str(info.value)
    assert message.startswith(str(path)) and words in message


def test_unknown_format_and_missing_file(tmp_path):
    with pytest.raises(InputError, match="unknown table format"):
        read_measurements(_table(tmp_path, GOOD, "m.xlsx"))
    with pytest.raises(InputError, match="no such file"):
        read_measurements(tmp_path / "nope.csv")


def test_synthetic_table_is_deterministic_noisy_and_valid(tmp_path):
    study = load_study(STUDY)
    a = synthesize(study, 400, seed=5, e=0.6, mu=0.45)
    b = synthesize(study, 400, seed=5, e=0.6, mu=0.45)
    assert a.equals(b) and len(a) == 400
    assert not a.equals(synthesize(study, 400, seed=6, e=0.6, mu=0.45))
    clean = synthesize(study, 400, seed=5, e=0.6, mu=0.45, speed_noise=1e-12,
                       angle_noise=1e-12, spin_noise=1e-12)
    pulls = (a["exit_speed"] - clean["exit_speed"]) / a["exit_speed_err"]
    assert abs(pulls.mean()) < 0.2 and pulls.std() == pytest.approx(1.0, abs=0.1)
    # one error for every row (5 % of the mean): not a function of each row's true value
    assert np.allclose(a["exit_speed_err"], 0.05 * clean["exit_speed"].abs().mean(), rtol=1e-9)
    path = tmp_path / "synth.csv"
    write_table_atomic(a, path)
    back = read_measurements(path, required=("impact_parameter", "exit_speed"))
    assert np.allclose(back["exit_speed"], a["exit_speed"], rtol=1e-9)


def test_synth_cli(tmp_path):
    out = tmp_path / "m.csv"
    proc = subprocess.run([sys.executable, "-m", "mcbat.cli", "synth", "--study", str(STUDY),
                           "--rows", "60", "--e", "0.6", "--mu", "0.5", "--seed", "1",
                           "--out", str(out)], capture_output=True, text=True, check=False)
    assert proc.returncode == 0, proc.stderr
    assert len(read_measurements(out)) == 60
