"""What the figure workers' fork server imports once, before it forks any worker.

Importing this module imports :mod:`it2track.report.figures` (matplotlib with it) and draws one
small figure in the study's style to memory, at both resolutions: matplotlib's font list and
font objects, the text layout engine, the tick machinery and the PNG encoders then start warm in
every worker forked from the server, instead of each worker paying for them on its first
figure. Imported by :mod:`.render` only (the fork server's preload); nothing else should.
"""

from __future__ import annotations

import io

import matplotlib
from matplotlib.figure import Figure

from . import figures  # noqa: F401  (the point: loaded once, before the fork)
from .figures.style import _DRAFT_RC, _RC, DRAFT_DPI, FIGURE_DPI, _compact_png


def _warm_up() -> None:
    for rc, dpi in ((_RC, FIGURE_DPI), ({**_RC, **_DRAFT_RC}, DRAFT_DPI)):
        with matplotlib.rc_context(rc):  # type: ignore[arg-type]
            fig = Figure(figsize=(3.0, 2.0), layout="constrained")
            ax = fig.subplots(1, 2)
            ax[0].plot([0.0, 1.0], [0.1, 1.0], label="IT2FLC 0.2")
            ax[0].set_yscale("log")
            ax[1].imshow([[0.0, 1.0]], cmap="RdBu")
            ax[1].text(0, 0, "0.50", fontsize=7.5)
            ax[0].set_title("σ = 0.05 rad: ISE (rad² s)")
            ax[0].set_xlabel("t (s)")
            fig.legend(loc="outside lower center", frameon=False)
            fig.suptitle("warm-up", fontsize=10)
            buf = io.BytesIO()
            fig.savefig(buf, format="png", dpi=dpi, pil_kwargs={"compress_level": 0})
            if dpi == FIGURE_DPI:
                _compact_png(buf.getvalue())


_warm_up()
