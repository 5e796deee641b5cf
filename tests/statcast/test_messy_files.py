"""Real Statcast files are messy: the reader drops (and counts) the copies of a pitch,
refuses a header line repeated inside a file, identifiers that are not whole numbers in
range, paths that are no regular file and gzip files that expand without end, reads a
Parquet file named .csv as Parquet, and never reads a bool as a number."""

import gzip
import os
import threading

import numpy as np
import pandas as pd
import pytest

from mcbat.errors import InputError
from mcbat.statcast import files, read
from mcbat.statcast.reader import read_with_lines
from tests.statcast.messy import DATA, export_text, line_of, rows, with_cell, write


def test_a_pitch_given_twice_is_dropped_and_counted(tmp_path):
    text = export_text()
    body = text.split("\n", 1)[1]
    path = tmp_path / "twice.csv"
    path.write_text(text + body)  # two overlapping downloads, the second without header
    once = read(DATA)
    twice = read(path)
    assert len(twice) == len(once) == 2507
    report = twice.attrs["statcast"]
    assert report["left_out"] == {"duplicate pitches": 2507}
    assert report["duplicate_pitches"]["first"] == "line 2509"
    assert report["duplicate_pitches"]["repeats"] == "line 2"
    pd.testing.assert_frame_equal(twice.reset_index(drop=True), once.reset_index(drop=True))


def test_strict_refuses_a_pitch_given_twice_naming_both_lines(tmp_path):
    text = export_text()
    lines = text.split("\n")
    path = tmp_path / "twice.csv"
    path.write_text("\n".join([*lines[:11], lines[5], *lines[11:]]))
    with pytest.raises(InputError) as err:
        read(path, strict=True)
    assert str(err.value).startswith(f"{path}: line 12: the pitch of line 6 again (game_pk ")
    assert "strict=True" in str(err.value)


def test_rows_without_the_whole_key_are_not_duplicates(tmp_path):
    header, body = rows()
    j = header.index("pitch_number")
    first = list(body[0])
    first[j] = ""
    path = write(tmp_path / "blank.csv", header, [first, list(first), *body[1:]])
    table = read(path)
    assert len(table) == 2508
    assert table.attrs["statcast"]["left_out"] == {}


def test_a_header_line_inside_the_file_is_refused_with_its_line(tmp_path):
    text = export_text()
    lines = text.split("\n")
    path = tmp_path / "header.csv"
    path.write_text("\n".join([*lines[:100], lines[0], *lines[100:]]))
    with pytest.raises(InputError, match=r"header\.csv: line 101: the header line again"):
        read(path)


@pytest.mark.parametrize("value, reason", [
    ("9223372036854775808", "outside 0..2\\*\\*53"), ("1.5", "not a whole number"),
    ("-3", "outside 0..2\\*\\*53"), ("abc", "not an identifier")])
@pytest.mark.parametrize("column", ["game_pk", "batter"])
def test_an_identifier_out_of_range_names_column_file_and_line(tmp_path, column, value,
                                                               reason):
    path = with_cell(tmp_path / "id.csv", column, 131, value)
    with pytest.raises(InputError) as err:
        read(path)
    message = str(err.value)
    assert message.startswith(f"{path}: {column}: line {line_of(131)}: ")
    assert pd.Series([message]).str.contains(reason).all(), message


def test_a_cell_out_of_a_measurements_range_is_missing_and_counted(tmp_path):
    path = with_cell(tmp_path / "far.csv", "launch_speed", 9, "1e20")
    table, lines = read_with_lines(path)
    far = table.attrs["statcast"]["out_of_range"]["launch_speed"]
    assert far == {"cells": 1, "value": "1e+20", "range": [0.0, 150.0], "line": line_of(9)}
    assert np.isnan(table.loc[9, "launch_speed"])
    assert lines[9] == line_of(9)


@pytest.mark.parametrize("kind", ["directory", "fifo", "device", "link to a device"])
def test_only_regular_files_are_read_and_at_once(tmp_path, kind):
    if kind == "directory":
        path, what = tmp_path, "is a directory"
    elif kind == "fifo":
        path, what = tmp_path / "pipe.csv", "is a named pipe \\(FIFO\\)"
        os.mkfifo(path)
    elif kind == "device":
        path, what = "/dev/zero", "is a character device"
    else:
        path, what = tmp_path / "zero.csv", "is a character device"
        path.symlink_to("/dev/zero")
    done = []
    thread = threading.Thread(target=lambda: done.append(_error(path)), daemon=True)
    thread.start()
    thread.join(20)
    assert done, f"reading {kind} did not return within 20 s"
    assert pd.Series([done[0]]).str.contains(f"{what}, not a regular file").all(), done[0]


def _error(path):
    try:
        read(path)
    except InputError as err:
        return str(err)
    return "read"


def test_a_gzip_bomb_is_refused_at_the_cap(tmp_path, monkeypatch):
    monkeypatch.setattr(files, "MIN_EXPANDED_BYTES", 1 << 20)
    path = tmp_path / "bomb.csv.gz"
    header = export_text().split("\n", 1)[0]
    path.write_bytes(gzip.compress((header + "\n" + "0," * (20 << 20)).encode(), 9))
    size = path.stat().st_size
    with pytest.raises(InputError) as err:
        read(path)
    assert f"the compressed file ({size:,} bytes) expands to more than" in str(err.value)


def test_a_real_gzip_export_is_read_whole(tmp_path):
    path = tmp_path / "day.csv.gz"
    path.write_bytes(gzip.compress(DATA.read_bytes()))
    assert len(read(path)) == 2507


def test_a_line_without_end_is_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(files, "MAX_LINE_BYTES", 4000)
    monkeypatch.setattr(files, "BLOCK_BYTES", 256)
    path = tmp_path / "long.csv"
    path.write_text(export_text().split("\n", 1)[0] + "\n" + "x" * 20000)
    with pytest.raises(InputError, match=r"long\.csv: line 2: longer than"):
        read(path)


def test_a_parquet_file_named_csv_is_read_as_parquet(tmp_path):
    raw = pd.read_csv(DATA, low_memory=False)
    path = tmp_path / "export.csv"
    raw.to_parquet(path)
    assert len(read(path)) == 2507


def test_text_that_is_not_utf8_names_its_line(tmp_path):
    text = export_text().encode()
    cut = text.index(b"\n", 1000)
    path = tmp_path / "latin.csv"
    path.write_bytes(text[:cut + 1] + b"\xff" + text[cut + 1:])
    line = text[:cut + 1].count(b"\n") + 1
    with pytest.raises(InputError, match=rf"line {line}: not UTF-8 text \(byte {cut + 1}\)"):
        read(path)


def test_a_bool_column_is_not_read_as_numbers():
    raw = pd.read_csv(DATA, low_memory=False).head(50)
    raw["launch_speed"] = raw["launch_speed"].notna()  # a flag where a speed belongs
    table = read(raw)
    assert table["launch_speed"].isna().all()
    bad = table.attrs["statcast"]["non_numeric"]["launch_speed"]
    assert bad["cells"] == 50 and bad["row"] == 1 and bad["value"] in ("True", "False")


def test_an_identifier_beyond_int64_in_a_dataframe_names_its_row():
    raw = pd.read_csv(DATA, low_memory=False).head(20)
    raw["game_pk"] = raw["game_pk"].astype(float)
    raw.loc[6, "game_pk"] = 1e19
    with pytest.raises(InputError, match=r"<DataFrame>: game_pk: row 7: 10000000000000000000"):
        read(raw)
