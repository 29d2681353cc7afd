"""README's test counts are those pytest collects (``benchmarks/readme_figures.py`` prints
them; README quotes its output).

Counting costs nothing here: the whole suite's collected items are this session's. So the
check runs when the session is the README's test command (every test path, nothing deselected)
and skips, saying so, in a partial run.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def readme_counts(text: str) -> tuple[int, int]:
    """(tests, strict expected failures) as the README's Tests section quotes them:
    ``**2 342 tests** (... 5 of them strict expected failures ...)``."""
    section = text[text.index("\n## Tests"):]
    tests = re.search(r"\*\*(\d[\d  ,]*) tests\*\*", section)
    xfail = re.search(r"(\d+) of them strict expected failures", section)
    if tests is None or xfail is None:
        raise AssertionError("README's Tests section must say '**N tests**' and "
                             "'K of them strict expected failures'")
    return int(re.sub(r"\D", "", tests.group(1))), int(xfail.group(1))


def test_the_readme_sentence_is_read_as_written():
    text = "intro\n## Tests\n\n**2 342 tests** (`pytest --collect-only`; 5 of them strict " \
           "expected failures)\n## Next"
    assert readme_counts(text) == (2342, 5)
    with pytest.raises(AssertionError, match="must say"):
        readme_counts("\n## Tests\nabout 2 000 tests\n")


def _whole_suite(config: pytest.Config) -> bool:
    opt = config.option
    return (config.args_source is pytest.Config.ArgsSource.TESTPATHS
            and not getattr(opt, "keyword", "") and not getattr(opt, "markexpr", "")
            and not getattr(opt, "deselect", None) and not getattr(opt, "lf", False)
            and not getattr(opt, "failedfirst", False))


def test_readme_quotes_what_pytest_collects(request):
    session = request.session
    if not _whole_suite(session.config):
        pytest.skip("checked when the whole suite runs (README's test command: no file, -k or "
                    "-m arguments)")
    collected = len(session.items)
    xfail = sum(1 for item in session.items if item.get_closest_marker("xfail"))
    assert readme_counts(README.read_text(encoding="utf-8")) == (collected, xfail), (
        f"README's Tests section is stale: pytest collects {collected} tests, {xfail} of them "
        "marked xfail; re-measure with benchmarks/readme_figures.py and quote its output")


CONFORMANCE = README.parent / "docs" / "guide" / "conformance.md"


def conformance_figures(readme: str, page: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(README's, the conformance page's) agreeing count, its percentage, the fuzzy systems'
    count and percentage, the number of files and of fuzzy systems; then the term libraries
    that agree, the files that are no systems, and the files agreeing as systems or as term
    libraries with their percentage."""
    flat = " ".join(readme.split())
    a = re.search(r"Of the (\d+) public example files .*?\*\*(\d+) \(([\d.]+) %\) load "
                  r"unmodified and agree\*\*.*?(\d+) of the (\d+) that are fuzzy systems, "
                  r"([\d.]+) %\)\. (\d+) of the (\d+) files that are no fuzzy systems .*?agree as "
                  r"term libraries.*?\*\*(\d+) of the \1 files, ([\d.]+) %, load and agree, as "
                  r"systems or as term libraries\*\*", flat)
    b = re.search(r"\*\*(\d+) of (\d+) files \(([\d.]+) %\) load and agree\*\*\. Of the (\d+) "
                  r"files that are fuzzy systems .*?\*\*(\d+) \(([\d.]+) %\) load and agree\*\*\. "
                  r"Of those (\d+), (\d+) are term libraries that agree as such.*?\*\*(\d+) of "
                  r"\2 files \(([\d.]+) %\) load and agree, as systems or as term libraries\*\*",
                  " ".join(page.split()))
    if a is None or b is None:
        raise AssertionError("README's 'Files users already have' paragraph or the conformance "
                             "page no longer says its figures in the expected words")
    files, agree, pct, agree_sys, systems, pct_sys, libs, others, both, pct_both = a.groups()
    (page_agree, page_files, page_pct, page_systems, page_agree_sys, page_pct_sys, page_others,
     page_libs, page_both, page_pct_both) = b.groups()
    return ((agree, pct, agree_sys, pct_sys, files, systems, libs, others, both, pct_both),
            (page_agree, page_pct, page_agree_sys, page_pct_sys, page_files, page_systems,
             page_libs, page_others, page_both, page_pct_both))


def test_readme_quotes_the_conformance_page():
    """README's conformance figures are the generated page's (tests/conformance/make_table.py
    writes the page from the measurements; test_conformance checks it is current)."""
    ours, page = conformance_figures(README.read_text(encoding="utf-8"),
                                     CONFORMANCE.read_text(encoding="utf-8"))
    assert ours == page, ("README's conformance figures (agree, %, of fuzzy systems, %, files, "
                          "systems, term libraries agreeing, files no systems, agreeing as "
                          "systems or term libraries, %) "
                          f"{ours} differ from docs/guide/conformance.md's {page}")


def test_the_conformance_sentences_are_read_as_written():
    readme = ("Of the 12 public example files in x, **9 (75.0 %) load unmodified and agree** "
              "with y (9 of the 10 that\n are fuzzy systems, 90.0 %). 1 of the 2 files that are "
              "no fuzzy systems (z) agree as term libraries: ... (counting them, **10 of the 12 "
              "files, 83.3 %, load and agree, as systems or as term libraries**); ...")
    page = ("compares: **9 of 12 files (75.0 %) load and agree**. Of the 10 files that are "
            "fuzzy systems (the rest ...), **9 (90.0 %) load and agree**. Of those 2, 1 are "
            "term libraries that agree as such: ...; counting them, **10 of 12 files (83.3 %) "
            "load and agree, as systems or as term libraries**.")
    assert conformance_figures(readme, page) == (
        ("9", "75.0", "9", "90.0", "12", "10", "1", "2", "10", "83.3"),) * 2
    with pytest.raises(AssertionError, match="expected words"):
        conformance_figures("about 90 % agree", page)
