"""The documentation site's API page names every public name, and its link rewriting
sends each relative link to where its target lands in the site."""

import importlib.util
import os
import re

import stillpoint

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), "..", ".."))


def _hooks():
    spec = importlib.util.spec_from_file_location("hooks", os.path.join(ROOT, "docs", "hooks.py"))
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except ImportError:  # mkdocs absent: the strict build in test.sh checks the site
        return None
    return module


def test_api_page_names_every_public_name():
    with open(os.path.join(ROOT, "docs", "api.md"), encoding="utf-8") as f:
        named = set(re.findall(r"^::: stillpoint\.(\w+)$", f.read(), re.MULTILINE))
    assert named == set(stillpoint.__all__), (
        f"docs/api.md lacks {sorted(set(stillpoint.__all__) - named)}, "
        f"names no longer public {sorted(named - set(stillpoint.__all__))}"
    )


def test_links_go_where_their_targets_land():
    hooks = _hooks()
    if hooks is None:
        return
    # A guide page's link out of docs/ lands under repo/, a results page's link back into
    # docs/ lands at the page itself; anchors are kept; leaving the repository is not
    # a repository path.
    assert hooks._repo_path("docs/integration.md", "../BENCHMARKS.md#x") == "BENCHMARKS.md"
    assert hooks._site_path("BENCHMARKS.md") == "repo/BENCHMARKS.md"
    assert hooks._site_path("docs/python.md") == "python.md"
    assert hooks._repo_path("results/quad/quad.md", "../../docs/python.md") == "docs/python.md"
    assert hooks._repo_path("README.md", "../outside.md") is None
    assert hooks._is_relative("python.md#a") and not hooks._is_relative("https://x.org/a.md")
    # Every file the guide reaches outside docs/ exists, and the front pages are in it.
    reached = set()
    seen = set()
    for page in os.listdir(os.path.join(ROOT, "docs")):
        if page.endswith(".md"):
            reached |= hooks._linked("docs/" + page, seen)
    assert {"BENCHMARKS.md", "README.md"} <= reached
    assert all(os.path.isfile(os.path.join(ROOT, p)) for p in reached)
