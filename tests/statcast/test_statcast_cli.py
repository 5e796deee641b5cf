"""``mcbat statcast``: the summary, strict JSON, the Parquet table with its units, and bad
input as one line with exit code 2 (in this process through ``main``; one test runs the real
command)."""

import json
import subprocess
import sys
from importlib import resources

import pyarrow.parquet as pq
import pytest

from mcbat.cli import main
from tests.conftest import ROOT

FILE_2020 = str(resources.files("mcbat.data").joinpath("statcast_2020-09-03.csv"))


def _mcbat(*args):
    return subprocess.run([sys.executable, "-m", "mcbat", *args], capture_output=True,
                          text=True, cwd=ROOT)


def _strict(text):
    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def test_summary_lines(cli):
    proc = cli("statcast", FILE_2020)
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    assert "2,507 pitches, seasons 2020" in out
    assert "pitches by type: FF 890, SL 446" in out
    assert "balls in play: 427 (424 with launch speed and angle)" in out
    assert "rows with a distance (hit_distance_sc): 797" in out
    assert "rows with bat tracking (bat_speed): 0" in out
    assert "FF at the plate (median): 85.3" in out
    assert "columns this export lacks (NaN): spin_axis, bat_speed" in out
    assert proc.stderr == ""


def test_json_is_one_strict_object_with_the_counts(tmp_path, cli):
    proc = cli("statcast", FILE_2020, "--json")
    assert proc.returncode == 0, proc.stderr
    got = _strict(proc.stdout)
    assert {"rows", "seasons", "pitch_types", "balls_in_play", "with_distance",
            "with_bat_tracking", "units"} <= set(got)
    assert got["rows"] == 2507 and got["seasons"] == [2020]
    assert got["pitch_types"]["FF"] == 890 and sum(got["pitch_types"].values()) == 2507
    assert got["balls_in_play"] == 427 and got["with_distance"] == 797
    assert got["with_bat_tracking"] == 0
    assert got["units"]["pitch_speed"] == "mph" and got["units"]["spray_angle"] == "deg"
    assert -6 < got["plate"]["FF"]["vertical_approach_angle"]["median"] < -4
    # an export where single pitch types have one pitch: sd is null, not NaN
    one = _strict(cli("statcast", str(resources.files("mcbat.data").joinpath(
        "statcast_2019_darvish.csv")), "--json").stdout)
    assert one["plate"]["EP"]["pitch_speed"]["sd"] is None


def test_out_writes_the_tidy_table_with_units(tmp_path, cli):
    out = tmp_path / "tidy.parquet"
    proc = cli("statcast", FILE_2020, "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    assert f"tidy table written to {out}" in proc.stdout
    table = pq.read_table(out)
    assert table.num_rows == 2507
    info = json.loads(table.schema.metadata[b"mcbat.statcast"])
    assert info["units"]["launch_speed"] == "mph"
    assert info["units"]["vertical_approach_angle"] == "deg"
    # the table reads back through the same command
    again = _strict(cli("statcast", str(out), "--json").stdout)
    assert again["rows"] == 2507 and again["balls_in_play"] == 427


def _cut(tmp_path):
    text = open(FILE_2020, encoding="utf-8").read()
    path = tmp_path / "cut.csv"
    path.write_text(text[: len(text) // 3])
    return path


def _not_csv(tmp_path):
    path = tmp_path / "notes.csv"
    path.write_text("exit_speed,scattering_angle\n1.2,3\n")
    return path


def _utf16(tmp_path):
    path = tmp_path / "u16.csv"
    path.write_bytes(open(FILE_2020, encoding="utf-8").read()[:2000].encode("utf-16"))
    return path


def _empty(tmp_path):
    path = tmp_path / "empty.csv"
    path.write_text("")
    return path


@pytest.mark.parametrize("make,message", [
    (_cut, "the file is truncated or malformed (an interrupted download?)"),
    (_not_csv, "not a Statcast (Baseball Savant) pitch-level export: missing 31 of its 31"),
    (_utf16, "not UTF-8 text (byte 0)"),
    (_empty, "empty file: no header line"),
    (lambda p: p / "nope.csv", "no such file"),
], ids=["truncated", "not savant", "utf-16", "empty", "missing file"])
def test_bad_input_exits_2_with_one_line(tmp_path, capsys, make, message):
    path = make(tmp_path)
    code = main(["statcast", str(path), "--out", str(tmp_path / "t.parquet")])
    captured = capsys.readouterr()
    assert code == 2
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"mcbat: error: {path}: ")
    assert message in lines[0]
    assert captured.out == ""
    assert not (tmp_path / "t.parquet").exists()


def test_bad_input_through_the_real_command_has_no_traceback(tmp_path):
    path = _cut(tmp_path)
    proc = _mcbat("statcast", str(path), "--json")
    assert proc.returncode == 2 and proc.stdout == ""
    assert len(proc.stderr.strip().splitlines()) == 1 and "Traceback" not in proc.stderr


def test_a_bad_out_path_is_refused_before_reading(tmp_path, cli):
    proc = cli("statcast", FILE_2020, "--out", str(tmp_path / "t.txt"))
    assert proc.returncode == 2
    assert proc.stderr.strip() == (f"mcbat: error: --out: unsupported file type '.txt' for "
                                   f"{tmp_path / 't.txt'} (use one of: .parquet, .pq, .csv)")


def test_a_non_numeric_cell_is_reported_not_fatal(tmp_path, cli):
    text = open(FILE_2020, encoding="utf-8").read()
    path = tmp_path / "cell.csv"
    path.write_text(text.replace('"106.3","28"', '"106.3","steep"', 1))
    proc = cli("statcast", str(path))
    assert proc.returncode == 0, proc.stderr
    assert "launch_angle: 1 non-numeric cell(s) set to NaN (first at line 2: 'steep')" \
        in proc.stdout
