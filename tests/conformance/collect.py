"""Copy the conformance suite's public example files, unmodified, from bare git mirrors of their
repositories, and write ``files/SOURCES.md`` (repository, commit and path of every file).

Usage (each mirror is a bare clone, e.g. ``git clone --bare https://github.com/OWNER/NAME``)::

    python tests/conformance/collect.py fuzzylite/fuzzylite=PATH.git \\
        fuzzylite/pyfuzzylite=PATH.git lmarkowsky/fuzzy-logic-toolkit=PATH.git \\
        pcingola/jFuzzyLogic=PATH.git

Files whose bytes repeat an earlier file of the same source are not copied; SOURCES.md lists
them as duplicates. The files are test data: the wheel does not include ``tests/``.
"""

from __future__ import annotations

import hashlib
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).parent
FILES = HERE / "files"


@dataclass(frozen=True)
class Source:
    """One repository: where its files go, which paths, which licence files."""

    folder: str
    repo: str
    pattern: str
    licences: tuple[str, ...]
    note: str


SOURCES = (
    Source("fuzzylite", "fuzzylite/fuzzylite",
           r"^examples/.*\.(fis|fll|fcl)$|^examples/.*/COPYING$",
           ("LICENSE", "LICENSE.FuzzyLite"),
           "fuzzylite 6 (C++): its examples exported as .fll, .fis and .fcl, and under "
           "examples/original/ the MATLAB and Octave originals it ships with its own .fll of "
           "them. fuzzylite's examples/README.md: mam21.fis and mam22.fis were modified by "
           "fuzzylite (the fourth gbellmf parameter removed); the other MATLAB files are "
           "MathWorks' Fuzzy Logic Toolbox examples as fuzzylite redistributes them."),
    Source("pyfuzzylite", "fuzzylite/pyfuzzylite", r"^fuzzylite/examples/.*\.fll$",
           ("LICENSE.GPL.txt", "LICENSE.FuzzyLite.txt"),
           "pyfuzzylite 8 (Python): the examples in fuzzylite 8's .fll, including the "
           "terms/ examples of every term."),
    Source("octave", "lmarkowsky/fuzzy-logic-toolkit", r"^inst/.*\.fis$", ("COPYING",),
           "The Octave Fuzzy Logic Toolkit's example .fis files. The toolkit at this commit "
           "is version 0.6.2; the file without a fuzzylite twin (mamdani_tip_calculator.fis) "
           "is compared with the toolkit itself, run by Octave (make_octave_references.py), "
           "and every file, read with dialect='octave', with the toolkit's own evalfis table "
           "of it."),
    Source("jfuzzylogic", "pcingola/jFuzzyLogic", r"\.fcl$|^tests/[^/]*\.txt$", ("LICENSE",),
           "jFuzzyLogic's .fcl files, and under tests/ the outputs its unit tests record "
           "(.txt)."),
)


def git(mirror: str, *args: str) -> bytes:
    return subprocess.run(["git", "--git-dir", mirror, *args], check=True,
                          capture_output=True).stdout


def main(argv: list[str]) -> int:
    mirrors = dict(arg.split("=", 1) for arg in argv)
    lines = [
        "# Sources of the conformance files",
        "",
        "Every file here is a public example file copied byte for byte by",
        "`tests/conformance/collect.py` from the repository and commit named below. They are test",
        "data under their own licences (each source's licence files are beside its files); the",
        "it2track wheel does not include them.",
    ]
    for source in SOURCES:
        mirror = mirrors[source.repo]
        commit = git(mirror, "rev-parse", "HEAD").decode().strip()
        paths = sorted(p for p in git(mirror, "ls-tree", "-r", "--name-only", "HEAD")
                       .decode().splitlines() if re.search(source.pattern, p))
        lines += ["", f"## {source.folder}/", "",
                  f"https://github.com/{source.repo} at commit `{commit}`. {source.note}", "",
                  "Licence files: " + ", ".join(f"`{name}`" for name in source.licences), "",
                  "| file (path in the repository) | sha256 (first 16) |", "|---|---|"]
        seen: dict[str, str] = {}
        duplicates = []
        for name in source.licences:
            target = FILES / source.folder / name
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(git(mirror, "show", f"HEAD:{name}"))
        for path in paths:
            data = git(mirror, "show", f"HEAD:{path}")
            digest = hashlib.sha256(data).hexdigest()
            if digest in seen:
                duplicates.append((path, seen[digest]))
                continue
            seen[digest] = path
            target = FILES / source.folder / path
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
            lines.append(f"| `{path}` | `{digest[:16]}` |")
        if duplicates:
            lines += ["", "Not copied (the same bytes as the file named):", ""]
            lines += [f"- `{path}` = `{first}`" for path, first in duplicates]
    (FILES / "SOURCES.md").write_text("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
