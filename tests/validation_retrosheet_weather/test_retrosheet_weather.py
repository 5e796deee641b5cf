"""The Retrosheet weather converter (validation/retrosheet_weather.py) on hand-made event
file excerpts: team codes, doubleheaders, unknown markers, roof, and bad input."""

import csv
import subprocess
import sys

import pytest

from mcbat.errors import InputError
from tests.conftest import ROOT
from validation import retrosheet_weather as rw

# Three games in Retrosheet's event-file layout (records shortened to what the converter
# reads, plus a few it must skip): a doubleheader at Wrigley Field with an unknown
# temperature in game 1 and an unknown wind speed in game 2, and an Athletics home game in
# 2025 under a dome sky.
EXCERPT_CHN = """\
id,CHN202107040
version,2
info,visteam,SLN
info,hometeam,CHN
info,site,CHI11
info,date,2021/07/04
info,number,1
info,daynight,day
info,temp,0
info,winddir,tolf
info,windspeed,14
info,sky,sunny
start,carlm003,"Matt Carpenter",0,1,5
play,1,0,carlm003,32,BCBBFX,HR/7/F
data,er,carlm003,0
id,CHN202107041
version,2
info,visteam,SLN
info,hometeam,CHN
info,site,CHI11
info,date,2021/07/04
info,number,2
info,daynight,night
info,temp,78
info,winddir,unknown
info,windspeed,-1
info,sky,unknown
play,1,0,carlm003,00,X,8/F
"""

EXCERPT_ATH = """\
id,ATH202504010
version,2
info,visteam,CHN
info,hometeam,ATH
info,site,SAC01
info,date,2025/04/01
info,number,0
info,temp,72
info,winddir,fromcf
info,windspeed,0
info,sky,dome
"""


@pytest.fixture
def events(tmp_path):
    folder = tmp_path / "events"
    folder.mkdir()
    (folder / "2021CHN.EVN").write_text(EXCERPT_CHN)
    (folder / "2025ATH.EVA").write_text(EXCERPT_ATH)
    (folder / "README.txt").write_text("not an event file\n")
    return folder


def test_rows_codes_and_unknown_markers(events):
    rows = rw.weather_table([events])
    assert [(r["game_date"], r["home_team"], r["game_number"]) for r in rows] == [
        ("2021-07-04", "CHC", 1), ("2021-07-04", "CHC", 2), ("2025-04-01", "ATH", 0)]
    first, second, athletics = rows
    # temp 0 is Retrosheet's unknown; a real wind of 14 mph stays.
    assert first["temperature"] == "" and first["wind_speed"] == 14
    assert first["wind_direction"] == "tolf" and first["roof"] == "open"
    # windspeed -1 is unknown; a real temperature stays; an unknown sky leaves the roof
    # unknown (empty).
    assert second["temperature"] == 78 and second["wind_speed"] == ""
    assert second["wind_direction"] == "unknown" and second["roof"] == ""
    # A recorded 0 mph wind is a value, not unknown; the dome sky is a closed roof.
    assert athletics["wind_speed"] == 0 and athletics["roof"] == "closed"
    assert athletics["retrosheet_game_id"] == "ATH202504010"


@pytest.mark.parametrize("code, season, expected", [
    ("ANA", 2019, "LAA"), ("ARI", 2019, "AZ"), ("CHA", 2019, "CWS"), ("CHN", 2019, "CHC"),
    ("KCA", 2019, "KC"), ("LAN", 2019, "LAD"), ("NYA", 2019, "NYY"), ("NYN", 2019, "NYM"),
    ("SDN", 2019, "SD"), ("SFN", 2019, "SF"), ("SLN", 2019, "STL"), ("TBA", 2019, "TB"),
    ("WAS", 2019, "WSH"), ("OAK", 2024, "OAK"), ("OAK", 2025, "ATH"), ("ATH", 2025, "ATH"),
    ("BOS", 2019, "BOS"), ("MIA", 2019, "MIA"), ("TOR", 2020, "TOR"),
])
def test_team_codes(code, season, expected):
    assert rw.statcast_team(code, season) == expected


def test_every_code_maps_to_a_statcast_club():
    clubs = {rw.statcast_team(code, 2019) for code in rw.TEAM_CODES}
    assert len(clubs) == 30


def test_unknown_team_code_is_named(tmp_path):
    path = tmp_path / "2019XXX.EVA"
    path.write_text(EXCERPT_ATH.replace("hometeam,ATH", "hometeam,XXX"))
    with pytest.raises(InputError, match="info,hometeam.*'XXX'"):
        rw.read_event_file(path)


def test_bad_values_are_named(tmp_path):
    path = tmp_path / "2025ATH.EVA"
    path.write_text(EXCERPT_ATH.replace("info,temp,72", "info,temp,warm"))
    with pytest.raises(InputError, match="info,temp"):
        rw.read_event_file(path)
    path.write_text(EXCERPT_ATH.replace("info,winddir,fromcf", "info,winddir,sideways"))
    with pytest.raises(InputError, match="info,winddir.*sideways"):
        rw.read_event_file(path)


def test_command_line(events, tmp_path):
    out = tmp_path / "weather.csv"
    done = subprocess.run(
        [sys.executable, "-m", "validation", "retrosheet_weather", str(events), "--out",
         str(out)], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    with open(out, newline="") as handle:
        table = list(csv.DictReader(handle))
    assert list(table[0])[:7] == ["game_date", "home_team", "game_number", "temperature",
                                  "wind_speed", "wind_direction", "roof"]
    assert [(r["home_team"], r["temperature"], r["wind_speed"]) for r in table] == [
        ("CHC", "", "14"), ("CHC", "78", ""), ("ATH", "72", "0")]

    missing = subprocess.run(
        [sys.executable, "-m", "validation", "retrosheet_weather", str(tmp_path / "nowhere"),
         "--out", str(out)], cwd=ROOT, capture_output=True, text=True)
    assert missing.returncode == 2
    assert "EVENT_DIR" in missing.stderr and "Traceback" not in missing.stderr


def test_shipped_sample_matches_its_statcast_games():
    """data/retrosheet_weather_sample.csv holds one row per game of the 2020-09-03 export,
    each keyed by date, home team and game number, with the Retrosheet notice on top."""
    path = ROOT / "data" / "retrosheet_weather_sample.csv"
    lines = path.read_text().splitlines()
    assert lines[0].startswith("#") and "www.retrosheet.org" in lines[0]
    table = list(csv.DictReader(lines[1:]))
    with open(ROOT / "data" / "statcast_2020-09-03.csv", newline="") as handle:
        games = {(r["game_date"], r["home_team"]) for r in csv.DictReader(handle)}
    keys = {(r["game_date"], r["home_team"]) for r in table}
    assert games <= keys
    assert all(r["temperature"] != "" for r in table)
