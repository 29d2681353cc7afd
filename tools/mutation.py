"""Mutation testing of one module against the tests chosen for it (mutmut 3).

Usage (from the repository root, with ``pip install -e '.[test,mutation]'``)::

    python tools/mutation.py MODULE [TEST ...] [--jobs 2] [--budget 900] [--table]
        [--show 20] [--keep DIR] [--no-jit]

MODULE is a dotted name (``it2track.atomicfile``) or a path (``src/it2track/atomicfile.py``);
TEST are pytest paths or node ids (default: the module's entry in :data:`DEFAULT_TESTS`). The
repository is copied to a scratch folder and mutmut mutates only MODULE there, running each
mutant against only the given tests -- and of those only the ones that call the mutated
function (mutmut's per-function test selection) -- in ``--jobs`` forked workers, for at most
``--budget`` seconds in all. Nothing in the repository is touched unless ``--table`` is given.

It prints the counts (killed, survived, timeouts, mutants no chosen test reaches), the score
and every surviving mutant as a diff; survivors recorded as equivalent in
``tools/mutation_equivalents.toml`` (module, function, the changed text -- ``change``, a
substring of the mutated lines, or ``line``, one whole mutated line -- and why no test can
tell them apart) are listed apart and left out of the score:

    score = killed / (killed + survived - equivalent)

where "killed" counts mutants a test failed on (or that hung past mutmut's timeout, or that
ended the test process abnormally: mutmut's "suspicious") and "survived" counts mutants every
chosen test passed with, including those no chosen test reaches. With ``--table`` a
complete run (not cut by the budget) writes the module's row into the score table of
``docs/guide/mutation.md`` and regenerates the page's list of equivalent mutants; the page's
numbers come only from here.

``--no-jit`` is for the compiled kernels (``fuzzy/_jit.py``, ``tracking/_jit.py``): mutmut
does not mutate decorated functions, so the copy's ``@njit``/``@_compiled(...)`` decorators are
removed and the tests run with ``NUMBA_DISABLE_JIT=1`` -- the kernels as the Python functions
numba compiles, checked by the tests that compare them with the numpy engine.
"""

from __future__ import annotations

import argparse
import ast
import contextlib
import datetime
import difflib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
import tomllib
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "guide" / "mutation.md"
EQUIVALENTS = ROOT / "tools" / "mutation_equivalents.toml"

#: test_sweep_store.py without its kill -9 / Ctrl-C tests (a 400-run sweep in a subprocess per
#: mutant; they test the atomic writes, :mod:`it2track.atomicfile`'s row, more than the store).
_SWEEP_STORE = [f"tests/experiments/test_sweep_store.py::test_{name}" for name in (
    "results_equal_direct_simulation", "store_is_standard_csv",
    "chunk_size_does_not_change_results", "resume_recomputes_only_missing_or_broken_chunks",
    "store_refuses_other_configs_and_second_writers", "cli_sweep_run_refuse_resume",
    "file_controller_is_identified_by_its_content", "file_edited_while_the_sweep_runs_is_refused",
    "store_of_another_it2track_version_is_refused",
    "cli_sweep_reports_a_failing_run_without_traceback")]

#: The tests of each module mutation-tested so far: what ``--table`` rows were measured with.
DEFAULT_TESTS: dict[str, list[str]] = {
    "it2track.atomicfile": ["tests/test_atomicfile.py"],
    "it2track.authorship": ["tests/test_authorship.py"],
    "it2track.cli.outdir": [
        "tests/cli/test_outdir.py", "tests/cli/test_reproduce_safety.py",
        "tests/cli/test_reproduce.py::test_publish_replaces_a_previous_run_without_leftovers",
        "tests/cli/test_reproduce.py::test_publish_never_removes_directories"],
    "it2track.experiments.sweep.store": [
        *_SWEEP_STORE, "tests/experiments/test_sweep_checksums.py",
        "tests/experiments/test_sweep_resume_refusals.py",
        "tests/experiments/test_sweep_chunk_checks.py"],
    "it2track.experiments.sweep.plan": [*_SWEEP_STORE, "tests/experiments/test_sweep_config.py",
                                        "tests/experiments/test_sweep_chunk_checks.py",
                                        "tests/experiments/test_sweep_plan_axes.py"],
    "it2track.experiments.sweep.config": ["tests/experiments/test_sweep_config_units.py",
                                          "tests/experiments/test_sweep_config.py",
                                          "tests/experiments/test_sweep_chunk_checks.py"],
    "it2track.experiments.sweep.chunks": ["tests/experiments/test_sweep_chunks_units.py",
                                          "tests/experiments/test_sweep_config.py",
                                          "tests/experiments/test_sweep_chunk_checks.py"],
    # (direct, fast tests: the runner's with the simulation replaced by a formula of the run)
    "it2track.experiments.sweep.runner": ["tests/experiments/test_sweep_runner_units.py"],
    "it2track.experiments.sweep.refs": ["tests/experiments/test_sweep_refs_units.py"],
    "it2track.experiments.analysis": ["tests/experiments/test_analysis.py"],
    "it2track.experiments.robustness": [
        "tests/experiments/test_robustness_judge.py",
        "tests/experiments/test_robustness.py::test_change_is_called_against_the_baselines_spread"],
    "it2track.experiments.robustness_config": [
        "tests/experiments/test_robustness_config.py",
        "tests/experiments/test_robustness.py::test_bad_choices_and_robustness_name_file_section_key_and_value",
        "tests/experiments/test_robustness.py::test_variants_one_at_a_time_then_factorial",
        "tests/experiments/test_robustness.py::test_the_default_factorial_crosses_half_track_period_and_output_gain",
        "tests/experiments/test_robustness.py::test_implied_choices_follow_the_studys_own_settings"],
    "it2track.experiments.stats": ["tests/experiments/test_stats.py",
                                   "tests/experiments/test_analysis.py"],
    "it2track.experiments.choices": [
        "tests/experiments/test_choices.py",
        "tests/experiments/test_robustness.py::test_variants_one_at_a_time_then_factorial",
        "tests/experiments/test_robustness.py::test_a_choice_value_is_validated_against_the_loop"],
    # (test_io_lock_previous.py: FCL's DEFAULT ... NC, 'x is any', .fis LockPrevious;
    # test_io_fcl_variables.py: parameters given by variables)
    "it2track.io.fcl": ["tests/io/test_io_fcl.py", "tests/io/test_io_fcl_dialects.py",
                        "tests/io/test_io_fcl_edges.py", "tests/io/test_io_lock_previous.py",
                        "tests/io/test_io_fcl_variables.py"],
    "it2track.io._fclparse": ["tests/io/test_io_fcl.py", "tests/io/test_io_fcl_dialects.py",
                              "tests/io/test_io_fcl_edges.py",
                              "tests/io/test_io_lock_previous.py",
                              "tests/io/test_io_fcl_variables.py"],
    "it2track.io._fclbuild": ["tests/io/test_io_fcl.py", "tests/io/test_io_fcl_dialects.py",
                              "tests/io/test_io_fcl_edges.py"],
    "it2track.io._fclsystem": ["tests/io/test_io_fcl.py", "tests/io/test_io_fcl_dialects.py",
                               "tests/io/test_io_fcl_edges.py",
                               "tests/io/test_io_lock_previous.py",
                               "tests/io/test_io_fcl_variables.py"],
    "it2track.io.matfis": ["tests/io/test_io_matfis.py", "tests/io/test_io_fis_dialects.py",
                           "tests/io/test_io_matfis_edges.py",
                           "tests/io/test_io_lock_previous.py"],
    "it2track.fuzzy.mamdani": ["tests/fuzzy/test_mamdani.py", "tests/fuzzy/test_mamdani_edges.py"],
    "it2track.codegen.errorbound": ["tests/codegen/test_errorbound.py",
                                    "tests/codegen/test_errorbound_terms.py"],
    "it2track.codegen._errorcore": ["tests/codegen/test_errorbound.py",
                                    "tests/codegen/test_errorbound_terms.py"],
    "it2track.codegen.generate": ["tests/codegen/test_generate.py",
                                  "tests/codegen/test_codegen_refuses.py",
                                  "tests/codegen/test_codegen_header.py"],
    # (--no-jit: the kernels as Python, so tiny batches; tests/engine/test_compiled_fuzzy.py
    # takes minutes a pass there)
    "it2track.fuzzy._jit": ["tests/engine/test_kernel_branches.py"],
    "it2track.tracking._jit": ["tests/engine/test_loop_kernel_branches.py",
                               "tests/engine/test_lanes.py"],
}

#: What is copied into the scratch folder (mutmut copies it again into ``mutants/``).
COPY = ("src", "tests", "configs", "examples", "docs", "pyproject.toml", "README.md")

#: mutmut 3.8's exit code -> status (``mutmut.stats.status_by_exit_code``; importing mutmut
#: here would make it read its configuration from the current folder).
STATUS = {1: "killed", 3: "killed", 0: "survived", 5: "no tests", 33: "no tests",
          2: "interrupted", None: "not checked", 34: "skipped", 35: "suspicious",
          36: "timeout", 37: "caught by type check", -24: "timeout", 24: "timeout",
          152: "timeout", 255: "timeout", -11: "segfault", -9: "segfault"}
#: "suspicious" is an exit status mutmut does not know, e.g. the test process killed by a
#: signal the mutant sent it: the tests did not pass, so the mutant did not survive.
KILLED = {"killed", "timeout", "segfault", "caught by type check", "suspicious"}
SURVIVED = {"survived", "no tests"}

#: ``module.x_func__mutmut_3`` or ``module.xǁClassǁmethod__mutmut_3`` (a method's name keeps
#: its leading underscores: ``xǁChoiceǁ__post_init____mutmut_1``).
_NAME = re.compile(r"^(?P<module>.+)\.x(?:ǁ(?P<cls>[^ǁ]+)ǁ|_)(?P<func>.+?)__mutmut_\d+$")


@dataclass
class Mutant:
    name: str
    status: str
    diff: str = ""
    equivalent: str = ""  # the reason, when recorded as equivalent

    @property
    def function(self) -> str:
        m = _NAME.match(self.name)
        if m is None:
            return self.name
        return f"{m['cls']}.{m['func']}" if m["cls"] else m["func"]


@dataclass
class Outcome:
    module: str
    tests: list[str]
    mutants: list[Mutant] = field(default_factory=list)
    seconds: float = 0.0
    complete: bool = True

    def count(self, statuses: set[str]) -> int:
        return sum(m.status in statuses for m in self.mutants)

    @property
    def killed(self) -> int:
        return self.count(KILLED)

    @property
    def survived(self) -> int:
        return self.count(SURVIVED)

    @property
    def equivalent(self) -> int:
        return sum(bool(m.equivalent) for m in self.mutants)

    @property
    def score(self) -> float:
        scored = self.killed + self.survived - self.equivalent
        return self.killed / scored if scored else float("nan")


def module_of(text: str) -> tuple[str, Path]:
    """``(dotted name, path relative to the root)`` of a module given either way."""
    if text.endswith(".py"):
        rel = Path(text).resolve().relative_to(ROOT)
        parts = rel.with_suffix("").parts
        if parts[0] != "src":
            raise SystemExit(f"{text}: not a module under src/")
        return ".".join(parts[1:]).removesuffix(".__init__"), rel
    rel = Path("src", *text.split(".")).with_suffix(".py")
    if not (ROOT / rel).is_file():
        package = Path("src", *text.split("."), "__init__.py")
        if (ROOT / package).is_file():
            return text, package
        raise SystemExit(f"{text}: no module {rel}")
    return text, rel


def _strip_decorators(path: Path) -> int:
    """Remove numba decorators (``@njit...``, ``@jit...``, ``@_compiled(...)``, one or more
    lines) from ``path``; returns how many."""
    lines = path.read_text(encoding="utf-8").splitlines(keepends=True)
    out, removed, depth = [], 0, 0
    for line in lines:
        stripped = line.lstrip()
        if depth == 0 and re.match(r"@(njit|jit|_compiled|numba\.\w+)\b", stripped):
            removed += 1
            depth = stripped.count("(") - stripped.count(")")
            continue
        if depth > 0:
            depth += line.count("(") - line.count(")")
            continue
        out.append(line)
    path.write_text("".join(out), encoding="utf-8")
    return removed


def prepare(work: Path, module_path: Path, tests: list[str], *, no_jit: bool) -> None:
    """Copy the repository into ``work`` and configure mutmut there."""
    work.mkdir(parents=True, exist_ok=True)
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "_build", "generated",
                                    "auto_examples", ".mutation")
    for name in COPY:
        src = ROOT / name
        if src.is_dir():
            shutil.copytree(src, work / name, ignore=ignore, symlinks=True)
        elif src.is_file():
            shutil.copy2(src, work / name)
    if no_jit:
        n = _strip_decorators(work / module_path)
        print(f"--no-jit: removed {n} numba decorator(s) from the copy of {module_path}")
    config = {
        "source_paths": ["src/"],
        "only_mutate": [str(module_path)],
        "pytest_add_cli_args_test_selection": tests,
        # (--no-jit: numba's error_model="numpy" divides by zero silently; the interpreter's
        # numpy scalars warn, which the suite's filterwarnings = error would make a failure)
        "pytest_add_cli_args": ["-p", "no:cacheprovider", "-q", "-x"]
        + (["-W", "ignore::RuntimeWarning"] if no_jit else []),
        "use_git_change_detection": False,
        # mutmut copies only src/ and tests/ into mutants/; some tests read these too
        "also_copy": [name for name in COPY if name not in ("src", "tests", "pyproject.toml")],
        "track_dependencies": False,
    }
    lines = ["", "[tool.mutmut]"]
    for key, value in config.items():
        lines.append(f"{key} = {json.dumps(value)}")
    with open(work / "pyproject.toml", "a", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")


def run_mutmut(work: Path, *, jobs: int, budget: float, no_jit: bool) -> tuple[bool, float]:
    """Run ``mutmut run`` in ``work`` for at most ``budget`` s; (finished, seconds)."""
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONDONTWRITEBYTECODE": "1"}
    if no_jit:
        env["NUMBA_DISABLE_JIT"] = "1"
    mutmut = shutil.which("mutmut", path=str(Path(sys.executable).parent)) or "mutmut"
    log = open(work / "mutmut.log", "wb")
    started = time.monotonic()
    proc = subprocess.Popen([mutmut, "run", "--max-children", str(jobs)], cwd=work, env=env,
                            stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    finished = True
    try:
        proc.wait(timeout=budget)
    except subprocess.TimeoutExpired:
        finished = False
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    except KeyboardInterrupt:
        os.killpg(proc.pid, signal.SIGTERM)
        proc.wait()
        raise
    finally:
        log.close()
    if finished and proc.returncode != 0:
        tail = (work / "mutmut.log").read_bytes()[-3000:].decode("utf-8", "replace")
        raise SystemExit(f"mutmut failed (exit {proc.returncode}):\n{tail}")
    return finished, time.monotonic() - started


def _functions(source: str) -> dict[str, str]:
    """Name -> source text of every function in ``source`` (methods included)."""
    # (whole lines sliced once: ast.get_source_segment rescans the file for every function,
    # which takes minutes on a module with a thousand mutants)
    tree = ast.parse(source)
    lines = source.splitlines(keepends=True)
    out = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.end_lineno:
            text = "".join(lines[node.lineno - 1:node.end_lineno])
            out[node.name] = textwrap.dedent(text).rstrip("\n")
    return out


def _diff(functions: dict[str, str], name: str, module_path: Path) -> str:
    """The unified diff of mutant ``name`` against the original function (what ``mutmut
    show`` prints, without a process per mutant)."""
    short = name.rsplit(".", 1)[1]  # x_func__mutmut_3 or xǁClassǁmethod__mutmut_3
    stem = short.rsplit("__mutmut_", 1)[0]
    orig, mutant = functions.get(f"{stem}__mutmut_orig"), functions.get(short)
    if orig is None or mutant is None:
        return f"# {name} (source not found)"
    real = stem.rsplit("ǁ", 1)[-1].removeprefix("x_")
    # (a newline at the end, so that a change on a function's last line is a line of its own)
    before = (orig.replace(f"{stem}__mutmut_orig", real, 1) + "\n").splitlines(keepends=True)
    after = (mutant.replace(short, real, 1) + "\n").splitlines(keepends=True)
    lines = difflib.unified_diff(before, after, f"{module_path}", f"{module_path}", n=3)
    return f"# {name}\n" + "".join(lines).rstrip()


def collect(work: Path, module: str, module_path: Path, tests: list[str],
            equivalents: list[dict[str, str]]) -> Outcome:
    mutated = work / "mutants" / module_path
    meta = mutated.with_name(mutated.name + ".meta")
    data = json.loads(meta.read_text(encoding="utf-8")) if meta.is_file() else {}
    codes = data.get("exit_code_by_key", {})
    functions = _functions(mutated.read_text(encoding="utf-8")) if mutated.is_file() else {}
    outcome = Outcome(module, tests)
    for name, code in codes.items():
        status = STATUS.get(code, "suspicious")
        mutant = Mutant(name, status)
        if status in SURVIVED:
            mutant.diff = _diff(functions, name, module_path)
            mutant.equivalent = _equivalent(module, mutant, equivalents)
        outcome.mutants.append(mutant)
    return outcome


def _changed_lines(diff: str) -> str:
    return "\n".join(line[1:] for line in diff.splitlines()
                     if line.startswith("+") and not line.startswith("+++"))


def _equivalent(module: str, mutant: Mutant, equivalents: list[dict[str, str]]) -> str:
    added = _changed_lines(mutant.diff)
    lines = {line.strip() for line in added.splitlines()}
    for entry in equivalents:
        if entry["module"] != module or entry["function"] != mutant.function:
            continue
        if ("line" in entry and entry["line"] in lines) or (
                "change" in entry and entry["change"] in added):
            return entry["reason"]
    return ""


def load_equivalents() -> list[dict[str, str]]:
    if not EQUIVALENTS.is_file():
        return []
    entries = tomllib.loads(EQUIVALENTS.read_text(encoding="utf-8")).get("equivalent", [])
    for e in entries:
        missing = {"module", "function", "reason"} - set(e)
        if missing or ("change" in e) == ("line" in e):
            raise SystemExit(f"{EQUIVALENTS}: an entry needs module, function, reason and "
                             f"either change (a substring) or line (a whole line): {e}")
    return entries


def report(outcome: Outcome, *, show: int) -> None:
    counts = Counter(m.status for m in outcome.mutants)
    print(f"\n{outcome.module}: {len(outcome.mutants)} mutants in {outcome.seconds:.0f} s "
          f"against {' '.join(outcome.tests)}")
    print("  " + ", ".join(f"{status} {n}" for status, n in counts.most_common()))
    if not outcome.complete:
        print("  BUDGET EXHAUSTED: the counts are partial (rerun with a larger --budget)")
    print(f"  score {outcome.killed}/{outcome.killed + outcome.survived - outcome.equivalent}"
          f" = {outcome.score:.1%} (killed / (killed + survived - {outcome.equivalent} "
          "equivalent))")
    survivors = [m for m in outcome.mutants if m.status in SURVIVED and not m.equivalent]
    equivalent = [m for m in outcome.mutants if m.equivalent]
    if equivalent:
        print(f"\nequivalent ({len(equivalent)}, tools/mutation_equivalents.toml):")
        for m in equivalent:
            print(f"  {m.name}: {m.equivalent}")
    if survivors:
        print(f"\nsurviving mutants ({len(survivors)}; showing {min(show, len(survivors))}):")
        for m in survivors[:show]:
            print(f"\n[{m.status}] {m.diff or m.name}")


# -- the docs page ---------------------------------------------------------------------------

_TABLE = ("<!-- BEGIN mutation-scores (tools/mutation.py --table) -->",
          "<!-- END mutation-scores -->")
_EQUIV = ("<!-- BEGIN equivalent-mutants (tools/mutation.py --table) -->",
          "<!-- END equivalent-mutants -->")
_HEADER = ("| module | tests | mutants | killed | survived | equivalent | score (first → now) "
           "| measured |\n|---|---|---:|---:|---:|---:|---:|---|")


def _between(text: str, markers: tuple[str, str]) -> tuple[str, str, str]:
    start, end = markers
    i, j = text.index(start) + len(start), text.index(end)
    return text[:i], text[i:j], text[j:]


def write_table(outcome: Outcome, equivalents: list[dict[str, str]]) -> None:
    text = PAGE.read_text(encoding="utf-8")
    before, body, after = _between(text, _TABLE)
    rows = {line.split("|")[1].strip().strip("`"): line for line in body.splitlines()
            if line.startswith("| `")}
    tests = ", ".join(f"`{t}`" for t in outcome.tests)
    day = datetime.date.today().isoformat()
    score = f"{outcome.score:.0%}"
    if outcome.module in rows:  # keep the score first recorded: "first → now"
        first = rows[outcome.module].split("|")[7].strip().split("→")[0].strip()
        score = f"{first} → {score}"
    rows[outcome.module] = (
        f"| `{outcome.module}` | {tests} | {len(outcome.mutants)} | {outcome.killed} | "
        f"{outcome.survived - outcome.equivalent} | {outcome.equivalent} | "
        f"{score} | {day}, mutmut {_mutmut_version()} |")
    body = "\n" + _HEADER + "\n" + "\n".join(rows[k] for k in sorted(rows)) + "\n"
    text = before + body + after
    before, _, after = _between(text, _EQUIV)
    shown = sorted({r for r in rows})
    lines = [f"- `{e['module']}`, `{e['function']}`: `{e.get('change') or e['line']}` -- "
             f"{e['reason']}" for e in equivalents if e["module"] in shown]
    text = before + "\n" + ("\n".join(lines) or "(none)") + "\n" + after
    PAGE.write_text(text, encoding="utf-8")
    print(f"\nwrote the row of {outcome.module} into {PAGE.relative_to(ROOT)}")


def _mutmut_version() -> str:
    from importlib.metadata import version

    return version("mutmut")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("module", help="dotted name or path of the module to mutate")
    parser.add_argument("tests", nargs="*", help="pytest paths or node ids (default: "
                        "the module's DEFAULT_TESTS)")
    parser.add_argument("--jobs", type=int, default=2, help="mutants tested at once")
    parser.add_argument("--budget", type=float, default=900.0,
                        help="seconds for the whole run (default 900)")
    parser.add_argument("--table", action="store_true",
                        help="write the score into docs/guide/mutation.md")
    parser.add_argument("--show", type=int, default=50, help="survivors printed")
    parser.add_argument("--keep", type=Path, default=None,
                        help="scratch folder to use and keep (default: a temporary one)")
    parser.add_argument("--no-jit", action="store_true",
                        help="remove numba decorators and run with NUMBA_DISABLE_JIT=1")
    parser.add_argument("--collect", type=Path, default=None, metavar="DIR",
                        help="only read the results of a finished run kept in DIR (--keep), "
                        "e.g. one whose report was interrupted")
    args = parser.parse_args(argv)
    if args.jobs < 1 or not args.budget > 0:
        parser.error("--jobs must be >= 1 and --budget > 0")
    module, module_path = module_of(args.module)
    tests = args.tests or DEFAULT_TESTS.get(module)
    if not tests:
        parser.error(f"no tests given and none known for {module}: name the test files")
    for t in tests:
        if not (ROOT / t.split("::")[0]).exists():
            parser.error(f"{t}: no such test file")
    equivalents = load_equivalents()
    if args.collect is not None:
        if not (args.collect / "mutants" / module_path).is_file():
            parser.error(f"--collect {args.collect}: no mutated {module_path} there")
        outcome = collect(args.collect, module, module_path, tests, equivalents)
        outcome.complete = bool(outcome.mutants) and not any(
            m.status == "not checked" for m in outcome.mutants)
        report(outcome, show=args.show)
        if args.table and outcome.complete:
            write_table(outcome, equivalents)
        return 0
    work = args.keep or Path(tempfile.mkdtemp(prefix="it2track-mutation-"))
    if args.keep and (work / "mutants").exists():
        parser.error(f"--keep {work}: holds a previous run; remove it first")
    try:
        prepare(work, module_path, tests, no_jit=args.no_jit)
        print(f"mutating {module_path} against {' '.join(tests)} in {work} "
              f"({args.jobs} at once, budget {args.budget:.0f} s; log: {work / 'mutmut.log'})")
        finished, seconds = run_mutmut(work, jobs=args.jobs, budget=args.budget,
                                       no_jit=args.no_jit)
        outcome = collect(work, module, module_path, tests, equivalents)
        outcome.seconds, outcome.complete = seconds, finished and not any(
            m.status == "not checked" for m in outcome.mutants)
        report(outcome, show=args.show)
        if args.table:
            if not outcome.complete:
                print("\nnot written to the table: the run was cut by the budget")
                return 1
            write_table(outcome, equivalents)
    finally:
        if args.keep is None:
            with contextlib.suppress(OSError):
                shutil.rmtree(work)
    return 0


if __name__ == "__main__":
    sys.exit(main())
