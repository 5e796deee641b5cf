"""``docs/sawicki2003.md`` says what ``mcbat reproduce sawicki2003`` and the undercut steps
compute: its generated blocks are recomputed here (the optimal cells and two steps fast,
everything with ``-m slow``), and its description of the scan is checked against the
scan's constants."""

import re

import pytest

from mcbat.papers.sawicki2003 import steps as st
from mcbat.papers.sawicki2003.doc import blocks, splice
from mcbat.papers.sawicki2003.reproduce import markdown_row, optimum_cell, verdict, verdict_lines
from mcbat.papers.sawicki2003.scan import (
    ATTACK_ANGLES_DEG,
    MODELS,
    PER_CELL,
    PITCHES,
    UNDERCUTS_IN,
)
from tests.conftest import ROOT

DOC = ROOT / "docs" / "sawicki2003.md"


@pytest.fixture(scope="module")
def doc_blocks():
    return blocks(DOC.read_text(encoding="utf-8"))


def _table_rows(body):
    return [line for line in body.splitlines() if line.startswith("| ")
            and not line.startswith("| step") and not line.startswith("| pitch")]


def test_splice_replaces_only_the_named_block():
    text = ("a\n<!-- begin generated: x -->\nold\n<!-- end generated: x -->\nb\n"
            "<!-- begin generated: y -->\nkeep\n<!-- end generated: y -->\n")
    out = splice(text, {"x": "new\nlines"})
    assert blocks(out) == {"x": "new\nlines", "y": "keep"}
    assert out.startswith("a\n") and "\nb\n" in out
    with pytest.raises(ValueError, match="z"):
        splice(text, {"z": "?"})


def test_the_doc_has_both_generated_blocks(doc_blocks):
    assert set(doc_blocks) == {"optimum", "steps"}
    assert len(_table_rows(doc_blocks["optimum"])) == len(PITCHES) * len(MODELS)
    assert len(_table_rows(doc_blocks["steps"])) >= len(st.STEPS)


def test_every_optimal_cell_of_the_doc_is_what_the_scan_computes(doc_blocks):
    """Each row's cell is re-solved with the scan's own draws (only that cell's samples),
    so its numbers and the verdict lines must come out digit for digit."""
    rows = _table_rows(doc_blocks["optimum"])
    results = {}
    for line in rows:
        cells = [c.strip() for c in line.strip("|").split("|")]
        pitch, model, undercut, attack = cells[0], cells[1], float(cells[2]), float(cells[3])
        best = optimum_cell(pitch, model, attack, undercut)
        assert best["count"] == PER_CELL
        assert markdown_row(pitch, model, best) == line
        results.setdefault(pitch, {})[model] = best
    lines = [f"- {line}" for line in verdict_lines(verdict(results))]
    assert doc_blocks["optimum"].splitlines()[-len(lines):] == lines


@pytest.mark.parametrize("name", ["no scatter", "level bat"])
def test_deterministic_steps_of_the_doc_are_what_the_scan_computes(doc_blocks, name):
    step = next(s for s in st.STEPS if s.name == name)
    row = {"name": name, "optimum": {p: st.run_step(step, p) for p in PITCHES}}
    assert st.markdown_row(row) in _table_rows(doc_blocks["steps"])


def test_the_doc_describes_the_scan_that_runs():
    raw = DOC.read_text(encoding="utf-8")
    text = " ".join(raw.split())
    cells = UNDERCUTS_IN[2] * ATTACK_ANGLES_DEG[2]
    assert f"{cells} cells of {PER_CELL}" in text
    u_step = (UNDERCUTS_IN[1] - UNDERCUTS_IN[0]) / (UNDERCUTS_IN[2] - 1)
    a_step = (ATTACK_ANGLES_DEG[1] - ATTACK_ANGLES_DEG[0]) / (ATTACK_ANGLES_DEG[2] - 1)
    assert (f"from −{-UNDERCUTS_IN[0]:g} to {UNDERCUTS_IN[1]:g} in ({u_step:.2f} in apart)"
            in text)
    assert (f"from {ATTACK_ANGLES_DEG[0]:g} to {ATTACK_ANGLES_DEG[1]:g}° "
            f"({a_step:g}° apart)" in text)
    assert f"`e_x = {MODELS['compliant']:g}`" in text
    fu, fa = st.FINE_UNDERCUTS_IN, st.FINE_ATTACK_ANGLES_DEG
    assert (f"{(fu[1] - fu[0]) / (fu[2] - 1):.3f} in x {(fa[1] - fa[0]) / (fa[2] - 1):g}° "
            "grid") in text
    # every number of the doc's tables sits in a generated block
    outside = re.sub(r"<!-- begin generated: (\w+) -->.*?<!-- end generated: \1 -->", "",
                     raw, flags=re.S)
    assert not [line for line in outside.splitlines() if line.startswith("| ")]


def _doc_script():
    from validation import sawicki2003_doc

    return sawicki2003_doc


@pytest.mark.slow
def test_the_doc_is_what_the_full_runs_give(doc_blocks):
    """The whole reproduction (its argmax over every cell) and every step."""
    assert _doc_script().render(echo=lambda *_: None) == doc_blocks


@pytest.mark.slow
def test_the_what_if_flight_agrees_with_the_kernel_on_the_calculators_model():
    assert _doc_script().check_what_if_flight() < 0.01
