"""The scripts of examples/ run on the shipped Savant export in a temporary directory, each
well within a minute, and draw their figures; what they print agrees with the physics
(thinner air carries farther, bat speed adds launch speed)."""

import re
import struct
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
SAVANT = ROOT / "data" / "statcast_2020-09-03.csv"


def run_example(name, tmp_path, *args):
    """Run ``examples/<name>`` in ``tmp_path``; returns its stdout and the PNG it wrote."""
    png = tmp_path / f"{Path(name).stem}.png"
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, str(EXAMPLES / name), str(SAVANT), *args,
                           "--out", str(png)], cwd=tmp_path, capture_output=True, text=True,
                          timeout=120)
    seconds = time.perf_counter() - start
    assert proc.returncode == 0, proc.stderr
    assert seconds < 60, f"{name} took {seconds:.0f} s"
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width, height = struct.unpack(">II", data[16:24])
    assert width > 400 and height > 400 and len(data) > 20_000  # a drawn figure, not empty
    return proc.stdout, png


def test_the_readme_names_every_script():
    readme = (EXAMPLES / "README.md").read_text()
    for script in EXAMPLES.glob("*.py"):
        assert script.name in readme, script.name


def test_spray_chart_at_coors_gains_home_runs(tmp_path):
    own, _ = run_example("spray_chart.py", tmp_path)
    coors, _ = run_example("spray_chart.py", tmp_path, "--park", "COL")
    pattern = r"(\d+) balls, (\d+) home runs"
    (balls_own, hr_own), (balls_col, hr_col) = (
        map(int, re.search(pattern, text).groups()) for text in (own, coors))
    assert balls_own == balls_col > 100
    assert hr_col > hr_own > 0


def test_park_comparison_puts_coors_longest(tmp_path):
    out, _ = run_example("park_comparison.py", tmp_path)
    parks = int(re.search(r"(\d+) parks", out).group(1))
    assert parks >= 25
    most = int(re.search(r"most home runs at \w+ \((\d+)\)", out).group(1))
    fewest = int(re.search(r"fewest at \w+ \((\d+)\)", out).group(1))
    assert most > fewest
    assert re.search(r"longest median carry at coors_field \(\d+ ft\)", out), out  # 5,200 ft


def test_bat_speed_scan_gains_launch_speed_and_distance(tmp_path):
    out, png = run_example("bat_speed_scan.py", tmp_path, "--samples", "20000")
    slope = float(re.search(r"\+([\d.]+) mph per mph", out).group(1))
    assert 0.7 < slope < 1.5  # at most 1 + q (q ~ 0.2 head on at the sweet spot)
    low, high = (float(x) for x in re.findall(r"([\d.]+) % at", out))
    assert high > low + 10
    assert (tmp_path / "bat_speed_scan.toml").exists()
    assert (tmp_path / "bat_speed_scan" / "_summary.parquet").exists()


@pytest.mark.parametrize("name", ["cabo2012_sec5.json", "game_fastball.json"])
def test_the_json_cases_still_solve(name):
    import mcbat

    result = mcbat.solve(EXAMPLES / name)
    results = result if isinstance(result, list) else [result]
    assert results and all(r.to_dict()["status"] == "ok" for r in results)
