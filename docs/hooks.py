"""MkDocs hooks of the documentation site: the pages outside docs/ that the guide links to
(README, BENCHMARKS, ARCHITECTURE, CHANGELOG, the results tables and every file they
link to) become pages of the site, under ``repo/`` with the repository's layout, and every
relative link is rewritten to where its target lands in the site. A link is therefore
checked against the repository itself: ``mkdocs build --strict`` fails on any link that
does not resolve, in docs/ or outside it.
"""

from __future__ import annotations

import os
import posixpath
import re
from typing import Optional, Set

from mkdocs.structure.files import File, Files

# The repository's root, one level above docs/.
ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

# Markdown links and images `](target)`, reference definitions `[x]: target` and HTML
# `src=`/`href=` attributes: the forms the pages use.
LINK = re.compile(
    r"(?P<pre>\]\(\s*<?|^\s*\[[^\]]+\]:\s*<?|(?:src|href)=\")(?P<target>[^)\s>\"]+)",
    re.MULTILINE,
)

# The pages outside docs/ that are part of the site even when nothing links to them.
ROOT_PAGES = ["README.md", "BENCHMARKS.md", "ARCHITECTURE.md", "CHANGELOG.md"]


def _is_relative(target: str) -> bool:
    return not (
        target.startswith(("#", "/", "mailto:"))
        or re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) is not None
    )


def _repo_path(page: str, target: str) -> Optional[str]:
    """The repository path a relative link of the page at repository path `page` points
    to (without its anchor), or None when it leaves the repository."""
    path = target.split("#", 1)[0]
    if not path:
        return None
    joined = posixpath.normpath(posixpath.join(posixpath.dirname(page), path))
    return None if joined.startswith("..") else joined


def _site_path(repo: str) -> str:
    """Where a repository file lands in the site's sources: docs/X at X, the rest under
    repo/."""
    return repo[len("docs/") :] if repo.startswith("docs/") else "repo/" + repo


def _repo_of(src_uri: str) -> str:
    return src_uri[len("repo/") :] if src_uri.startswith("repo/") else "docs/" + src_uri


def _linked(repo_page: str, seen: Set[str]) -> Set[str]:
    """The repository files outside docs/ reachable by links from `repo_page`, the page
    itself included when it is outside docs/."""
    out: Set[str] = set()
    stack = [repo_page]
    while stack:
        page = stack.pop()
        if page in seen:
            continue
        seen.add(page)
        full = os.path.join(ROOT, page)
        if not os.path.isfile(full):
            continue
        if not page.startswith("docs/"):
            out.add(page)
        if not page.endswith(".md"):
            continue
        with open(full, encoding="utf-8") as f:
            text = f.read()
        for m in LINK.finditer(text):
            target = m.group("target")
            if _is_relative(target):
                repo = _repo_path(page, target)
                if repo is not None:
                    stack.append(repo)
    return out


def on_files(files: Files, config) -> Files:
    seen: Set[str] = set()
    outside: Set[str] = set()
    for f in list(files):
        if f.src_uri.endswith(".md"):
            outside |= _linked("docs/" + f.src_uri, seen)
    for page in ROOT_PAGES:
        outside |= _linked(page, seen)
    for repo in sorted(outside):
        files.append(
            File(
                "repo/" + repo,
                src_dir=ROOT,
                dest_dir=config["site_dir"],
                use_directory_urls=config["use_directory_urls"],
            )
        )
        # The File reads its source from src_dir/src_uri: point it at the real file.
        files.get_file_from_path("repo/" + repo).abs_src_path = os.path.join(ROOT, repo)
    return files


def on_page_markdown(markdown: str, page, config, files: Files) -> str:
    here = page.file.src_uri
    repo_page = _repo_of(here)

    def rewrite(m: "re.Match[str]") -> str:
        target = m.group("target")
        if not _is_relative(target):
            return m.group(0)
        repo = _repo_path(repo_page, target)
        if repo is None:
            return m.group(0)
        anchor = target[len(target.split("#", 1)[0]) :]
        site = _site_path(repo)
        if os.path.isdir(os.path.join(ROOT, repo)):
            # A folder: its README, if the site has it, else the link stays as written
            # and the strict build reports it.
            readme = posixpath.join(site, "README.md")
            if files.get_file_from_path(readme) is None:
                return m.group(0)
            site = readme
        rel = posixpath.relpath(site, posixpath.dirname(here) or ".")
        return m.group("pre") + rel + anchor

    return LINK.sub(rewrite, markdown)
