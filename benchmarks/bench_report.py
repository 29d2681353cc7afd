"""What the presentation layer of ``it2track reproduce`` costs (issue #12): figures and report.

Runs the study once (``--quick``: the smoke configuration, else the default one) and then, on
that result, prints:

1. per figure: CPU seconds to build it (matplotlib artists), to draw and write the PNG
   (constrained layout, Agg, palette quantisation) and to write the SVG;
2. all figures in this process (``write_figures``), PNG only and PNG + SVG, wall time;
3. all figures through :class:`~it2track.report.render.FigureRenderer` with 0, 1 and 2 worker
   processes (worker start-up included), wall time;
4. the HTML page (``write_html``: templates, captions, base64 figures), wall time;
5. the load average before and after, since the numbers mean little on a busy machine.

Run from the repository root::

    .venv/bin/python benchmarks/bench_report.py --quick
    .venv/bin/python benchmarks/bench_report.py
"""

from __future__ import annotations

import argparse
import io
import os
import tempfile
import time
from pathlib import Path

import matplotlib


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the smoke study (seconds)")
    args = parser.parse_args()

    from it2track.cli.reproduce import _quick
    from it2track.experiments.analysis import evaluate_claims, summarise
    from it2track.experiments.study import StudyConfig, run_study
    from it2track.report.figures import draw_figure, figure_plan, write_figures
    from it2track.report.figures.style import _DRAFT_RC, _RC, FIGURE_DPI, _compact_png, _save
    from it2track.report.html import write_html
    from it2track.report.render import FigureRenderer

    print(f"load average before: {_load()}  (cores: {os.cpu_count()})")
    config = _quick(StudyConfig()) if args.quick else StudyConfig()
    t0 = time.perf_counter()
    result = run_study(config)
    print(f"study ({'quick' if args.quick else 'default'}): {time.perf_counter() - t0:.1f} s "
          "wall (not part of the figures)")
    summary = summarise(result.rows)
    claims = evaluate_claims(result.rows, fous=config.fous, main_fou=config.main_fou,
                             trajectories=config.trajectories)

    print("\n1. per figure, CPU seconds (this process)")
    print(f"{'figure':<18} {'build':>7} {'PNG':>7} {'SVG':>7}")
    totals = [0.0, 0.0, 0.0]
    with matplotlib.rc_context(_RC):  # type: ignore[arg-type]
        for key in figure_plan(result, summary):
            c0 = time.process_time()
            fig = draw_figure(key, result, summary)
            c1 = time.process_time()
            buf = io.BytesIO()
            fig.savefig(buf, format="png", dpi=FIGURE_DPI, pil_kwargs={"compress_level": 0})
            _compact_png(buf.getvalue())
            c2 = time.process_time()
            fig.set_layout_engine("none")
            fig.savefig(io.BytesIO(), format="svg", metadata={"Date": None, "Creator": None})
            c3 = time.process_time()
            row = (c1 - c0, c2 - c1, c3 - c2)
            totals = [a + b for a, b in zip(totals, row, strict=True)]
            print(f"{key:<18} {row[0]:7.2f} {row[1]:7.2f} {row[2]:7.2f}")
    print(f"{'total':<18} {totals[0]:7.2f} {totals[1]:7.2f} {totals[2]:7.2f}")

    print("\n1b. per figure, CPU seconds of its draft (reproduce --quick: DRAFT_DPI, fixed "
          "spacing, the first trajectory of a figure with a panel per trajectory) against the "
          "same draft with every trajectory")
    print(f"{'figure':<18} {'draft':>7} {'all':>7}")
    draft_totals = [0.0, 0.0]
    with tempfile.TemporaryDirectory() as tmp, \
            matplotlib.rc_context({**_RC, **_DRAFT_RC}):  # type: ignore[arg-type]
        for key in figure_plan(result, summary):
            row = []
            for first_only in (True, False):
                c0 = time.process_time()
                fig = draw_figure(key, result, summary, draft=first_only)
                _save(fig, Path(tmp), key, svg=False, draft=True)
                row.append(time.process_time() - c0)
            draft_totals = [a + b for a, b in zip(draft_totals, row, strict=True)]
            print(f"{key:<18} {row[0]:7.2f} {row[1]:7.2f}")
    print(f"{'total':<18} {draft_totals[0]:7.2f} {draft_totals[1]:7.2f}  "
          f"(ratio {draft_totals[0] / draft_totals[1]:.2f})")

    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        print("\n2. write_figures in this process, wall seconds")
        for svg in (False, True):
            t0 = time.perf_counter()
            figures = write_figures(result, summary, out / f"seq{svg}", svg=svg)
            print(f"   {'PNG + SVG' if svg else 'PNG only':<10} {time.perf_counter() - t0:6.2f}")

        print("\n3. FigureRenderer (workers started, then every figure), wall seconds")
        for workers in (0, 1, 2):
            for svg in (False, True):
                t0 = time.perf_counter()
                with FigureRenderer(out / f"w{workers}{svg}", workers=workers,
                                    svg=svg) as renderer:
                    renderer.submit(result, summary)
                    renderer.results(result)
                print(f"   workers={workers} {'PNG + SVG' if svg else 'PNG only':<10} "
                      f"{time.perf_counter() - t0:6.2f}")

        print("\n4. report.html, wall seconds")
        manifest = {"command": "bench", "config": config.to_dict()}
        t0 = time.perf_counter()
        page = write_html(out / "report.html", result=result, summary=summary, claims=claims,
                          manifest=manifest, figures=figures, elapsed_s=0.0)
        print(f"   {time.perf_counter() - t0:6.2f}  ({page.stat().st_size / 1e6:.2f} MB)")
    print(f"\nload average after: {_load()}")


if __name__ == "__main__":
    main()
