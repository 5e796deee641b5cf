"""A reproduction writes only what it owns."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from mcbat.errors import InputError
from mcbat.papers.outputs import MARKER, ResultsDirectory

ROOT = Path(__file__).resolve().parents[2]


def test_foreign_names_are_refused_before_any_work(tmp_path):
    (tmp_path / "summary.json").write_text('{"mine": true}')
    proc = subprocess.run([sys.executable, "-m", "mcbat", "reproduce", "--out", str(tmp_path),
                           "--samples", "1000", "--quiet"], capture_output=True, text=True,
                          cwd=ROOT)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    line, = proc.stderr.strip().splitlines()
    assert "--out" in line and "'summary.json', which mcbat did not write" in line \
        and "--overwrite" in line
    assert json.loads((tmp_path / "summary.json").read_text()) == {"mine": True}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["summary.json"]  # nothing ran


def test_a_users_figures_directory_is_refused_too(tmp_path):
    (tmp_path / "sawicki2003" / "figures").mkdir(parents=True)
    (tmp_path / "sawicki2003" / "figures" / "plot.png").write_bytes(b"user's")
    proc = subprocess.run([sys.executable, "-m", "mcbat", "reproduce", "sawicki2003",
                           "--out", str(tmp_path)], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 2 and "'figures', which mcbat did not write" in proc.stderr


def test_owned_names_are_rewritten_and_others_left_alone(tmp_path):
    first = ResultsDirectory(tmp_path, "demo", ("summary.json", "figures"))
    with first.writing():
        first.write_text("summary.json", "1\n")
        (first.directory("figures") / "a.png").write_bytes(b"x")
    (tmp_path / "notes.txt").write_text("the user's")
    again = ResultsDirectory(tmp_path, "demo", ("summary.json", "figures"))  # ours: accepted
    with again.writing():
        again.write_text("summary.json", "2\n")
    assert (tmp_path / "summary.json").read_text() == "2\n"
    assert (tmp_path / "notes.txt").read_text() == "the user's"
    assert json.loads((tmp_path / MARKER).read_text())["names"] == ["figures", "summary.json"]
    # another program's name: refused, unless overwrite
    with pytest.raises(InputError, match="'table.txt', which mcbat did not write"):
        (tmp_path / "table.txt").write_text("theirs")
        ResultsDirectory(tmp_path, "demo", ("summary.json", "table.txt"))
    taken = ResultsDirectory(tmp_path, "demo", ("summary.json", "table.txt"), overwrite=True)
    with taken.writing():
        taken.write_text("table.txt", "ours now\n")
    assert "table.txt" in json.loads((tmp_path / MARKER).read_text())["names"]
