"""The CSV reader parses an export a piece at a time: the pieces make the same table and
report as one piece, and errors still name the file's line."""

import csv
import gzip
import io
from importlib import resources

import pandas as pd
import pytest

from mcbat.errors import InputError
from mcbat.statcast import files, reader


@pytest.fixture()
def export(tmp_path):
    text = resources.files("mcbat.data").joinpath("statcast_2020-09-03.csv").read_text(
        encoding="utf-8-sig")
    rows = list(csv.reader(io.StringIO(text)))
    # a non-numeric launch speed far into the file (line 2301), in the third piece of 1000
    rows[2300][rows[0].index("launch_speed")] = "abc"
    path = tmp_path / "export.csv"
    with path.open("w", newline="", encoding="utf-8") as out:
        csv.writer(out, lineterminator="\n").writerows(rows)
    return path


def test_pieces_make_the_same_table_and_report(export, monkeypatch):
    whole = reader.read(export)
    monkeypatch.setattr(reader, "CHUNK_ROWS", 1000)
    assert [len(raw) for raw, _, _ in reader._csv_chunks(export, "x")] == [1000, 1000, 507]
    pieces = reader.read(export)
    pd.testing.assert_frame_equal(whole, pieces)
    assert whole.attrs["statcast"] == pieces.attrs["statcast"]
    bad = pieces.attrs["statcast"]["non_numeric"]["launch_speed"]
    assert bad == {"cells": 1, "value": "abc", "line": 2301}


def test_a_gzip_export_reads_as_the_plain_one(export, tmp_path, monkeypatch):
    monkeypatch.setattr(reader, "CHUNK_ROWS", 700)
    packed = tmp_path / "export.csv.gz"
    packed.write_bytes(gzip.compress(export.read_bytes()))
    pd.testing.assert_frame_equal(reader.read(export), reader.read(packed))


def test_a_short_row_in_a_later_piece_names_its_line(export, tmp_path, monkeypatch):
    monkeypatch.setattr(reader, "CHUNK_ROWS", 500)
    rows = list(csv.reader(io.StringIO(export.read_text(encoding="utf-8"))))
    rows[1800] = rows[1800][:20]
    cut = tmp_path / "cut.csv"
    with cut.open("w", newline="", encoding="utf-8") as out:
        csv.writer(out, lineterminator="\n").writerows(rows)
    with pytest.raises(InputError, match="line 1801: 20 fields"):
        reader.read(cut)


def test_bad_bytes_name_their_offset_in_the_file(export, tmp_path, monkeypatch):
    monkeypatch.setattr(files, "BLOCK_BYTES", 4096)
    data = bytearray(export.read_bytes())
    data[100_000] = 0xFF
    broken = tmp_path / "broken.csv"
    broken.write_bytes(bytes(data))
    with pytest.raises(InputError, match=r"not UTF-8 text \(byte 100000\)"):
        reader.read(broken)
