"""Bad configuration files (sweep, optimiser, study), parsed in-process: every case is a
``ConfigError`` naming the file, the key and the value, raised while the file is read --
before anything is simulated or written."""

from __future__ import annotations

import textwrap
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hostile_helpers import BINARY, make_device_link, make_fifo, make_sparse

import it2track
from it2track.experiments.optimize import load_optimize_config
from it2track.experiments.specs import ConfigError
from it2track.experiments.study import load_study_config
from it2track.experiments.sweep import load_sweep_config

SWEEP = """
[sweep]
seeds = 2
noise_std = [0.0, 0.1]
trajectories = ["straight"]

[simulation]
duration = 1.0

[[controllers]]
kind = "flc"
"""

OPTIMIZE = """
[optimize]
objective = "ISE"
train_seeds = 2
holdout_seeds = { start = 100, count = 2 }
noise_std = 0.05
trajectories = ["straight"]

[simulation]
duration = 1.0
"""

STUDY = """
[study]
seeds = 2
"""

LOADERS: dict[str, tuple[Callable[[Path], Any], str]] = {
    "sweep": (load_sweep_config, SWEEP),
    "optimize": (load_optimize_config, OPTIMIZE),
    "study": (load_study_config, STUDY),
}

#: (id, loader, edit, needles): ``edit`` is the base text with (old, new) replaced or appended,
#: or a special file kind; needles must all appear in the message (the file name always).
CASES: list[tuple[str, str, Any, tuple[str, ...]]] = []


def case(name: str, loader: str, edit: Any, *needles: str) -> None:
    CASES.append((name, loader, edit, needles))


for _loader in ("sweep", "optimize", "study"):
    case(f"{_loader}-binary", _loader, "binary", "binary data")
    case(f"{_loader}-latin1", _loader, "latin1", "not valid UTF-8", "0xe9")
    case(f"{_loader}-fifo", _loader, "fifo", "FIFO")
    case(f"{_loader}-dev-zero", _loader, "zero", "character device")
    case(f"{_loader}-huge", _loader, "huge", "larger than")
    case(f"{_loader}-syntax", _loader, ("", "this is = = not toml"), "invalid TOML")
    case(f"{_loader}-unknown-section", _loader, ("", "[surprise]\nx = 1"), "surprise")
    case(f"{_loader}-duration-1e9", _loader, ("", "[simulation]\nduration = 1e9")
         if _loader == "study" else ("duration = 1.0", "duration = 1e9"),
         "duration=1000000000.0", "0 < x <= 3600 s")
    # one cap for every command: simulate --duration 3601 is refused, so is a config's
    case(f"{_loader}-duration-3601", _loader, ("", "[simulation]\nduration = 3601\nts = 1.0")
         if _loader == "study" else ("duration = 1.0", "duration = 3601\nts = 1.0"),
         "duration=3601", "0 < x <= 3600 s")
    case(f"{_loader}-ts-1e-9", _loader, ("", "[simulation]\nts = 1e-9")
         if _loader == "study" else ("duration = 1.0", "duration = 1.0\nts = 1e-9"),
         "ts=1e-09", "memory")
    case(f"{_loader}-quadrature-1e6", _loader,
         ("", "[simulation]\nquadrature_nodes = 1000000") if _loader == "study" else
         ("duration = 1.0", "duration = 1.0\nquadrature_nodes = 1000000"),
         "quadrature_nodes=1000000", "[1, 64]")
    case(f"{_loader}-motor-negative", _loader, ("", "[robot.motor]\nresistance = -5.0"),
         "resistance", "-5.0")
    case(f"{_loader}-inductance-1e-300", _loader, ("", "[robot.motor]\ninductance = 1e-300"),
         "inductance=1e-300", "shorten ts")
    case(f"{_loader}-robot-string", _loader, ("", "[robot]\nhalf_track = \"wide\""),
         "half_track", "'wide'")
    case(f"{_loader}-start-pose", _loader, ("", "[simulation]\nstart_pose = [0, 0]")
         if _loader == "study" else ("duration = 1.0", "duration = 1.0\nstart_pose = [0, 0]"),
         "start_pose", "[0.0, 0.0]")
    case(f"{_loader}-seed-negative", _loader,
         {"sweep": ("seeds = 2", "seeds = 2\nseed = -1"),
          "optimize": ('objective = "ISE"', 'objective = "ISE"\nseed = -1'),
          "study": ("seeds = 2", "seeds = 2\nseed = -1")}[_loader], "seed=-1")

# sweep-specific
case("sweep-noise-1e308", "sweep", ("noise_std = [0.0, 0.1]", "noise_std = [0.0, 1e308]"),
     "noise_std", "1e+308", "1e+06 rad")
case("sweep-noise-negative", "sweep", ("noise_std = [0.0, 0.1]", "noise_std = -0.1"),
     "noise_std", "-0.1")
case("sweep-noise-string", "sweep", ("noise_std = [0.0, 0.1]", 'noise_std = "low"'),
     "noise_std", "'low'")
case("sweep-seed-22-digits", "sweep", ("seeds = 2", "seeds = [1, 1234567890123456789012]"),
     "seeds", "1234567890123456789012", "2**63 - 1")
case("sweep-seed-count-1e15", "sweep", ("seeds = 2", "seeds = { count = 1000000000000000 }"),
     "seeds", "1000000000000000", "memory")
case("sweep-seed-start-overflow", "sweep",
     ("seeds = 2", "seeds = { start = 9223372036854775807, count = 2 }"), "seeds",
     "2**63 - 1")
case("sweep-seeds-zero", "sweep", ("seeds = 2", "seeds = 0"), "seeds=0", ">= 1")
case("sweep-seeds-repeat", "sweep", ("seeds = 2", "seeds = [3, 3]"), "must not repeat")
case("sweep-chunk-zero", "sweep", ("seeds = 2", "seeds = 2\nchunk_size = 0"), "chunk_size=0")
case("sweep-chunk-float", "sweep", ("seeds = 2", "seeds = 2\nchunk_size = 1.5"),
     "chunk_size=1.5", "integer")
case("sweep-chunk-huge", "sweep",
     ("seeds = 2", "seeds = { count = 4000000 }\nchunk_size = 4000000"), "chunk_size=4000000",
     "memory")
case("sweep-trajectory-unknown", "sweep", ('["straight"]', '["spiral"]'), "'spiral'")
case("sweep-trajectory-twice", "sweep", ('["straight"]', '["straight", "straight"]'),
     "must not repeat")
case("sweep-trajectory-fifo", "sweep", ('["straight"]', '["fifo.csv"]'), "fifo.csv", "FIFO")
case("sweep-trajectory-binary", "sweep", ('["straight"]', '["binary.csv"]'), "binary.csv",
     "binary")
case("sweep-trajectory-same-file-twice", "sweep", ('["straight"]', '["a/p.csv", "a/../a/p.csv"]'),
     "listed twice")
case("sweep-empty-axis", "sweep", ("", "[robot]\nhalf_track = []"), "half_track", "empty axis")
case("sweep-no-controllers", "sweep", ('[[controllers]]\nkind = "flc"', ""), "controllers")
case("sweep-kind-unknown", "sweep", ('kind = "flc"', 'kind = "mamdani2"'), "kind='mamdani2'")
case("sweep-pd-with-fou", "sweep", ('kind = "flc"', 'kind = "pd"\nkp = 5.0\nfou = 0.2'),
     "fou=0.2", "does not apply to kind 'pd'")
case("sweep-pd-no-gains", "sweep", ('kind = "flc"', 'kind = "pd"'), "kind 'pd' needs", "kp")
case("sweep-pd-negative-kp", "sweep", ('kind = "flc"', 'kind = "pd"\nkp = -3.0'), "kp=-3.0")
case("sweep-pd-negative-kd", "sweep", ('kind = "flc"', 'kind = "pd"\nkp = 3.0\nkd = -1.0'),
     "kd=-1.0")
case("sweep-file-with-fou", "sweep",
     ('kind = "flc"', 'kind = "file"\npath = "good.t2fis"\nfou = 0.2'), "fou=0.2",
     "kind 'file'")
case("sweep-file-with-reducer", "sweep",
     ('kind = "flc"', 'kind = "file"\npath = "good.t2fis"\nreducer = "km"'), "reducer='km'",
     "kind 'file'")
case("sweep-file-missing", "sweep", ('kind = "flc"', 'kind = "file"\npath = "nope.t2fis"'),
     "nope.t2fis", "No such file")
case("sweep-file-fifo", "sweep", ('kind = "flc"', 'kind = "file"\npath = "fifo.t2fis"'),
     "fifo.t2fis", "FIFO")
case("sweep-file-binary", "sweep", ('kind = "flc"', 'kind = "file"\npath = "binary.toml"'),
     "binary.toml", "binary")
case("sweep-file-no-path", "sweep", ('kind = "flc"', 'kind = "file"'), "needs a path")
case("sweep-flc-with-kp", "sweep", ('kind = "flc"', 'kind = "flc"\nkp = 3.0'), "kp=3.0",
     "kind 'flc'")
case("sweep-it2-zero-fou", "sweep", ('kind = "flc"', 'kind = "it2"\nfou = [0.0, 0.2]'),
     "fou > 0")
case("sweep-ke-zero", "sweep", ('kind = "flc"', 'kind = "flc"\nke = 0.0'), "ke=0.0")
case("sweep-label-for-axis", "sweep", ('kind = "flc"', 'kind = "it2"\nfou = [0.1, 0.2]\n'
                                       'label = "x"'), "label='x'", "2 controllers")
case("sweep-unknown-key", "sweep", ('kind = "flc"', 'kind = "flc"\ncolour = "red"'),
     "colour")
case("sweep-missing-seeds", "sweep", ("seeds = 2", ""), "seeds")
# optimize-specific
case("optimize-objective-unknown", "optimize", ('objective = "ISE"', 'objective = "ISEE"'),
     "ISEE")
case("optimize-weight-negative", "optimize", ('objective = "ISE"', "objective = { ISE = -1 }"),
     "ISE", "-1")
case("optimize-bounds-reversed", "optimize",
     ('objective = "ISE"', 'objective = "ISE"\nbounds = [1.0, 0.5]'), "bounds", "(1.0, 0.5)")
case("optimize-holdout-overlap", "optimize",
     ("{ start = 100, count = 2 }", "{ start = 0, count = 2 }"), "disjoint")
case("optimize-train-count-huge", "optimize", ("train_seeds = 2", "train_seeds = 1000000000"),
     "train_seeds", "1000000000 seed indices", "memory")
case("optimize-popsize-huge", "optimize",
     ("", "[optimize.asymmetric]\npopsize = 100000000"), "600000000 candidates", "memory")
case("optimize-tnorm", "optimize", ("", '[controller]\ntnorm = "max"'), "max")
case("optimize-ke-negative", "optimize", ("", "[controller]\nke = -1.0"), "ke=-1.0")
case("optimize-noise-1e308", "optimize", ("noise_std = 0.05", "noise_std = 1e308"),
     "noise_std", "1e+308")
case("optimize-seed-22-digits", "optimize",
     ("train_seeds = 2", "train_seeds = [12345678901234567890123]"), "train_seeds",
     "12345678901234567890123")
# study-specific
case("study-seeds-negative", "study", ("seeds = 2", "seeds = -1"), "seeds=-1")
case("study-pd-no-gains", "study", ("", '[[controllers]]\nkind = "pd"'), "kind 'pd' needs")
case("study-pd-with-fou", "study", ("", '[[controllers]]\nkind = "pd"\nkp = 2.0\nfou = 0.2'),
     "fou=0.2", "kind 'pd'")
case("study-file-with-fou", "study",
     ("", '[[controllers]]\nkind = "file"\npath = "good.t2fis"\nfou = 0.2'), "fou=0.2",
     "kind 'file'")
case("study-file-fifo", "study", ("", '[[controllers]]\nkind = "file"\npath = "fifo.t2fis"'),
     "fifo.t2fis", "FIFO")
case("study-trajectory-fifo", "study", ("seeds = 2", 'seeds = 2\ntrajectories = ["fifo.csv"]'),
     "fifo.csv", "FIFO")
case("study-fou-negative", "study", ("seeds = 2", "seeds = 2\nfous = [-0.1]"), "fous")
case("study-pd-grid-negative", "study", ("", "[pd]\nkp_grid = [-1.0]"), "kp_grid")


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("hostile-configs")
    make_fifo(d / "fifo.csv")
    make_fifo(d / "fifo.t2fis")
    (d / "binary.csv").write_bytes(BINARY)
    (d / "binary.toml").write_bytes(BINARY)
    (d / "a").mkdir()
    (d / "a" / "p.csv").write_text("t,x,y\n0,0,0\n1,1,0\n2,2,0\n3,3,0\n")
    it2track.save(it2track.heading_fls(0.2), d / "good.t2fis")
    return d


def _write(folder: Path, name: str, base: str, edit: Any) -> Path:
    path = folder / f"{name}.toml"
    if edit == "binary":
        path.write_bytes(BINARY)
    elif edit == "latin1":
        path.write_bytes(b"# caf\xe9\n" + base.encode())
    elif edit == "fifo":
        make_fifo(path)
    elif edit == "zero":
        make_device_link(path)
    elif edit == "huge":
        make_sparse(path, (64 << 20) + 1)
    else:
        old, new = edit
        text = textwrap.dedent(base)
        if old:
            assert old in text, old
            text = text.replace(old, new, 1)
        else:
            text += "\n" + new + "\n"
        path.write_text(text)
    return path


@pytest.mark.parametrize(("loader", "edit", "needles"), [c[1:] for c in CASES],
                         ids=[c[0] for c in CASES])
def test_bad_config_is_a_clear_error(folder: Path, loader: str, edit: Any,
                                     needles: tuple[str, ...]) -> None:
    load, base = LOADERS[loader]
    name = f"case{len(list(folder.glob('case*.toml')))}"
    path = _write(folder, name, base, edit)
    before = sorted(p.name for p in folder.rglob("*"))
    with pytest.raises(ConfigError) as info:
        load(path)
    message = str(info.value)
    assert str(path) in message, message
    for needle in needles:
        assert needle in message, f"{needle!r} not in {message!r}"
    assert "Traceback" not in message
    assert sorted(p.name for p in folder.rglob("*")) == before, "a file was written"


def test_the_base_configs_are_valid(folder: Path) -> None:
    """The cases are edits of configs that load: each case fails for its edit only."""
    for name, (load, base) in LOADERS.items():
        load(_write(folder, f"valid-{name}", base, ("", "")))


def test_csvs_with_the_same_file_name_get_distinct_identities(folder: Path) -> None:
    (folder / "b").mkdir(exist_ok=True)
    (folder / "b" / "p.csv").write_text("t,x,y\n0,0,0\n1,0,1\n2,0,2\n3,0,3\n")
    path = _write(folder, "two-p", SWEEP, ('["straight"]', '["a/p.csv", "b/p.csv"]'))
    plan = load_sweep_config(path)
    names = [r.name for r in plan.trajectory_refs]
    assert names == ["a-p", "b-p"]
    assert [t.name for t in plan.trajectories] == names
    first, second = (t(np.array([1.0])) for t in plan.trajectories)
    assert first[0, 1] == 0.0 and first[0, 0] == 1.0  # a/p.csv runs along x
    assert second[0, 0] == 0.0 and second[0, 1] == 1.0  # b/p.csv along y
