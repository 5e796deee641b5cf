"""The fitted preset ``studies/mlb_balls_in_play.toml`` against the real balls in play it
was fitted to (``data/statcast_2020-09-03_in_play.csv``; docs/batting.md, "Presets fitted
to real balls in play")."""

import csv
import io
import math
from pathlib import Path

import numpy as np
import pytest

import mcbat
from mcbat.statcast import read
from mcbat.stats.compare.comparison import ks_test

ROOT = Path(__file__).resolve().parents[2]
DAY = ROOT / "data" / "statcast_2020-09-03.csv"
IN_PLAY = ROOT / "data" / "statcast_2020-09-03_in_play.csv"
PRESET = ROOT / "studies" / "mlb_balls_in_play.toml"


def _rows(path):
    """The file's data lines as written, each with its parsed fields."""
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    header = next(csv.reader([lines[0]]))
    return header, [(line, next(csv.reader(io.StringIO(line)))) for line in lines[1:]]


def test_in_play_file_is_the_days_rows_of_type_x():
    # the subset is the day's export cut to its balls in play, rows unchanged and in order
    header, day = _rows(DAY)
    sub_header, sub = _rows(IN_PLAY)
    assert sub_header == header
    kind = header.index("type")
    assert [line for line, _ in sub] == [line for line, row in day if row[kind] == "X"]
    assert len(sub) == 427


@pytest.fixture(scope="module")
def real():
    t = read(IN_PLAY)
    t = t[t["launch_speed"].notna() & t["launch_angle"].notna()]
    return t["launch_speed"].to_numpy(float), t["launch_angle"].to_numpy(float)


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    study = mcbat.load_study(PRESET)
    out = tmp_path_factory.mktemp("in_play") / "d"
    mcbat.run(study, out, samples=6000, progress=False)
    df = mcbat.load(out, columns=["launch_speed", "launch_angle", "status"])
    ok = df["status"].to_numpy() == 0
    assert ok.mean() > 0.99
    return df["launch_speed"].to_numpy()[ok], df["launch_angle"].to_numpy()[ok]


def test_preset_launch_distributions_match_the_real_balls(simulated, real):
    (ls, la), (real_ls, real_la) = simulated, real
    assert len(real_ls) == 424
    speed = ks_test(ls, real_ls)["statistic"]
    angle = ks_test(la, real_la)["statistic"]
    assert speed <= 0.08, speed
    assert angle <= 0.07, angle


@pytest.mark.parametrize("what", ["weak contact", "pop-ups"])
def test_preset_shares_of_weak_contact_and_popups_match(simulated, real, what):
    # within 2.5 binomial standard errors of the real share (424 balls)
    (ls, la), (real_ls, real_la) = simulated, real
    ours, theirs = ((np.mean(ls < 80), np.mean(real_ls < 80)) if what == "weak contact"
                    else (np.mean(la > 50), np.mean(real_la > 50)))
    assert theirs > 0.05                                  # the real file has them
    error = math.sqrt(theirs * (1 - theirs) / len(real_ls))
    assert abs(ours - theirs) <= 2.5 * error, (ours, theirs)
