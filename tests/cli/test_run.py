"""`mcbat run`: library errors named by their flags, `--tolerance`, bad game studies, and
the line that a first run compiles the kernels."""

import json
import subprocess
import sys
import tomllib

import pytest

from mcbat.cli import main
from tests.conftest import ROOT


def test_library_errors_name_parameters_and_the_cli_names_flags(tmp_path, capsys):
    from mcbat.errors import InputError
    from mcbat.runner import run_study
    from mcbat.study import load_study

    study = load_study(ROOT / "studies" / "example.toml")
    (tmp_path / "foreign.txt").write_text("not mcbat's")
    with pytest.raises(InputError) as info:
        run_study(study, tmp_path, samples=10, progress=False)
    assert info.value.field == "out"
    with pytest.raises(InputError) as info:
        run_study(study, tmp_path / "new", chunk_size=0, progress=False)
    assert info.value.field == "chunk_size"
    with pytest.raises(InputError) as info:
        run_study(study, tmp_path / "new", workers=2, progress=False)
    assert info.value.field == "workers" and "--" not in str(info.value)
    # The same errors through the command line name the flags.
    assert main(["run", str(ROOT / "studies" / "example.toml"), "--out", str(tmp_path / "n"),
                 "--chunk-size", "0", "--quiet"]) == 2
    assert "error: --chunk-size: must be an integer >= 1" in capsys.readouterr().err
    assert main(["run", str(ROOT / "studies" / "example.toml"), "--out", str(tmp_path / "n"),
                 "--workers", "2", "--quiet"]) == 2
    assert "error: --workers: only with --engine dask" in capsys.readouterr().err
    out = tmp_path / "other"
    assert main(["run", str(ROOT / "studies" / "example.toml"), "--out", str(out),
                 "--samples", "50", "--quiet"]) == 0
    capsys.readouterr()
    assert main(["run", str(ROOT / "studies" / "example.toml"), "--out", str(out),
                 "--samples", "60", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "--out: holds a dataset written with" in err and "pass --overwrite to" in err


def _with_solver_tolerance(tmp_path, tolerance):
    """studies/example.toml with ``[solver] tolerance`` written in."""
    path = tmp_path / f"example_{tolerance}.toml"
    text = (ROOT / "studies" / "example.toml").read_text()
    assert "solver" not in tomllib.loads(text)
    path.write_text(f"{text}\n[solver]\ntolerance = {tolerance}\n")
    return path


def test_run_tolerance_flag_is_the_studys_solver_tolerance(tmp_path, capsys):
    """``mcbat run --tolerance T`` writes the rows of the study with ``[solver] tolerance =
    T``, records T in the dataset's config, and is part of it: resuming with another
    tolerance (or none) is refused, with the same one it resumes."""
    import pandas as pd

    import mcbat

    study = str(ROOT / "studies" / "example.toml")
    common = ["--samples", "60", "--quiet"]
    flagged, in_toml, default = tmp_path / "flag", tmp_path / "toml", tmp_path / "default"
    assert main(["run", study, "--out", str(flagged), "--tolerance", "1e-11", *common]) == 0
    assert main(["run", str(_with_solver_tolerance(tmp_path, 1e-11)), "--out", str(in_toml),
                 *common]) == 0
    assert main(["run", study, "--out", str(default), *common]) == 0
    capsys.readouterr()

    manifest = json.loads((flagged / "_mcbat.json").read_text())
    assert manifest["study"]["solver"]["tolerance"] == 1e-11
    reference = json.loads((in_toml / "_mcbat.json").read_text())
    assert manifest["config_hash"] == reference["config_hash"]
    rows = mcbat.load(flagged)
    pd.testing.assert_frame_equal(rows, mcbat.load(in_toml))
    steps, default_steps = rows["rk4_steps"], mcbat.load(default)["rk4_steps"]
    assert (steps >= default_steps).all() and (steps > default_steps).any()  # T was used

    for again in (["--tolerance", "1e-10"], []):
        assert main(["run", study, "--out", str(flagged), *again, *common]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err
        assert "--out: holds a dataset written with a different study config" in err, err
    assert main(["run", study, "--out", str(flagged), "--tolerance", "1e-11", *common]) == 0
    assert "0 computed, 1 kept from before" in capsys.readouterr().out
    assert main(["run", study, "--out", str(tmp_path / "bad"), "--tolerance", "1", *common]) == 2
    assert "mcbat: error: --tolerance: must be > 0 and < 1, got 1.0" in capsys.readouterr().err
    assert not (tmp_path / "bad").exists()


@pytest.mark.parametrize("edit,key", [
    (("[swing]", '[swing]\nvertical_bat_angle = { value = -60, unit = "deg" }\n'
      'attack_angle = { value = 40, unit = "deg" }\n'), "swing.attack_angle"),
    (('low = -2, high = 2, unit = "in" }', 'low = -2, high = 3.5, unit = "in" }'),
     "contact.undercut.high"),
])
def test_bad_game_study_exits_2_naming_the_key(tmp_path, edit, key, cli):
    text = (ROOT / "studies" / "game_fastball.toml").read_text()
    if edit[0] == "[swing]":  # replace the swing section's angles
        text = text.replace("attack_angle = {", "x_attack = {").replace(
            "vertical_bat_angle = {", "x_vertical = {")
        text = text.replace("x_attack = {", "#").replace("x_vertical = {", "#")
    assert edit[0] in text
    text = text.replace(edit[0], edit[1], 1)
    study = tmp_path / "bad.toml"
    study.write_text(text)
    proc = cli("run", str(study), "--out", str(tmp_path / "o"), "--quiet")
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and key in lines[0], lines
    assert not (tmp_path / "o").exists()


# ---------------------------------------------------------------- compiling the kernels

KERNEL_MODULE = '''
import numba


@numba.njit(cache=True)
def twice(x):
    return 2.0 * x
'''


def _cache_state(tmp_path, cache_dir=None):
    """``is_cold`` of a cached numba function in a fresh process (before its first call),
    with ``NUMBA_CACHE_DIR`` set to ``cache_dir``; the process then calls it."""
    import os

    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    if cache_dir is not None:
        env["NUMBA_CACHE_DIR"] = str(cache_dir)
    # (compiling.py is loaded alone: the runner's package imports pandas and pyarrow, seconds
    # a process on a loaded machine)
    code = ("import importlib.util, sys; sys.path.insert(0, sys.argv[1]); "
            "import kernel_for_test as k; "
            "spec = importlib.util.spec_from_file_location('compiling', sys.argv[2]); "
            "c = importlib.util.module_from_spec(spec); spec.loader.exec_module(c); "
            "print(c.is_cold(k.twice)); k.twice(1.0); print(c.is_cold(k.twice))")
    proc = subprocess.run([sys.executable, "-c", code, str(tmp_path),
                           str(ROOT / "mcbat" / "runner" / "compiling.py")],
                          capture_output=True, text=True, cwd=ROOT, env=env, check=True)
    return proc.stdout.split()


def test_a_cold_cache_is_told_from_a_warm_one(tmp_path):
    """Cold before the first call with an empty cache directory; warm after it in the
    process; warm in the next process, which loads the machine code from the cache."""
    (tmp_path / "kernel_for_test.py").write_text(KERNEL_MODULE)
    cache = tmp_path / "cache"
    assert _cache_state(tmp_path, cache) == ["True", "False"]
    assert _cache_state(tmp_path, cache) == ["False", "False"]


def test_the_run_says_it_is_compiling_before_its_progress_bar(tmp_path, capsys, monkeypatch):
    """One line on stderr before the bar when a kernel is cold; none with --quiet, none
    when the kernels are compiled, and none before a refusal (the error stays the one
    line)."""
    import mcbat.runner.compiling as compiling

    study = str(ROOT / "studies" / "example.toml")
    monkeypatch.setattr(compiling, "is_cold", lambda kernel: True)
    assert main(["run", study, "--out", str(tmp_path / "a"), "--samples", "60"]) == 0
    err = capsys.readouterr().err
    assert err.splitlines()[0] == compiling.COMPILING and err.count(compiling.COMPILING) == 1
    assert main(["run", study, "--out", str(tmp_path / "b"), "--samples", "60",
                 "--quiet"]) == 0
    assert capsys.readouterr().err == ""
    assert main(["run", study, "--out", str(tmp_path / "c"), "--samples", "60",
                 "--chunk-size", "0"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    monkeypatch.setattr(compiling, "is_cold", lambda kernel: False)
    assert main(["run", study, "--out", str(tmp_path / "d"), "--samples", "60"]) == 0
    assert "compil" not in capsys.readouterr().err


def test_the_kernels_of_a_run_are_those_of_its_study():
    from mcbat.core.batch import solve_batch
    from mcbat.core.flight.trajectory import fly_batch
    from mcbat.core.swing.game import solve_game_batch
    from mcbat.runner.compiling import kernels_for
    from mcbat.study import load_study

    assert kernels_for(load_study(ROOT / "studies" / "example.toml")) == [solve_batch]
    game = load_study(ROOT / "studies" / "game_fastball.toml")  # (with [flight])
    assert kernels_for(game) == [solve_game_batch, fly_batch]


def test_the_help_gives_the_runners_default_chunk(capsys):
    from mcbat.runner.plan import DEFAULT_CHUNK_SIZE

    with pytest.raises(SystemExit):
        main(["run", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert f"or {DEFAULT_CHUNK_SIZE:,})" in text and "262,144" not in text


def test_a_shipped_study_runs_by_name_from_any_directory(tmp_path, cli):
    """From a directory without studies/: by name, and by the path it has in the
    repository; --list names them; an unknown name lists them."""
    listed = cli("run", "--list", cwd=tmp_path)
    assert listed.returncode == 0
    names = [line.split()[0] for line in listed.stdout.splitlines()]
    assert "game_fastball" in names and "example" in names
    assert sorted(names) == sorted(p.stem for p in (ROOT / "studies").glob("*.toml"))
    for given, out in (("example", "a"), ("studies/example.toml", "b")):
        proc = cli("run", given, "--samples", "40", "--out", out, "--quiet", cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
        assert "shipped with mcbat" in proc.stderr
        assert "rows: 40 in 1 chunk file(s)" in proc.stdout
        assert (tmp_path / out / "_mcbat.json").is_file()
    unknown = cli("run", "game_fastbal", cwd=tmp_path)
    assert unknown.returncode == 2 and "game_fastball" in unknown.stderr
    assert len(unknown.stderr.strip().splitlines()) == 1
    missing = cli("run", str(tmp_path / "elsewhere" / "example.toml"), cwd=tmp_path)
    assert missing.returncode == 2 and "cannot read the study file" in missing.stderr


def test_pitches_flag_draws_another_exports_pitches(tmp_path, cli):
    """``--pitches FILE`` runs a study's swing and filters on another export: every drawn
    pitch is one of FILE's, and the dataset's config names FILE (its SHA-256); a study
    without real pitches, a missing file, a file that is no export and one without bat
    tracking exit 2, one line naming the flag."""
    import hashlib

    import mcbat
    from mcbat.statcast import balls_in_play, read

    lines = (ROOT / "data" / "statcast_2025-05-01_bat_tracking.csv").read_text().splitlines()
    excerpt = tmp_path / "excerpt.csv"
    excerpt.write_text("\n".join(lines[:121]) + "\n")  # its header and first 120 pitches
    proc = cli("run", "bat_tracking", "--pitches", str(excerpt), "--samples", "2000",
               "--out", "ds", "--quiet", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "rows of excerpt.csv drawn from" in proc.stdout
    keys = ["game_pk", "at_bat_number", "pitch_number"]
    drawn = mcbat.load(tmp_path / "ds", columns=keys).drop_duplicates()
    real = read(excerpt)
    real = real[balls_in_play(real)][keys]
    assert len(drawn.merge(real, on=keys)) == len(drawn) > 50
    config = json.loads((tmp_path / "ds" / "_mcbat.json").read_text())["study"]
    assert config["pitches"]["file"] == "excerpt.csv"
    assert config["pitches"]["sha256"] == hashlib.sha256(excerpt.read_bytes()).hexdigest()
    (tmp_path / "notes.csv").write_text("a,b\n1,2\n")
    for argv, words in ((("game_fastball", "--pitches", str(excerpt)), "no [pitches]"),
                        (("bat_tracking", "--pitches", "nope.csv"), "no such file"),
                        (("bat_tracking", "--pitches", "notes.csv"), "not a Statcast"),
                        # an export of 2020, before bat tracking: no swing to draw
                        (("bat_tracking", "--pitches",
                          str(ROOT / "data" / "statcast_2020-09-03.csv")), "real_pitches")):
        bad = cli("run", *argv, "--out", "x", cwd=tmp_path)
        assert bad.returncode == 2, bad.stderr
        error = [s for s in bad.stderr.splitlines() if "error" in s]
        assert len(error) == 1 and "--pitches" in error[0] and words in error[0]
    assert not (tmp_path / "x").exists()
