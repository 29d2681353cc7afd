"""The self-contained HTML report: well-formed, every figure embedded, every verdict shown,
text escaped, no script or network; and it renders in headless Chromium when available."""

from __future__ import annotations

import base64
import shutil
import subprocess
from dataclasses import replace
from html.parser import HTMLParser
from pathlib import Path

import matplotlib.image
import pytest

from it2track.experiments.analysis import evaluate_claims, summarise
from it2track.experiments.study import PDTuning, StudyConfig, run_study
from it2track.report.figures import write_figures
from it2track.report.html import write_html
from it2track.tracking import LoopConfig

VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source",
        "track", "wbr"}  # fmt: skip
COMMAND = "it2track reproduce --seeds 3 --out 'results <&>'"


class _Collector(HTMLParser):
    """Collects tags, image sources, links and text; checks that elements nest properly."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.errors: list[str] = []
        self.tags: list[str] = []
        self.imgs: list[dict[str, str | None]] = []
        self.hrefs: list[str] = []
        self.text: list[str] = []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        a = dict(attrs)
        if tag == "img":
            self.imgs.append(a)
        if "href" in a and a["href"] is not None:
            self.hrefs.append(a["href"])
        if tag not in VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.handle_starttag(tag, attrs)
        if tag not in VOID:
            self.stack.pop()

    def handle_endtag(self, tag):
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes <{self.stack[-1] if self.stack else None}>")
            if tag in self.stack:
                while self.stack and self.stack.pop() != tag:
                    pass
        else:
            self.stack.pop()

    def handle_data(self, data):
        self.text.append(data)


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory):
    config = StudyConfig(
        seeds=3,
        sweep_seeds=3,
        fou_sweep=(0.0, 0.2),
        noise_levels=(0.0, 0.1),
        loop=LoopConfig(duration=2.0),
        pd=PDTuning(seeds=2, kp_grid=(5.0, 20.0), kd_grid=(0.0, 0.1)),
    )
    result = run_study(config)
    summary = summarise(result.rows)
    claims = evaluate_claims(result.rows, fous=config.fous, main_fou=config.main_fou,
                             trajectories=config.trajectories)
    # A statement with markup in it: must come out escaped.
    claims[0] = replace(claims[0], statement=claims[0].statement + " <b>& more</b>")
    out = tmp_path_factory.mktemp("report")
    figures = write_figures(result, summary, out / "figures")
    manifest = {"command": COMMAND, "config": config.to_dict(), "git_revision": "abc123",
                "versions": {"python": "3.11"}, "elapsed_s": 1.5}
    path = write_html(out / "report.html", result=result, summary=summary, claims=claims,
                      manifest=manifest, figures=figures, elapsed_s=1.5)
    return path, figures, claims


@pytest.fixture(scope="module")
def parsed(report):
    path, _, _ = report
    parser = _Collector()
    parser.feed(path.read_text(encoding="utf-8"))
    parser.close()
    return parser


def test_written_atomically_and_alone(report):
    path, _, _ = report
    assert path.is_file()
    assert sorted(p.name for p in path.parent.iterdir()) == ["figures", "report.html"]


def test_parses_and_nests(parsed):
    assert parsed.errors == []
    assert parsed.stack == [], f"unclosed elements: {parsed.stack}"
    for tag in ("html", "head", "title", "style", "body", "table", "figure"):
        assert tag in parsed.tags, f"no <{tag}>"


def test_self_contained(parsed, report):
    path, _, _ = report
    text = path.read_text(encoding="utf-8")
    assert "script" not in parsed.tags, "the report must not need JavaScript"
    assert "<link" not in text
    for img in parsed.imgs:
        assert (img.get("src") or "").startswith("data:"), "image not embedded"
    for href in parsed.hrefs:
        assert href.startswith("#"), f"external link {href!r}"
    assert "http://" not in text and "https://" not in text


def test_every_figure_embedded(parsed, report):
    _, figures, _ = report
    srcs = [img.get("src") or "" for img in parsed.imgs]
    assert len(srcs) == len(figures)
    payloads = {base64.b64decode(s.split(",", 1)[1]) for s in srcs
                if s.startswith("data:image/png;base64,")}
    for key, png in figures.items():
        assert png.read_bytes() in payloads, f"figure {key} is not embedded"


def test_every_claim_and_verdict_shown(parsed, report):
    _, _, claims = report
    text = " ".join("".join(parsed.text).split())
    for c in claims:
        assert c.verdict in text, f"verdict of {c.id} missing"
        assert " ".join(c.criterion.split()) in text, f"criterion of {c.id} missing"
        assert " ".join(c.statement.split()) in text, f"statement of {c.id} missing"


def test_text_is_escaped(report, parsed):
    path, _, _ = report
    raw = path.read_text(encoding="utf-8")
    assert "<b>& more</b>" not in raw
    assert "&lt;b&gt;&amp; more&lt;/b&gt;" in raw
    assert "results &lt;&amp;&gt;" in raw
    assert COMMAND in "".join(parsed.text)


def test_sections_present(parsed):
    text = "".join(parsed.text)
    for heading in ("Setup", "Assumptions", "Results", "Claims", "Summary table",
                    "How to rerun"):
        assert heading in text, heading
    for fact in ("5.6 m", "3.16 rad", "atan2", "zero-order hold", "V0", "trapezoid",
                 "Common random numbers", "dead zone", "misprinted eq. 9"):
        assert fact in text, f"assumption about {fact!r} missing"


def _chromium() -> str | None:
    for name in ("chromium", "chromium-browser"):
        exe = shutil.which(name)
        if exe:
            return exe
    return None


def _screenshot(exe: str, page: Path, shot: Path, profile: Path, size: str) -> None:
    cmd = [
        exe, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--hide-scrollbars", f"--user-data-dir={profile}", f"--screenshot={shot}",
        f"--window-size={size}", page.resolve().as_uri(),
    ]  # fmt: skip
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=180, check=False)
    assert proc.returncode == 0, f"chromium failed ({proc.returncode}): {proc.stderr[-2000:]}"


def test_renders_in_headless_chromium(report, tmp_path):
    exe = _chromium()
    if exe is None:
        pytest.skip("chromium not installed: apt-get install chromium (or chromium-browser)")
    path, _, _ = report
    shot = tmp_path / "shot.png"
    _screenshot(exe, path, shot, tmp_path / "profile", "1280,2000")
    assert shot.is_file() and shot.stat().st_size > 20_000, "no or tiny screenshot"
    img = matplotlib.image.imread(shot)[..., :3]
    assert img.shape[:2] == (2000, 1280)
    ink = (img < 0.8).any(axis=2).mean()
    assert ink > 0.01, f"screenshot nearly blank ({ink:.2%} ink)"


def test_figures_decode_in_chromium(report, tmp_path):
    """A window tall enough for the whole page: the embedded figures must be drawn (the page's
    own text and tables are grey; saturated colour comes from the figures)."""
    exe = _chromium()
    if exe is None:
        pytest.skip("chromium not installed: apt-get install chromium (or chromium-browser)")
    path, _, _ = report
    shot = tmp_path / "tall.png"
    _screenshot(exe, path, shot, tmp_path / "profile", "1280,16000")
    img = matplotlib.image.imread(shot)[..., :3]
    saturation = img.max(axis=2) - img.min(axis=2)
    coloured = (saturation > 0.4).mean()
    assert coloured > 0.01, f"figures not drawn: {coloured:.2%} coloured pixels"
