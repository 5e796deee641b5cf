"""Bad game inputs exit 2 with one line naming the key (``mcbat impact`` and ``mcbat run``)."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BASE = {"bat": {"preset": "r161"}, "mu": 0.5, "pitch": {"speed": 40}, "swing": {"bat_speed": 30}}


def _mcbat(*args, stdin=None):
    return subprocess.run([sys.executable, "-m", "mcbat", *args], input=stdin,
                          capture_output=True, text=True, cwd=ROOT)


def _with(section, **values):
    case = json.loads(json.dumps(BASE))
    case.setdefault(section, {}).update(values)
    return case


@pytest.mark.parametrize("case,key", [
    (_with("swing", attack_angle={"value": 50, "unit": "deg"},
           vertical_bat_angle={"value": -45, "unit": "deg"}), "swing.vertical_bat_angle"),
    (_with("contact", undercut={"value": 3, "unit": "in"}), "contact.undercut"),
    (_with("contact", from_barrel_end={"value": 40, "unit": "in"}), "contact.from_barrel_end"),
    (_with("pitch", horizontal_approach_angle={"value": 120, "unit": "deg"}),
     "pitch.horizontal_approach_angle"),
    (_with("pitch", speed=-40), "pitch.speed"),
])
def test_bad_game_case_exits_2_naming_the_key(case, key):
    proc = _mcbat("impact", "-", stdin=json.dumps(case))
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and f"case 0: {key}:" in lines[0]
    assert proc.stdout == ""


def test_game_case_and_bat_frame_case_in_one_file(tmp_path):
    game = json.loads((ROOT / "examples" / "game_fastball.json").read_text())
    bat_frame = json.loads((ROOT / "examples" / "cabo2012_sec5.json").read_text())
    path = tmp_path / "cases.json"
    path.write_text(json.dumps([game, bat_frame]))
    proc = _mcbat("impact", str(path))
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert 90 < out[0]["launch_speed"] < 120 and "exit_speed" in out[1]


@pytest.mark.parametrize("edit,key", [
    (("[swing]", '[swing]\nvertical_bat_angle = { value = -60, unit = "deg" }\n'
      'attack_angle = { value = 40, unit = "deg" }\n'), "swing.attack_angle"),
    (('low = -2, high = 2, unit = "in" }', 'low = -2, high = 3.5, unit = "in" }'),
     "contact.undercut.high"),
])
def test_bad_game_study_exits_2_naming_the_key(tmp_path, edit, key):
    text = (ROOT / "studies" / "game_fastball.toml").read_text()
    if edit[0] == "[swing]":  # replace the swing section's angles
        text = text.replace("attack_angle = {", "x_attack = {").replace(
            "vertical_bat_angle = {", "x_vertical = {")
        text = text.replace("x_attack = {", "#").replace("x_vertical = {", "#")
    assert edit[0] in text
    text = text.replace(edit[0], edit[1], 1)
    study = tmp_path / "bad.toml"
    study.write_text(text)
    proc = _mcbat("run", str(study), "--out", str(tmp_path / "o"), "--quiet")
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and key in lines[0], lines
    assert not (tmp_path / "o").exists()
