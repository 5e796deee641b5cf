"""mkdocs hook: links from a page of docs/ to files of the repository outside docs/.

The pages link to the files beside the code (``../mcbat/core/cabo2012/README.md``,
``../data/README.md``, ``../CHANGELOG.md``): right when the Markdown is read in the
repository, outside the site when it is built. This hook rewrites each such link before
mkdocs validates the page: to the file in the repository when ``repo_url`` is set in
mkdocs.yml, to its text otherwise. A link to a file that does not exist stops the build.
"""

from __future__ import annotations

import re
from pathlib import Path, PurePosixPath

from mkdocs.exceptions import PluginError

#: ``[text](target)`` and ``[text](target#anchor)``, not images, not absolute URLs.
_LINK = re.compile(r"(?<!!)\[(?P<text>[^\]]+)\]\((?P<target>[^)\s#]+)(?P<anchor>#[^)\s]*)?\)")


def on_page_markdown(markdown, page, config, files):
    """Rewrite the links of one page that leave docs/."""
    docs_dir = Path(config["docs_dir"]).resolve()
    root = docs_dir.parent
    page_dir = (docs_dir / page.file.src_uri).parent
    repo_url = (config.get("repo_url") or "").rstrip("/")

    def rewrite(match):
        target = match.group("target")
        if "://" in target or target.startswith(("mailto:", "/")):
            return match.group(0)
        path = (page_dir / target).resolve()
        if path.is_relative_to(docs_dir):
            return match.group(0)
        if not path.is_relative_to(root) or not path.exists():
            raise PluginError(f"{page.file.src_uri}: the link {target!r} names no file of "
                              "the repository")
        relative = PurePosixPath(path.relative_to(root).as_posix())
        if not repo_url:
            return match.group("text")
        return f"[{match.group('text')}]({repo_url}/blob/main/{relative}" \
               f"{match.group('anchor') or ''})"

    return _LINK.sub(rewrite, markdown)
