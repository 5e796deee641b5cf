"""Before a run's clock starts, the local engine loads the kernels its study calls, and
only those: a game study's first run does not compile the game kernel inside its timed
part, nor the bat-frame kernel it never calls."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

PROBE = """
import json, sys
from types import SimpleNamespace
from mcbat.core.batch import solve_batch
from mcbat.core.flight.trajectory import fly_batch
from mcbat.core.sampling import draw_random_inputs
from mcbat.core.swing.game import solve_game_batch
from mcbat.runner.engines.local import LocalEngine
from mcbat.runner.pitches import load_pitches
from mcbat.study import load_study

study = load_study(sys.argv[1])
if getattr(study, "pitches", None) is not None:
    study = load_pitches(study)
LocalEngine(threads=1).ready(study, SimpleNamespace(seed=study.seed))
print(json.dumps({name: bool(d.signatures) for name, d in (
    ("bat_frame", solve_batch), ("game", solve_game_batch), ("flight", fly_batch),
    ("sampler", draw_random_inputs))}))
"""


def _loaded(study):
    out = subprocess.run([sys.executable, "-c", PROBE, str(ROOT / "studies" / study)],
                         capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("study, expected", [
    ("game_fastball.toml", {"bat_frame": False, "game": True, "flight": True,
                            "sampler": True}),
    ("example.toml", {"bat_frame": True, "game": False, "flight": False,
                      "sampler": True}),
])
def test_ready_loads_the_kernels_of_the_study_and_only_those(study, expected):
    assert _loaded(study) == expected
