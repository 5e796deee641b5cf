"""The generated blocks of ``docs/sawicki2003.md``.

A block is the text between ``<!-- begin generated: NAME -->`` and
``<!-- end generated: NAME -->``; ``validation/sawicki2003_doc.py`` renders it from the
outputs of ``mcbat reproduce sawicki2003`` (``table.md``) and of the undercut steps
(``mcbat.papers.sawicki2003.steps``), and writes or checks it.
"""

from __future__ import annotations

import re

__all__ = ["blocks", "splice"]

_BLOCK = re.compile(r"<!-- begin generated: (?P<name>[\w-]+) -->\n(?P<body>.*?)"
                    r"<!-- end generated: (?P=name) -->", re.S)


def blocks(text: str) -> dict:
    """``name -> body`` of every generated block of ``text`` (the body without its
    trailing newline)."""
    out = {}
    for m in _BLOCK.finditer(text):
        if m["name"] in out:
            raise ValueError(f"generated block {m['name']!r} appears twice")
        out[m["name"]] = m["body"].rstrip("\n")
    return out


def splice(text: str, bodies: dict) -> str:
    """``text`` with the body of each block named in ``bodies`` replaced."""
    missing = set(bodies) - set(blocks(text))
    if missing:
        raise ValueError(f"no generated block named {sorted(missing)}")

    def replace(m):
        if m["name"] not in bodies:
            return m[0]
        return (f"<!-- begin generated: {m['name']} -->\n{bodies[m['name']]}\n"
                f"<!-- end generated: {m['name']} -->")

    return _BLOCK.sub(replace, text)


def stale_blocks(doc_name: str, text: str, bodies: dict, echo=print) -> list:
    """Names of the ``bodies`` that differ from ``text``'s blocks; a unified diff of each
    is passed to ``echo``."""
    import difflib

    current = blocks(text)
    stale = [name for name in bodies if current.get(name) != bodies[name]]
    for name in stale:
        echo("".join(difflib.unified_diff(
            (current.get(name, "") + "\n").splitlines(True),
            (bodies[name] + "\n").splitlines(True),
            f"{doc_name} ({name})", f"code ({name})")), end="")
    return stale
