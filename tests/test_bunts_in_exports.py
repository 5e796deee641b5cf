"""Real 2025 rows with bunts go through every command that reads a Statcast export.

The excerpt (tests/statcast/data/README.md) holds five real bunt rows, one of them a
missed bunt with ``attack_direction`` -148.5 deg and a 1.9 mph bat speed: no command may
refuse the file for them, and the commands that use the swing say what they did with them.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.cli_runner import run_in_process

HERE = Path(__file__).parent
EXCERPT = HERE / "statcast" / "data" / "statcast_2025-05-01_excerpt.csv"
STUDY = HERE.parent / "studies" / "real_pitches.toml"


def _mcbat(capsys, monkeypatch, *args, cwd=None):
    result = run_in_process(capsys, monkeypatch, *args, cwd=cwd)
    assert "Traceback" not in result.stderr
    return result


def test_the_excerpt_holds_real_bunts():
    import mcbat.statcast as sc

    df = sc.read(EXCERPT)
    bunts = sc.is_bunt(df["description"].to_numpy(object), df["events"].to_numpy(object),
                       df["des"].to_numpy(object))
    assert bunts.sum() == 5
    assert (df.loc[bunts, "attack_direction"].abs() >= 90).sum() == 1


def test_statcast(capsys, monkeypatch):
    result = _mcbat(capsys, monkeypatch, "statcast", EXCERPT, "--json")
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert summary["rows"] == 105 and summary["with_bat_tracking"] == 104


def test_infer(capsys, monkeypatch, tmp_path):
    out = tmp_path / "spin.parquet"
    result = _mcbat(capsys, monkeypatch, "infer", EXCERPT, "--out", out)
    assert result.returncode == 0, result.stderr
    assert "unusable_swing 1" in result.stdout  # the sacrifice bunt in play
    # every other tracked ball in play takes its bat's angle from its swing plane
    assert "from the measured swing plane (swing_path_tilt) on " in result.stdout
    import pandas as pd

    spin = pd.read_parquet(out)
    assert (spin["inference_status"] == "unusable_swing").sum() == 1
    assert spin.loc[spin["events"] == "sac_bunt", "inference_status"].iloc[0] == \
        "unusable_swing"


def test_infer_spin_takes_every_row(capsys):
    # every pitch, the missed bunt (attack direction -148.5 deg) among them: no error
    import mcbat.statcast as sc
    from mcbat.inference import infer_spin

    df = sc.read(EXCERPT)
    spin = infer_spin(df)
    counts = spin.attrs["status_counts"]
    assert sum(counts.values()) == len(df)
    missed = df.index[df["description"] == "missed_bunt"][0]
    # not in play: no launch, so a missing input first
    assert spin.loc[missed, "inference_status"] == "missing_input"


def test_reproduce_and_fit_flight(capsys, monkeypatch, tmp_path):
    result = _mcbat(capsys, monkeypatch, "reproduce", "statcast", "--data", EXCERPT,
                    "--out", tmp_path / "o")
    assert result.returncode == 0, result.stderr
    result = _mcbat(capsys, monkeypatch, "fit", "--flight", "--data", EXCERPT)
    assert result.returncode == 0, result.stderr


@pytest.fixture(scope="module")
def swing_study(tmp_path_factory):
    """studies/real_pitches.toml on the excerpt with the swing from the rows."""
    text = STUDY.read_text(encoding="utf-8")
    text = text.replace('file = "../data/statcast_2020-09-03.csv"',
                        f'file = "{EXCERPT.as_posix()}"\nswing = true')
    text = text.replace('p_throws = "R"\n', "").replace("samples = 20000", "samples = 300")
    kept = [line for line in text.splitlines()
            if not line.startswith(("bat_speed =", "attack_angle =", "attack_direction ="))]
    path = tmp_path_factory.mktemp("bunts") / "study.toml"
    path.write_text("\n".join(kept) + "\n", encoding="utf-8")
    return path


def test_pitches_study_leaves_bunts_out_and_counts_them(capsys, monkeypatch, swing_study):
    out = swing_study.parent / "out"
    result = _mcbat(capsys, monkeypatch, "run", swing_study, "--out", out)
    assert result.returncode == 0, result.stderr
    # the foul bunt on a sinker (bat speed 4 mph) is the one bunt among FF and SI
    assert "1 bunts" in result.stdout + result.stderr
    import mcbat.statcast as sc
    from mcbat.dataset import load

    rows = sc.read(EXCERPT)
    bunt = int(rows.index[(rows["description"] == "foul_bunt")
                          & (rows["pitch_type"] == "SI")][0])
    data = load(out)
    assert bunt not in set(data["source_row"])
    # (mph) the bunt's 4.0 mph swing is never drawn; slow real swings may be
    assert not (abs(data["bat_speed"] - rows.loc[bunt, "bat_speed"]) < 1e-6).any()
    result = _mcbat(capsys, monkeypatch, "compare", out, EXCERPT)
    assert result.returncode == 0, result.stderr


def test_bat_tracking_on_the_excerpt_and_judged_on_its_drawn_balls(capsys, monkeypatch,
                                                                   tmp_path):
    # the shipped study on another export (--pitches); the sacrifice bunt in play is left
    # out of the draws, and `compare --drawn` leaves it out of the judged rows too
    out = tmp_path / "bt"
    result = _mcbat(capsys, monkeypatch, "run", "bat_tracking", "--pitches", EXCERPT,
                    "--samples", "3000", "--out", out, "--quiet", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "bunts" in result.stdout
    result = _mcbat(capsys, monkeypatch, "compare", out, EXCERPT, "--drawn", "--by",
                    "bat_speed", "--permutations", "0", "--json")
    assert result.returncode == 0, result.stderr
    compared = json.loads(result.stdout)
    import mcbat.statcast as sc

    rows = sc.read(EXCERPT)
    in_play = rows[sc.balls_in_play(rows)]
    assert compared["settings"]["drawn"] == len(in_play) - 1  # all but the sac bunt
    assert compared["per_row"]["met"] == len(in_play) - 1


def test_replay(capsys, monkeypatch):
    result = _mcbat(capsys, monkeypatch, "replay", EXCERPT, "--park", "COL", "--json")
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)


def test_population_fit_of_the_shipped_study_by_name(capsys, monkeypatch, tmp_path):
    # the bat-tracking study named as it ships; the sacrifice bunt in play is not fitted
    import mcbat.statcast as sc

    result = _mcbat(capsys, monkeypatch, "fit", "--population", "--study", "bat_tracking",
                    "--data", EXCERPT, "--free", "contact.undercut.mean", "--draws", "10",
                    "--json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "shipped with mcbat" in result.stderr
    fitted = json.loads(result.stdout)
    rows = sc.read(EXCERPT)
    assert fitted["rows"] == sc.balls_in_play(rows).sum() - 1
