"""Every relative link and anchor in README.md, CHANGELOG.md, CONTRIBUTING.md and docs/**/*.md
resolves: the file (or folder) exists, and a ``#anchor`` names a heading of the target page
(GitHub's and MyST's heading slugs, which agree; MyST makes anchors for levels 1-3 only,
``myst_heading_anchors = 3`` in docs/conf.py)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
GENERATED = ("_build", "generated", "auto_examples")
PAGES = sorted(
    [ROOT / "README.md", ROOT / "CHANGELOG.md", ROOT / "CONTRIBUTING.md"]
    + [p for p in (ROOT / "docs").rglob("*.md")
       if not any(part in GENERATED for part in p.relative_to(ROOT).parts)]
)
#: Inline links and images ``[text](target "title")``; reference definitions ``[id]: target``.
INLINE = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFDEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def _prose_lines(text: str, *, blank_code: bool = True) -> list[tuple[int, str]]:
    """Lines outside fenced code blocks, with inline code spans blanked out (unless
    ``blank_code`` is false)."""
    out, fence = [], None
    for number, line in enumerate(text.splitlines(), 1):
        m = re.match(r"^\s*(`{3,}|~{3,})", line)
        if m:
            mark = m.group(1)
            if fence is None:
                fence = mark
                continue
            if mark[0] == fence[0] and len(mark) >= len(fence) and not line.strip()[
                    len(mark):].strip():
                fence = None
                continue
        if fence is None:
            out.append((number, re.sub(r"(`+)(?:(?!\1).)+?\1", "``", line) if blank_code
                        else line))
    return out


def slug(title: str) -> str:
    """The anchor GitHub and MyST give a heading: its text (links, code and emphasis marks
    removed) lower-cased, characters other than word characters, hyphens and spaces dropped,
    spaces turned into hyphens."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", title)  # [text](url) -> text
    text = re.sub(r"[`*]", "", text)
    text = re.sub(r"(?<!\w)_|_(?!\w)", "", text)  # _emphasis_, not snake_case
    return re.sub(r"[^\w\- ]", "", text.strip().lower()).replace(" ", "-")


def anchors(page: Path, *, max_level: int = 6) -> set[str]:
    """Every heading anchor of a Markdown page (repeats get ``-1``, ``-2``, ... as on
    GitHub)."""
    seen: dict[str, int] = {}
    found = set()
    for _, line in _prose_lines(page.read_text(encoding="utf-8"), blank_code=False):
        m = HEADING.match(line)
        if not m:
            continue
        base = slug(m.group(2))
        n = seen.get(base, 0)
        seen[base] = n + 1
        if len(m.group(1)) <= max_level:
            found.add(base if n == 0 else f"{base}-{n}")
    return found


def links(page: Path) -> list[tuple[int, str]]:
    """The relative link targets of a page, with their line numbers."""
    out = []
    raw = page.read_text(encoding="utf-8").splitlines()
    for number, line in _prose_lines(page.read_text(encoding="utf-8")):
        targets = [m.group(1) for m in INLINE.finditer(line)]
        m = REFDEF.match(raw[number - 1])
        if m:
            targets.append(m.group(1))
        out.extend((number, t) for t in targets if not SCHEME.match(t))
    return out


def broken(page: Path) -> list[str]:
    """What does not resolve in ``page``: ``"file:line: target: why"``."""
    problems = []
    where = page.relative_to(ROOT) if page.is_relative_to(ROOT) else page
    for number, target in links(page):
        path_part, _, anchor = target.partition("#")
        dest = (page.parent / path_part).resolve() if path_part else page
        if not dest.exists():
            problems.append(f"{where}:{number}: {target}: no such file or folder")
            continue
        if not anchor:
            continue
        if dest.suffix != ".md" or dest.is_dir():
            problems.append(f"{where}:{number}: {target}: an anchor into a non-Markdown target")
            continue
        in_sphinx = (ROOT / "docs") in dest.parents and (ROOT / "docs") in page.parents
        if anchor not in anchors(dest, max_level=3 if in_sphinx else 6):
            problems.append(f"{where}:{number}: {target}: no heading with anchor #{anchor} in "
                            f"{dest.name}")
    return problems


def test_the_pages_exist():
    for name in ("README.md", "CHANGELOG.md", "CONTRIBUTING.md"):
        assert (ROOT / name).is_file(), name
    assert len(PAGES) > 10


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_and_anchor_resolves(page):
    assert broken(page) == []


def test_the_checker_finds_broken_links_and_anchors(tmp_path):
    (tmp_path / "other.md").write_text("# Other page\n\n#### Deep — `code` here\n")
    page = tmp_path / "page.md"
    page.write_text(
        "# Title\n\n## A *b* `c_d` and [link](other.md)\n\n"
        "[ok](other.md#other-page) [ok2](#a-b-c_d-and-link) ![img](other.md)\n"
        "[deep](other.md#deep--code-here)\n"
        "[bad file](missing.md) [bad anchor](other.md#nope) [bad self](#nothing)\n"
        "`[in code](missing2.md)` and https://example.invalid/x.md\n"
        "```\n[in a fence](missing3.md)\n```\n"
        "[ref]: gone/\n"
    )
    found = broken(page)
    assert [p.split(": ", 1)[1] for p in found] == [
        "missing.md: no such file or folder",
        "other.md#nope: no heading with anchor #nope in other.md",
        "#nothing: no heading with anchor #nothing in page.md",
        "gone/: no such file or folder",
    ], found


def test_slugs_match_the_headings_we_link_to():
    assert slug("Half-track l — `half_track`") == "half-track-l--half_track"
    assert slug("Robustness to the open modelling choices") == (
        "robustness-to-the-open-modelling-choices")
    assert slug("The study: what `it2track reproduce` finds") == (
        "the-study-what-it2track-reproduce-finds")
    assert slug("[Unreleased]") == "unreleased"
