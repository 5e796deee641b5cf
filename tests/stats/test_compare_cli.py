"""`mcbat compare`: a small game dataset against the real Statcast rows shipped in data/;
bad input exits 2 with one line; --json is strict JSON."""

import json
import subprocess
import sys

import pandas as pd
import pytest
from scipy import stats

import mcbat
from mcbat.cli import main
from mcbat.cli.common import as_flags
from mcbat.cli.compare import COMPARE_PARAMETERS, _units_as_flag_values
from mcbat.errors import InputError
from mcbat.runner import run_study
from mcbat.statcast import balls_in_play, read
from mcbat.study import load_study
from tests.conftest import ROOT

REAL = [str(ROOT / "data" / "statcast_2020-09-03.csv"),
        str(ROOT / "data" / "statcast_2019_darvish.csv")]


@pytest.fixture(scope="module")
def game(tmp_path_factory):
    # (through the library: what `mcbat run` does, without a process of its own)
    out = tmp_path_factory.mktemp("compare") / "game"
    run_study(load_study(ROOT / "studies" / "game_fastball.toml"), out, samples=3000,
              chunk_size=1000, progress=False)
    return str(out)


def _strict(text):
    def refuse(name):
        raise ValueError(f"non-finite {name} in JSON")
    return json.loads(text, parse_constant=refuse)


def _run(capsys, *argv):
    code = main(["compare", *argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_game_dataset_against_real_balls_in_play(game, capsys, tmp_path):
    figure = tmp_path / "compare.png"
    code, out, err = _run(capsys, game, *REAL, "--json", "--permutations", "200",
                          "--figure", str(figure))
    assert code == 0, err
    result = _strict(out)
    columns = {c["column"]: c for c in result["columns"]}
    assert {"launch_speed", "launch_angle", "spray_angle", "hit_distance",
            "pitch_speed"} <= set(columns)
    # the same numbers from the inputs, read and tested independently here
    sim = mcbat.load(game, columns=["launch_speed", "launch_angle"])
    real = pd.concat([read(p) for p in REAL], ignore_index=True)
    real = real[balls_in_play(real)]
    for name in ("launch_speed", "launch_angle"):
        x = sim[name].dropna().to_numpy()
        y = real[name].dropna().to_numpy()
        ks = stats.ks_2samp(x, y)
        assert columns[name]["ks"]["statistic"] == pytest.approx(ks.statistic, rel=1e-12)
        assert columns[name]["ks"]["p_value"] == pytest.approx(ks.pvalue, rel=1e-9)
        assert columns[name]["wasserstein"] == pytest.approx(
            stats.wasserstein_distance(x, y), rel=1e-12)
        assert columns[name]["measured"]["rows"] == len(y)
        assert columns[name]["measured"]["dropped"] == len(real) - len(y)
        assert columns[name]["simulated"]["rows"] == len(x)
    assert result["measured"]["rows"] == len(real)
    # the pitch speed: in mph on both sides, nothing to convert
    assert columns["pitch_speed"]["unit"] == "mph"
    assert columns["pitch_speed"].get("converted_from") is None
    plane = result["plane"]
    assert plane["columns"] == ["launch_speed", "launch_angle"]
    assert plane["simulated_rows"] == 2000
    assert 0 < plane["p_value"] <= 1
    assert result["settings"]["p_value_resolution"] == pytest.approx(1 / 201)
    assert figure.stat().st_size > 10_000 and figure.read_bytes()[:4] == b"\x89PNG"
    # the printed table carries the same rows
    code, out, err = _run(capsys, game, *REAL, "--columns", "launch_speed,launch_angle",
                          "--permutations", "50")
    assert code == 0, err
    line = next(s for s in out.splitlines() if s.startswith("launch_speed "))
    assert f"{columns['launch_speed']['ks']['statistic']:.3f}" in line
    assert "plane launch_speed x launch_angle" in out


def _table(tmp_path, name, frame):
    path = tmp_path / name
    frame.to_csv(path, index=False)
    return str(path)


def _bad_inputs(tmp_path, game):
    real = read(REAL[0])
    speeds = real.loc[balls_in_play(real), ["launch_speed", "launch_angle"]].dropna()
    in_m_s = speeds.assign(launch_speed=speeds["launch_speed"] * 0.44704)
    header_only = tmp_path / "empty.csv"
    header_only.write_text("launch_speed,launch_angle\n")
    return {
        "missing dataset": ([str(tmp_path / "nope"), REAL[0]], ["nope"]),
        "missing table": ([game, str(tmp_path / "nope.csv")], ["nope.csv", "no such file"]),
        "no shared column": ([game, _table(tmp_path, "foo.csv", pd.DataFrame({"foo": [1.0]}))],
                             ["foo.csv", "shares no column"]),
        "empty table": ([game, str(header_only)], ["empty.csv", "no data rows"]),
        "launch speed in m/s": ([game, _table(tmp_path, "ms.csv", in_m_s)],
                                ["ms.csv", "launch_speed:", "wrong unit", "m/s",
                                 "--units launch_speed=m/s"]),
        "unknown column": ([game, *REAL, "--columns", "launch_sped"],
                           ["launch_sped", "not a column"]),
        "units of another quantity": ([game, _table(tmp_path, "ms2.csv", in_m_s), "--units",
                                       "launch_speed=deg", "--columns", "launch_speed"],
                                      ["launch_speed:", "units differ"]),
        "unknown unit": ([game, *REAL, "--units", "launch_speed=furlongs"],
                         ["--units:", "furlongs"]),
        "bad units flag": ([game, *REAL, "--units", "launch_speed"], ["--units:", "COLUMN=UNIT"]),
        "negative permutations": ([game, *REAL, "--permutations", "-1"], ["--permutations:"]),
        "figure of unknown type": ([game, *REAL, "--figure", str(tmp_path / "f.txt")],
                                   ["--figure:", ".txt"]),
    }


def test_bad_input_exits_2_with_one_line(game, capsys, tmp_path):
    for name, (argv, words) in _bad_inputs(tmp_path, game).items():
        code, out, err = _run(capsys, *argv)
        assert code == 2, (name, err)
        assert out == "", name
        lines = err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("mcbat: error: "), (name, err)
        for word in words:
            assert word in lines[0], (name, lines[0])


def test_the_unit_advice_names_the_flag(game, capsys, tmp_path):
    """The library's advice is a mention of its ``units`` parameter (data); the command
    spells it as the flag, in the form the flag takes, and the advice works."""
    real = read(REAL[0])
    speeds = real.loc[balls_in_play(real), ["launch_speed"]].dropna() * 0.44704
    table = _table(tmp_path, "ms.csv", speeds)
    code, out, err = _run(capsys, game, table)
    assert code == 2 and out == ""
    assert "(--units launch_speed=m/s)" in err and "units=" not in err, err
    code, _, err = _run(capsys, game, table, "--units", "launch_speed=m/s",
                        "--permutations", "10")
    assert code == 0, err


def test_several_columns_advised_take_one_flag_each():
    error = InputError("x", "state the units ({units})",
                       mentions={"units": {"launch_speed": "m/s", "launch_angle": "rad"}})
    advised = as_flags(_units_as_flag_values(error), COMPARE_PARAMETERS)
    assert advised.message == ("state the units (--units launch_speed=m/s "
                               "--units launch_angle=rad)")


def test_stated_m_s_is_converted(game, capsys, tmp_path):
    real = read(REAL[0])
    speeds = real.loc[balls_in_play(real), ["launch_speed"]].dropna()
    path = _table(tmp_path, "ms.csv", speeds.assign(launch_speed=speeds.launch_speed * 0.44704))
    code, out, err = _run(capsys, game, path, "--units", "launch_speed=m/s", "--json",
                          "--permutations", "20")
    assert code == 0, err
    column = _strict(out)["columns"][0]
    code, out, err = _run(capsys, game, REAL[0], "--columns", "launch_speed", "--json",
                          "--permutations", "20")
    in_mph = _strict(out)["columns"][0]
    assert column["unit"] == "m/s" and column["converted_from"] == "mph"
    assert column["ks"]["statistic"] == pytest.approx(in_mph["ks"]["statistic"], abs=1e-12)
    assert column["wasserstein"] == pytest.approx(in_mph["wasserstein"] * 0.44704, rel=1e-9)


def test_subprocess_exit_codes():
    done = subprocess.run([sys.executable, "-m", "mcbat", "compare", "/nonexistent/ds",
                           REAL[0]], capture_output=True, text=True, check=False)
    assert done.returncode == 2
    assert "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1


def test_a_dataset_against_itself(game, capsys):
    code, out, err = _run(capsys, game, game, "--columns", "launch_speed,launch_angle",
                          "--permutations", "20", "--json")
    assert code == 0, err
    result = _strict(out)
    for column in result["columns"]:
        assert column["ks"]["statistic"] == 0 and column["wasserstein"] == 0
        assert column["energy"]["distance"] == 0 and column["energy"]["p_value"] == 1
        assert column["converted_from"] is None
    assert result["measured"]["sources"][0]["kind"] == "dataset"
    # the plane's test draws its 2,000 rows of each side independently
    assert result["plane"]["distance"] < 0.1 and result["plane"]["p_value"] > 0.05
