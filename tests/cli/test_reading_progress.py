"""A season's export counts its rows on a terminal as it is read, and says nothing when
stderr is a file or a pipe."""

import io
from pathlib import Path

from mcbat.cli.common import reading_progress
from mcbat.statcast import read, reader

DATA = Path(__file__).resolve().parents[2] / "data" / "statcast_2020-09-03.csv"


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_a_terminal_sees_the_rows_counted_piece_by_piece(monkeypatch):
    monkeypatch.setattr(reader, "CHUNK_ROWS", 1000)
    terminal = _Terminal()
    with reading_progress(terminal):
        table = read(DATA)
    shown = terminal.getvalue()
    assert "1,000 rows" in shown and "2,000 rows" in shown
    assert shown.endswith(f"{len(table):,} rows\n") and shown.count("\n") == 1


def test_a_file_or_pipe_sees_nothing():
    stream = io.StringIO()
    with reading_progress(stream):
        read(DATA)
    assert stream.getvalue() == ""
