"""The animated top view of robots tracking side by side (report/animation.py)."""

from __future__ import annotations

import dataclasses

import numpy as np
import PIL.Image
import pytest

from it2track.paper import heading_fls
from it2track.report.animation import AnimationPanel, tracking_gif
from it2track.tracking import (
    FuzzyHeadingController,
    LoopConfig,
    get_trajectory,
    run_grid,
    simulate,
)


@pytest.fixture(scope="module")
def traces():
    ctrls = [FuzzyHeadingController(fls=heading_fls(0.2), name="IT2FLC"),
             FuzzyHeadingController(fls=heading_fls(0.0), name="FLC")]
    runs = run_grid(2, 1, [0.05], 1)
    config = LoopConfig(duration=1.0)
    curved = simulate(ctrls, [get_trajectory("curved")], runs, config)
    slow = simulate(ctrls, [get_trajectory("curved")], runs,
                    dataclasses.replace(config, ts=0.02))
    return curved, slow


def _frames(path):
    with PIL.Image.open(path) as im:
        out = []
        for k in range(im.n_frames):
            im.seek(k)
            out.append((np.asarray(im.convert("RGB")), im.info.get("duration")))
        return im.size, out


def test_gif_frames_and_determinism(tmp_path, traces):
    curved, _ = traces
    panels = [AnimationPanel("kinematic", curved, ("IT2FLC", "FLC")),
              AnimationPanel("again", curved, ("FLC", "IT2FLC"))]
    first = tracking_gif(panels, tmp_path / "a.gif", frames=4, fps=5, panel_size=2.0, dpi=50)
    assert first == tmp_path / "a.gif"
    size, frames = _frames(first)
    assert size == (200, 125)  # 2 panels x 2 in x 50 dpi, (2 + 0.5) in high
    assert len(frames) == 4
    assert [d for _, d in frames] == [200, 200, 200, 1700]  # the last frame held 1.5 s more
    # the robots move: no two frames alike
    assert all(not np.array_equal(frames[i][0], frames[i + 1][0]) for i in range(3))
    # the bytes depend on the data only
    tracking_gif(panels, tmp_path / "b.gif", frames=4, fps=5, panel_size=2.0, dpi=50)
    assert (tmp_path / "a.gif").read_bytes() == (tmp_path / "b.gif").read_bytes()


def test_bad_panels_are_refused(tmp_path, traces):
    curved, slow = traces
    out = tmp_path / "x.gif"
    good = AnimationPanel("ok", curved, ("a", "b"))
    with pytest.raises(ValueError, match="at least one"):
        tracking_gif([], out)
    with pytest.raises(ValueError, match="1 labels for 2 runs"):
        tracking_gif([AnimationPanel("short", curved, ("a",))], out)
    with pytest.raises(ValueError, match="another time grid"):
        tracking_gif([good, AnimationPanel("slow", slow, ("a", "b"))], out)
    with pytest.raises(ValueError, match=r"panels\[1\] is a Trace, not an AnimationPanel"):
        tracking_gif([good, curved], out)  # type: ignore[list-item]
    for frames in (1, 501, 2.0, True):
        with pytest.raises(ValueError, match="frames="):
            tracking_gif([good], out, frames=frames)  # type: ignore[arg-type]
    for fps in (0.4, 51, "10"):
        with pytest.raises(ValueError, match="fps="):
            tracking_gif([good], out, fps=fps)  # type: ignore[arg-type]
    assert not out.exists()
