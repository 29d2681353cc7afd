"""Fuzzing: random byte mutations of valid files raise nothing but FisFormatError (and warn
nothing but FisFormatWarning).

A seeded loop (reproducible; a failure message carries the seed and the mutated bytes). Loaded
systems must also evaluate, where the only allowed error is ValueError (e.g. ZeroFiringError
where a mutated rule base leaves a hole).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from io_systems import random_system

from it2track import heading_fls
from it2track.fuzzy import HybridSystem, IT2Mamdani, IT2Sugeno, T1Mamdani, T1Sugeno, T1Tsukamoto
from it2track.io import FORMATS, TYPE2, FisFormatError, FisFormatWarning, dumps, load

DATA = Path(__file__).parent / "data"
CONFORMANCE = Path(__file__).parents[1] / "conformance" / "files"
#: files as the tools write them (tests/conformance/files/SOURCES.md): MATLAB's duplicated key
#: and comments, Octave's, fuzzylite's exports of a hybrid engine, jFuzzyLogic's FCL
REAL_FILES = ["fuzzylite/examples/original/takagi-sugeno/matlab/slcp1.fis",
              "octave/inst/heart_disease_risk.fis",
              "fuzzylite/examples/hybrid/tipper.fll", "fuzzylite/examples/hybrid/tipper.fis",
              "fuzzylite/examples/hybrid/tipper.fcl", "jfuzzylogic/tests/junit_tipper.fcl"]
MUTATIONS_PER_FILE = 250
TOKENS = [b"Inf", b"NaN", b"-", b"1e999", b"1e-999", b"'", b'"', b"[", b"]", b"\n", b"=",
          b",", b":", b"0", b"-1", b"9" * 12, b"%", b"[Rules]", b"[Input9]", b"\x00", b"\xff",
          b"\xc3\xa9", b" ", b"{", b"}", b"inf", b"nan", b"0.5", b"trimf", b"gauss2mf",
          b"\r", b"(", b")", b"#", b"1_0", b"+"]


def valid_files() -> list[tuple[str, bytes]]:
    files = [(p.name, p.read_bytes()) for p in sorted(DATA.glob("*.*"))]
    files += [(path.replace("/", "."), (CONFORMANCE / path).read_bytes()) for path in REAL_FILES]
    for fmt, (suffix, _, _) in FORMATS.items():
        type1 = fmt not in TYPE2
        files.append((f"paper{suffix}", dumps(heading_fls(0.0 if type1 else 0.2), fmt).encode()))
        system = random_system(5, type1=type1, identifiers=type1)
        files.append((f"random{suffix}", dumps(system, fmt).encode()))
    return files


def mutate(data: bytes, rng: np.random.Generator) -> bytes:
    out = bytearray(data)
    for _ in range(int(rng.integers(1, 4))):
        if not out:
            out += bytes(rng.integers(0, 256, 3, dtype=np.uint8))
        pos = int(rng.integers(len(out)))
        op = int(rng.integers(8))
        if op == 0:  # flip one byte
            out[pos] = int(rng.integers(256))
        elif op == 1:  # insert a random byte
            out.insert(pos, int(rng.integers(256)))
        elif op == 2:  # delete a run of bytes
            del out[pos:pos + int(rng.integers(1, 8))]
        elif op == 3:  # insert a troublesome token
            token = TOKENS[int(rng.integers(len(TOKENS)))]
            out[pos:pos] = token
        elif op == 4:  # replace a digit by another
            digits = [i for i, b in enumerate(out) if 48 <= b <= 57]
            if digits:
                out[digits[int(rng.integers(len(digits)))]] = int(rng.integers(48, 58))
        elif op == 5:  # duplicate or drop a line
            lines = bytes(out).split(b"\n")
            k = int(rng.integers(len(lines)))
            if rng.random() < 0.5:
                lines.insert(k, lines[k])
            else:
                del lines[k]
            out = bytearray(b"\n".join(lines))
        elif op == 6:  # truncate
            del out[pos:]
        else:  # swap two lines
            lines = bytes(out).split(b"\n")
            i, j = (int(v) for v in rng.integers(len(lines), size=2))
            lines[i], lines[j] = lines[j], lines[i]
            out = bytearray(b"\n".join(lines))
    return bytes(out)


def lines(data: bytes, suffix: str) -> int:
    """The file's line count as its reader numbers lines (XML also breaks lines at a lone CR)."""
    breaks = data.count(b"\n")
    if suffix == ".fml":
        breaks += data.count(b"\r") - data.count(b"\r\n")
    return breaks + 1


@pytest.mark.parametrize(("name", "data"), valid_files(), ids=[n for n, _ in valid_files()])
def test_mutations_raise_only_fis_format_error(name: str, data: bytes, tmp_path) -> None:
    rng = np.random.default_rng(sum(data) + len(name))
    suffix = Path(name).suffix
    target = tmp_path / f"mutant{suffix}"
    loaded = 0
    for k in range(MUTATIONS_PER_FILE):
        mutant = mutate(data, rng)
        target.write_bytes(mutant)
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                system = load(target)
            for warning in caught:  # only the documented warning, naming this file
                assert isinstance(warning.message, FisFormatWarning), warning
                assert warning.message.path == str(target)
                line = warning.message.line
                assert line is None or 1 <= line <= lines(mutant, suffix), warning
        except FisFormatError as err:
            assert err.path == str(target)
            assert err.line is None or 1 <= err.line <= lines(mutant, suffix), err
            continue
        except Exception as exc:  # pragma: no cover - the failure we look for
            pytest.fail(f"{name} mutation {k}: {type(exc).__name__}: {exc}\n{mutant!r}")
        loaded += 1
        assert isinstance(system, IT2Sugeno | T1Sugeno | IT2Mamdani | T1Mamdani | T1Tsukamoto
                          | HybridSystem)
        points = [np.linspace(*inp.universe, 7) for inp in system.inputs]
        try:
            system(*points)
        except ValueError:
            pass
    assert loaded < MUTATIONS_PER_FILE  # the mutations do bite
