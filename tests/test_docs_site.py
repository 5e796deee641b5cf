"""The documentation site (mkdocs.yml) builds with ``--strict``, every Markdown table of
docs/ comes out as an HTML table with all its rows, and no docstring's Sphinx role
(``:func:`x```) reaches a page as raw text. Skipped without mkdocs (``pip install -e
".[docs]"``, which CI's docs step installs)."""

import html
import importlib.util
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("mkdocs") is None
    or importlib.util.find_spec("mkdocstrings") is None,
    reason="mkdocs and mkdocstrings not installed (pip install -e '.[docs]')")

ROLE = re.compile(r":(func|class|mod|meth|data|attr):")
FENCE = re.compile(r"^\s*(```|~~~)")


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--quiet",
                           "--site-dir", str(out)], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return out


def markdown_tables(text: str) -> list[list[str]]:
    """The tables of a Markdown page: each a list of its lines, a table being a block of
    consecutive lines that start with ``|`` outside fenced code."""
    tables, current, fenced = [], [], False
    for line in text.splitlines():
        if FENCE.match(line):
            fenced = not fenced
        is_row = not fenced and line.lstrip().startswith("|")
        if is_row:
            current.append(line.strip())
        elif current:
            tables.append(current)
            current = []
    if current:
        tables.append(current)
    return tables


def is_separator(line: str) -> bool:
    return bool(re.fullmatch(r"\|?\s*:?-+:?\s*(\|\s*:?-+:?\s*)*\|?", line))


def page_html(site: Path, page: Path) -> str:
    rel = page.relative_to(DOCS).with_suffix("")
    target = site / "index.html" if rel.name == "index" and rel.parent == Path(".") \
        else site / rel / "index.html"
    return target.read_text(encoding="utf-8")


PAGES = sorted(p for p in DOCS.rglob("*.md") if "_hooks" not in p.parts
               and "reference" not in p.parts)


def test_the_pages_are_found():
    assert len(PAGES) > 20 and DOCS / "errors.md" in PAGES


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(DOCS)))
def test_every_markdown_table_is_an_html_table(site, page):
    tables = markdown_tables(page.read_text(encoding="utf-8"))
    built = page_html(site, page)
    content = built[built.find('<article'):built.rfind('</article>')]
    assert content.count("<table") == len(tables), (
        f"{page.name}: {len(tables)} Markdown tables, {content.count('<table')} HTML tables")
    rows = sum(sum(not is_separator(line) for line in t) for t in tables)
    assert content.count("<tr") == rows, f"{page.name}: {rows} table rows in Markdown"
    for paragraph in re.findall(r"<p>(.*?)</p>", content, re.S):
        text = html.unescape(re.sub(r"<[^>]+>", "", paragraph)).strip()
        assert not (text.startswith("|") and text.count("|") >= 3), \
            f"{page.name}: a table row rendered as text: {text[:120]}"


def test_no_raw_sphinx_role_in_the_built_site(site):
    found = {}
    for path in site.rglob("*.html"):
        text = re.sub(r"<[^>]+>", "", path.read_text(encoding="utf-8"))
        hits = ROLE.findall(html.unescape(text))
        if hits:
            found[str(path.relative_to(site))] = len(hits)
    assert not found, found


def test_the_dataset_reference_documents_load(site):
    page = (site / "reference" / "dataset" / "index.html").read_text(encoding="utf-8")
    assert 'id="mcbat.dataset.load.load"' in page
    assert "allow_partial" in page  # its signature and parameters, not only its name
