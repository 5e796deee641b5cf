"""What the population-fit tests share: the study, the real rows, and running the CLI."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
STUDY = ROOT / "examples" / "population_game.toml"
REAL = ROOT / "data" / "statcast_2020-09-03.csv"


def run_mcbat(*args):
    """``python -m mcbat ARGS``, its output captured."""
    return subprocess.run([sys.executable, "-m", "mcbat", *args], capture_output=True,
                          text=True, check=False)


def assert_one_line_exit_2(proc, *words):
    """The process failed with exit code 2 and one line of stderr naming every word."""
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    for word in words:
        assert word in lines[0], lines[0]
