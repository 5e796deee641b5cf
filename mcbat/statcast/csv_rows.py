"""The rows of a Savant CSV export, as text, a piece at a time: every row checked to be a
row of the table (as many fields as the header, not the header again), with its line in
the file. ``mcbat.statcast.reader`` turns each piece into the tidy table.
"""

from __future__ import annotations

import csv
import operator

import numpy as np

from mcbat.errors import InputError
from mcbat.statcast.files import text_lines

__all__ = ["csv_chunks"]


def csv_chunks(path, label, wanted, check_header, rows):
    """The columns ``wanted`` (names; those the file has) of a Savant CSV export as
    strings, ``rows`` rows at a time: yields ``(frame, lines, duplicates)``, ``lines`` the
    file line of each row, ``duplicates`` the column names the header gives twice (the
    first copy is read). ``check_header(names, label)`` raises on a header that is no
    export's.

    Every row is checked to have as many fields as the header (Python's csv module, in
    strict mode): pandas would pad a short row with NaN, and a download cut in the middle
    of a row would pass for a row of missing values. Blank lines are skipped.
    """
    import pandas as pd

    reader = csv.reader(text_lines(path, label), strict=True)
    try:
        header = next(reader, None)
        if not header or not any(cell.strip() for cell in header):
            raise InputError(None, "empty file: no header line (not a Savant export)",
                             label)
        names = [cell.strip() for cell in header]
        check_header(names, label)
        first = {}
        for index, column in enumerate(names):
            first.setdefault(column, index)
        duplicates = sorted(c for c in first if names.count(c) > 1)
        wanted = sorted(first[c] for c in wanted if c in first)
        columns = [names[i] for i in wanted]
        width = len(header)
        pick = operator.itemgetter(*wanted)
        marks = [(first[c], c) for c in ("pitch_type", "game_date", "game_pk")]
        body, lines = [], []
        emitted = False
        for row in reader:
            if not row:
                continue
            if len(row) != width:
                raise InputError(None, f"line {reader.line_num}: {len(row)} fields where "
                                 f"the header has {width}: the file is truncated or "
                                 "malformed (an interrupted download?)", label)
            if all(row[i].strip() == c for i, c in marks):
                raise InputError(None, f"line {reader.line_num}: the header line again "
                                 "(the column names as a row): two exports concatenated "
                                 "with their headers? Remove the line (and check for "
                                 "pitches given twice)", label)
            body.append(pick(row))
            lines.append(reader.line_num)
            if len(body) == rows:
                yield pd.DataFrame(body, columns=columns, dtype=object), np.array(lines), \
                    duplicates
                body, lines, emitted = [], [], True
    except csv.Error as err:
        raise InputError(None, f"line {reader.line_num}: malformed CSV ({err}): the file "
                         "is truncated or malformed (an interrupted download?)",
                         label) from None
    if body or not emitted:
        yield pd.DataFrame(body, columns=columns, dtype=object), np.array(lines, dtype=int), \
            duplicates
