"""The Statcast commands on messy files: every row left out counted on stderr and in the
JSON, a stated unit checked against the values, a flight fit refused on distances that do
not follow the launches, errors naming the file and line, and no exit 1."""

import json
import os
import re
import shutil
import signal

import pandas as pd
import pytest

from tests.statcast.messy import (
    DATA,
    ROOT,
    export_text,
    line_of,
    rows,
    with_cell,
    with_column,
    write,
)


@pytest.fixture
def cli(cli):
    """``mcbat ARGS`` in this process: (exit code, stdout, stderr)."""
    def run(*args):
        result = cli(*map(str, args))
        return result.returncode, result.stdout, result.stderr
    return run


def within(seconds, call):
    """``call()``, or a failure if it has not returned after ``seconds`` (an alarm: a read
    that blocks is interrupted)."""
    def expire(*_):
        raise TimeoutError(f"no answer within {seconds} s")
    previous = signal.signal(signal.SIGALRM, expire)
    signal.alarm(seconds)
    try:
        return call()
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def one_line(result):
    code, out, err = result
    assert code == 2, (code, out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.fixture
def twice(tmp_path):
    text = export_text()
    path = tmp_path / "twice.csv"
    path.write_text(text + text.split("\n", 1)[1])
    return path


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    from mcbat.cli import main

    out = tmp_path_factory.mktemp("ds") / "ds"
    assert main(["run", str(ROOT / "studies" / "game_fastball.toml"), "--samples", "400",
                 "--quiet", "--out", str(out)]) == 0
    return out


def test_statcast_counts_the_copies_on_stderr_and_in_json(cli, twice):
    code, out, err = cli("statcast", twice, "--json")
    assert code == 0
    summary = json.loads(out)
    assert summary["rows"] == 2507
    assert summary["left_out"] == {"duplicate pitches": 2507}
    assert err.strip() == f"mcbat: {twice}: 2,507 pitch(es) left out: 2,507 duplicate pitches"
    code, out, err = cli("statcast", twice)
    assert code == 0 and out.startswith(f"{twice}: 2,507 pitches")
    line = one_line(cli("statcast", twice, "--strict"))
    assert f"{twice}: line 2509: the pitch of line 2 again" in line and "--strict" in line


def test_a_second_header_line_is_refused_with_its_line(cli, tmp_path):
    text = export_text()
    path = tmp_path / "two.csv"
    path.write_text(text + text)
    line = one_line(cli("statcast", path))
    assert line.startswith(f"mcbat: error: {path}: line 2509: the header line again")


@pytest.mark.parametrize("command", [("statcast",), ("infer",), ("fit", "--flight", "--data")])
def test_devices_fifos_and_directories_are_refused_at_once(cli, tmp_path, command):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    for path, what in ((fifo, "a named pipe (FIFO)"), ("/dev/zero", "a character device"),
                       (tmp_path, "a directory")):
        result = within(30, lambda path=path: cli(*command, path))
        assert f"is {what}, not a regular file" in one_line(result)


def test_compare_refuses_a_device_and_runs_without_permutations(cli, dataset):
    assert "is a character device" in one_line(cli("compare", dataset, "/dev/zero"))
    code, out, err = cli("compare", dataset, DATA, "--permutations", "0")
    assert code == 0, err
    assert "energy without p-values (0 permutations)" in out
    assert "nan" not in out.replace("nan ", "").lower().split()
    assert err.strip() == f"mcbat: {DATA}: 2,080 pitch(es) left out: 2,080 not in play"


def test_compare_of_copies_gives_the_p_values_of_the_file_once(cli, dataset, twice):
    args = ("--columns", "launch_speed", "--permutations", "200", "--json")
    once = json.loads(cli("compare", dataset, DATA, *args)[1])
    code, out, err = cli("compare", dataset, twice, *args)
    assert code == 0
    result = json.loads(out)
    assert result["columns"] == once["columns"]
    assert result["measured"]["sources"][0]["left_out"] == {
        "not in play": 2080, "duplicate pitches": 2507}
    assert "2,507 duplicate pitches" in err


def test_a_stated_unit_the_values_contradict_is_refused(cli, dataset, tmp_path):
    line = one_line(cli("compare", dataset, DATA, "--units", "launch_speed=m/s"))
    assert f"{DATA}: launch_speed: stated in m/s, but the values' median 89.65 m/s" in line
    assert "--units launch_speed=mph" in line
    # a Parquet table whose metadata says mph for values in m/s
    import pyarrow as pa
    import pyarrow.parquet as pq

    from mcbat.statcast import balls_in_play, read

    tidy = read(DATA)
    balls = tidy[balls_in_play(tidy)].dropna(subset=["launch_speed"])
    table = pa.Table.from_pandas(pd.DataFrame(
        {"launch_speed": balls["launch_speed"].to_numpy() * 0.44704}), preserve_index=False)
    path = tmp_path / "ms.parquet"
    pq.write_table(table.replace_schema_metadata(
        {b"units": json.dumps({"launch_speed": "mph"}).encode()}), path)
    line = one_line(cli("compare", dataset, path))
    assert "launch_speed: stated in mph, but the values' median 40.08 mph lies outside" in line
    assert "--units launch_speed=m/s" in line


def test_flight_fit_refuses_distances_that_do_not_follow_the_launch(cli, tmp_path):
    path = with_column(tmp_path / "d350.csv", "hit_distance_sc", lambda _: "350")
    line = one_line(cli("fit", "--flight", "--data", path, "--intervals", "curvature"))
    assert line.startswith(f"mcbat: error: {path}: hit_distance_sc: every distance of the ")
    assert "is 350 ft" in line


def test_flight_fit_names_the_launch_column_at_fault(cli, tmp_path):
    ms = with_column(tmp_path / "ms.csv", "launch_speed",
                     lambda cell: f"{float(cell) * 0.44704:.1f}")
    line = one_line(cli("fit", "--flight", "--data", ms, "--intervals", "curvature"))
    assert f"{ms}: launch_speed: the median launch speed" in line and "(in m/s?)" in line
    steep = with_column(tmp_path / "a500.csv", "launch_angle", lambda _: "500")
    line = one_line(cli("fit", "--flight", "--data", steep))
    assert line == (f"mcbat: error: {steep}: launch_angle: no ball is left to fly: 785 cells "
                    f"are outside the range of a measurement (the first at line 2: 500)")


def test_flight_fit_counts_every_row_it_leaves_out(cli, twice):
    code, out, err = cli("fit", "--flight", "--data", twice, "--intervals", "curvature",
                         "--json")
    assert code == 0, err
    result = json.loads(out)
    left = result["left_out"]
    assert left["duplicate pitches"] == 2507
    assert result["rows"] - result["balls"] == sum(v for k, v in left.items()
                                                   if k != "duplicate pitches")
    assert err.startswith(f"mcbat: {twice}: ") and "2,507 duplicate pitches" in err


def test_infer_names_the_file_line_of_the_cell(cli, tmp_path):
    header, body = rows()
    description = header.index("description")
    row = [i for i, r in enumerate(body) if r[description].startswith("hit_into_play")][20]
    path = with_cell(tmp_path / "la.csv", "launch_angle", row, "90")
    line = one_line(cli("infer", path))
    assert line == (f"mcbat: error: {path}: launch_angle: must lie within (-90, 90) deg, "
                    f"got 90.0 at line {line_of(row)}")


def test_infer_of_an_export_without_a_pitch_fit_is_an_error(cli, tmp_path):
    header, body = rows()
    j = header.index("vx0")
    for r in body:
        r[j] = ""
    path = write(tmp_path / "novx0.csv", header, body)
    line = one_line(cli("infer", path))
    assert line == (f"mcbat: error: {path}: none of the 427 balls in play can be inferred: "
                    "pitch_speed, vertical_approach_angle, horizontal_approach_angle "
                    "(computed from vx0, vy0, vz0, ax, ay, az) missing in every one")


def test_a_game_fit_error_on_a_savant_export_is_one_line(cli, tmp_path):
    path = with_column(tmp_path / "ms.csv", "launch_speed",
                       lambda cell: f"{float(cell) * 0.44704:.2f}")
    one_line(cli("fit", "--study", ROOT / "studies" / "game_fastball.toml", "--data", path,
                 "--free", "e", "--intervals", "curvature", "--no-compare", "--draws", "8"))


def _pitches_study(tmp_path, data, swing=False):
    study = tmp_path / "real.toml"
    text = (ROOT / "studies" / "real_pitches.toml").read_text().replace(
        "../data/statcast_2020-09-03.csv", str(data)).replace("samples = 20000",
                                                              "samples = 300")
    study.write_text(text)
    return study


@pytest.mark.parametrize("kind", ["zero", "fifo"])
def test_pitches_from_a_device_or_fifo_are_refused_at_once(cli, tmp_path, kind):
    data = "/dev/zero" if kind == "zero" else tmp_path / "pipe.csv"
    if kind == "fifo":
        os.mkfifo(data)
    study = _pitches_study(tmp_path, data)
    line = one_line(within(30, lambda: cli("run", study, "--quiet", "--out", tmp_path / "o")))
    assert "pitches.file: cannot read" in line and "not a regular file" in line


def test_a_pitches_identifier_beyond_int64_names_its_line(cli, tmp_path):
    from mcbat.statcast import read

    tidy = read(DATA).head(40)
    tidy["game_pk"] = tidy["game_pk"].astype(object)
    tidy.loc[9, "game_pk"] = "9223372036854775808"
    path = tmp_path / "tidy.csv"
    tidy.to_csv(path, index=False)
    line = one_line(cli("run", _pitches_study(tmp_path, path), "--quiet", "--out",
                        tmp_path / "o"))
    import csv

    with open(path, newline="") as handle:
        table = csv.reader(handle)
        for _ in range(11):
            next(table)
        line_of_row_9 = table.line_num
    assert (f"pitches.file: {path}: line {line_of_row_9}: column game_pk holds "
            "9223372036854775808, not an identifier (a whole number from 0 to 2**53)") in line
    assert not (tmp_path / "o").exists()


def test_pitches_out_of_range_and_copies_are_left_out_and_counted(cli, tmp_path):
    from mcbat.statcast import read

    tidy = read(DATA)
    chosen = tidy.index[tidy["pitch_type"].isin(["FF", "SI"]) & (tidy["p_throws"] == "R")
                        & tidy["game_pk"].notna()]
    tidy.loc[chosen[:5], "pitch_speed"] = 1e6
    tidy = pd.concat([tidy, tidy.loc[chosen[100:103]]], ignore_index=True)
    path = tmp_path / "tidy.csv"
    tidy.to_csv(path, index=False)
    study = _pitches_study(tmp_path, path)
    code, out, err = cli("run", study, "--quiet", "--out", tmp_path / "o", "--columns",
                         "status")
    assert code == 0, err
    config = json.loads((tmp_path / "o" / "_mcbat.json").read_text())
    pitches = json.dumps(config)
    assert '"duplicate pitches": 3' in pitches
    import mcbat

    data = mcbat.load(tmp_path / "o")
    assert (data["status"] == 0).all()  # no invalid_input row: the 10^6 mph never drawn
    assert '"pitch_speed out of range": 5' in pitches


def test_a_run_that_cannot_fill_the_sweet_spot_window_prints_no_nan(cli, tmp_path):
    from mcbat.runner.study_run import batted_ball_lines

    lines = batted_ball_lines({"launch_speed": (90.0, 80.0, 100.0),
                               "collision_efficiency_sweet_spot": (float("nan"), 0)})
    assert "nan" not in " ".join(lines) and "no row in that window" in lines[-1]


def test_distance_axes_stay_finite_for_huge_predictions():
    import numpy as np

    from mcbat.papers.statcast.figures import _distance_limits

    part = pd.DataFrame({"hit_distance_sc": [300.0, 350.0],
                         "predicted_distance": [1e30, np.inf]})
    lo, hi = _distance_limits([part])
    assert np.isfinite([lo, hi]).all() and lo < hi <= 2000.0
    assert _distance_limits([part.iloc[:0]]) == (0.0, 500.0)


def test_shipped_data_unchanged_by_the_fixtures():
    assert shutil.disk_usage(DATA.parent).free > 0 and DATA.exists()


def test_a_game_fit_error_about_a_row_names_its_file_line(cli):
    import re

    import numpy as np

    from mcbat.statcast.reader import read_with_lines

    line = one_line(cli("fit", "--study", ROOT / "studies" / "game_fastball.toml", "--data",
                        DATA, "--free", "e", "--intervals", "curvature", "--no-compare",
                        "--draws", "4"))
    found = re.search(r"(\w+): lines? (\d+) \(([-\d.e+]+)\)", line)
    assert found and not re.search(r"\brows? \d", line), line
    column, number, value = found.group(1), int(found.group(2)), float(found.group(3))
    table, lines = read_with_lines(DATA)
    row = int(np.flatnonzero(lines == number)[0])
    assert table.loc[row, column] == pytest.approx(value, rel=1e-5)


def test_infer_says_where_it_assumed_the_contact_of_balls_without_a_swing(cli):
    # the 2020 export has no bat tracking: every bat speed is inferred, with the contact
    # at the assumed place, and the bats it needs are the speeds batters swing
    code, out, err = cli("infer", DATA)
    assert code == 0, err
    line = next(s for s in out.splitlines() if "bat speed inferred on" in s)
    median = float(re.search(r"median ([\d.]+) mph", line).group(1))
    assert 68.0 < median < 78.0
    assert "the contact assumed 10.9 in from the barrel end" in line
