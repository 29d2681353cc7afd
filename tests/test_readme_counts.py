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
