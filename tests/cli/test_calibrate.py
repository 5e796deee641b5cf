"""`mcbat calibrate`: JSON by default (scripts read it), the same with --json, and a line of
prose with --text."""

import json

import pytest

from mcbat.cli import main
from mcbat.papers.cabo2012 import sec5


def _run(capsys, *args):
    code = main(["calibrate", *args])
    out, err = capsys.readouterr()
    return code, out, err


def test_json_is_the_default_and_the_flag_gives_the_same(capsys):
    code, default, err = _run(capsys)
    assert code == 0 and err == ""
    code, flagged, err = _run(capsys, "--json")
    assert code == 0 and err == "" and flagged == default
    result = json.loads(flagged)
    assert result["target_speed"] == sec5.TARGET_SPEED
    assert result["loss_fraction"] == pytest.approx(sec5.LOSS_FRACTION, abs=5e-4)
    assert result["loss_fraction"] == pytest.approx(1 - result["e_star"] ** 2, rel=1e-12)


def test_text_is_one_line_with_the_json_numbers(capsys):
    result = json.loads(_run(capsys, "--target", "1.45")[1])
    code, text, err = _run(capsys, "--target", "1.45", "--text")
    assert code == 0 and err == "" and text.count("\n") == 1
    assert text.startswith(f"e* = {result['e_star']:.7f} (e^2 = {result['loss_fraction']:.7f})")
    assert "exit speed of 1.45 m/s" in text


def test_json_and_text_exclude_each_other(capsys):
    code, out, err = _run(capsys, "--json", "--text")
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "--text: not allowed with argument --json" in err
