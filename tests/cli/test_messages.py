"""Messages that point the right way: a flipped sign is not called a wrong unit, an
interrupted fit does not promise chunk files, an unknown key lists each allowed key
once, and units take their article ("an angle")."""

import pandas as pd

from tests.conftest import ROOT

STUDY = str(ROOT / "studies" / "cross_nathan_2006.toml")
DATA = ROOT / "data" / "synthetic_cross_nathan_60.csv"


def _table(tmp_path, column, change):
    df = pd.read_csv(DATA, comment="#")
    df[column] = change(df[column])
    path = tmp_path / "m.csv"
    df.to_csv(path, index=False)
    return str(path)


def test_flipped_scattering_angles_are_called_a_sign_not_a_unit(tmp_path, cli):
    out = cli("fit", "--study", STUDY, "--data", _table(tmp_path, "scattering_angle",
                                                         lambda c: -c), "--no-compare")
    assert out.returncode == 2
    line = out.stderr.strip()
    assert "\n" not in line and "scattering_angle:" in line
    assert "sign flipped?" in line and "radians" not in line and "wrong unit" not in line


def test_scattering_angles_in_radians_are_still_called_a_unit(tmp_path, cli):
    out = cli("fit", "--study", STUDY, "--data", _table(tmp_path, "scattering_angle",
                                                         lambda c: c * 3.141592653589793 / 180),
              "--no-compare")
    assert out.returncode == 2
    assert "wrong unit?" in out.stderr and "sign flipped" not in out.stderr


def test_an_interrupted_fit_does_not_speak_of_chunk_files(cli, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr("mcbat.stats.fit.estimate.fit", interrupted)
    out = cli("fit", "--study", STUDY, "--data", str(DATA), "--no-compare")
    assert out.returncode == 130
    assert "interrupted" in out.stderr and "chunk" not in out.stderr
    assert "resume" not in out.stderr and len(out.stderr.strip().splitlines()) == 1


def test_an_unknown_key_lists_each_allowed_key_once(tmp_path, cli):
    text = (ROOT / "studies" / "game_fastball.toml").read_text()
    assert "\n[swing]\n" in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace("\n[swing]\n", "\n[swing]\ncolour = 1\n"))
    out = cli("run", str(path), "--out", str(tmp_path / "out"), "--quiet")
    assert out.returncode == 2
    listed = out.stderr.split("expected one of: ")[1].rstrip(")\n").split(", ")
    assert "bat_speed" in listed and len(listed) == len(set(listed)), listed


def test_a_unit_of_another_quantity_takes_its_article(cli):
    out = cli("flight", "-", stdin='{"launch_speed": {"value": 20, "unit": "deg"}, '
                                   '"launch_angle": 20}')
    assert out.returncode == 2
    assert "is an angle unit, but this input is a speed" in out.stderr
    out = cli("flight", "-", stdin='{"launch_speed": 90, "launch_angle": '
                                   '{"value": 20, "unit": "mph"}}')
    assert "is a speed unit, but this input is an angle" in out.stderr
    assert "a angle" not in out.stderr
