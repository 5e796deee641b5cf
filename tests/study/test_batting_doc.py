"""docs/batting.md quotes what the code gives: its generated blocks and the numbers in
its text are those ``python -m validation batting_doc`` computes now."""

import re

import pytest

from mcbat.papers.sawicki2003.doc import blocks
from tests.conftest import ROOT
from validation import batting_doc

TEXT = (ROOT / "docs" / "batting.md").read_text(encoding="utf-8")


DOC = batting_doc


def test_every_block_and_inline_number_is_in_the_doc_once():
    assert set(blocks(TEXT)) == {"location_q", "plate_pitches", "run_game_fastball",
                                 "run_real_pitches", "spin_vs_nathan", "presets_vs_real",
                                 "population_fit"}
    given = DOC.inline_values(TEXT)
    assert [name for name, value in given.items() if value is None] == []


def test_the_fast_blocks_and_the_presets_numbers_are_what_the_code_gives():
    """The ``q`` table against location, the real pitches at the plate and the numbers
    quoted from them, and the game preset's ``e*``, ``q`` and ``r`` (seconds)."""
    bodies, values = DOC.render(["location_q", "plate_pitches", "game_preset", "in_play"])
    current = blocks(TEXT)
    for name, body in bodies.items():
        assert current[name] == body, name
    given = DOC.inline_values(TEXT)
    assert {name: given[name] for name in values} == values


def test_a_drifted_number_is_found_and_rewritten():
    """The check can fail: a changed number of the text is reported and put back."""
    drifted = TEXT.replace("`r = 0.2194`", "`r = 0.2190`")
    assert drifted != TEXT
    assert DOC.inline_values(drifted)["r_sweet"] == "0.2190"
    assert DOC.splice_inline(drifted, {"r_sweet": "0.2194"}) == TEXT


@pytest.mark.slow
def test_the_runs_and_the_numbers_quoted_from_them_are_what_the_code_gives():
    """``mcbat run studies/game_fastball.toml`` (20,000 samples with their flight),
    ``studies/real_pitches.toml``, the presets against the real balls in play (seven
    runs of 20,000) and the two population fits (~30 s each)."""
    bodies, values = DOC.render(["run_game_fastball", "run_real_pitches", "presets_vs_real",
                                 "population_fit", "attack_free"])
    current = blocks(TEXT)
    for name, body in bodies.items():
        assert current[name] == body, name
    given = DOC.inline_values(TEXT)
    assert {name: given[name] for name in values} == values


def test_the_tables_outside_the_generated_blocks_are_the_typed_ones():
    """The keys (the code's defaults), the location tables' files (their shipped values)
    and the record of an earlier preset's runs; every other table is generated."""
    outside = re.sub(r"<!-- begin generated: ([\w-]+) -->.*?<!-- end generated: \1 -->", "",
                     TEXT, flags=re.S)
    lines = outside.splitlines()
    headers = [line for i, line in enumerate(lines) if line.startswith("| ")
               and i + 1 < len(lines) and lines[i + 1].startswith("|---")]
    assert headers == ["| key | unit in files | a bare number in a JSON case (range) | default "
                       "| meaning |",
                       "| `location` | file | shape | used by |",
                       "| change | backspin / Nathan per bin | slope (rpm/°) |"]
