"""`mcbat` itself: the version, `python -m`, and internal errors (exit 1, `--debug`)."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from mcbat.cli import main
from tests.conftest import ROOT

GOOD = json.loads((ROOT / "examples" / "cabo2012_sec5.json").read_text())


def run_cli(capsys, monkeypatch, payload, *args):
    """Run ``mcbat impact -`` in-process with ``payload`` on stdin."""
    monkeypatch.setattr(sys, "stdin", __import__("io").StringIO(json.dumps(payload)))
    code = main(["impact", "-", *args])
    out, err = capsys.readouterr()
    return code, out, err


def test_internal_error_exits_1_and_debug_shows_the_traceback(capsys, monkeypatch):
    import mcbat.api

    def broken(*args, **kwargs):
        raise RuntimeError("simulated bug")

    monkeypatch.setattr(mcbat.api, "solve", broken)
    code, out, err = run_cli(capsys, monkeypatch, GOOD)
    assert code == 1 and out == ""
    assert err.strip() == ("mcbat: internal error: RuntimeError: simulated bug "
                           "(run with --debug for a traceback)")
    monkeypatch.setattr(sys, "stdin", __import__("io").StringIO(json.dumps(GOOD)))
    code = main(["--debug", "impact", "-"])
    err = capsys.readouterr().err
    assert code == 1 and "Traceback" in err and "simulated bug" in err


def test_version_and_python_dash_m():
    import mcbat

    proc = subprocess.run([sys.executable, "-m", "mcbat", "--version"], capture_output=True,
                          text=True, check=False)
    assert proc.returncode == 0 and proc.stdout.strip() == f"mcbat {mcbat.__version__}"


def test_the_installed_console_script():
    """The ``mcbat`` script of ``[project.scripts]``: its answer and its exit status 2 on a
    bad input, one line, no traceback."""
    script = Path(sys.executable).with_name("mcbat")
    if not script.exists():
        pytest.skip(f"the package is not installed in this environment ({script})")
    proc = subprocess.run([str(script), "impact", str(ROOT / "examples" / "cabo2012_sec5.json")],
                          capture_output=True, text=True, check=False)
    assert proc.returncode == 0 and json.loads(proc.stdout)["status"] == "ok"
    proc = subprocess.run([str(script), "impact", "-"], input="{", capture_output=True,
                          text=True, check=False)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.startswith("mcbat: error: <stdin>")
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
