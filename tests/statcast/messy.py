"""Messy copies of data/statcast_2020-09-03.csv for the tests of messy input."""

import csv
import io
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "data" / "statcast_2020-09-03.csv"


def export_text():
    """The shipped export's text, ending with a newline."""
    text = DATA.read_text(encoding="utf-8-sig")
    return text if text.endswith("\n") else text + "\n"


def rows():
    """The shipped export as a header and rows of strings."""
    table = list(csv.reader(io.StringIO(export_text())))
    return table[0], table[1:]


def write(path, header, body):
    """``header`` and ``body`` written as CSV to ``path``; returns ``path``."""
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(header)
        writer.writerows(body)
    return path


def with_cell(path, column, row, value):
    """The export with ``column`` of data row ``row`` (from 0; file line ``row + 2``)
    replaced by ``value``."""
    header, body = rows()
    body[row][header.index(column)] = value
    return write(path, header, body)


def with_column(path, column, change, where=None):
    """The export with every given cell of ``column`` (of the rows ``where(header, row)``
    selects) replaced by ``change(cell)``."""
    header, body = rows()
    j = header.index(column)
    for row in body:
        if row[j] not in ("", "null") and (where is None or where(header, row)):
            row[j] = change(row[j])
    return write(path, header, body)


def line_of(row):
    """The file line (from 1) on which data row ``row`` (from 0) ends, as csv counts it
    (a quoted cell may hold a line break)."""
    reader = csv.reader(io.StringIO(export_text()))
    next(reader)
    for i, _ in enumerate(reader):
        if i == row:
            return reader.line_num
    raise IndexError(row)
