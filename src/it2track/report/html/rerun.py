"""The page's "How to rerun" section: the command, the configuration and the provenance."""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any

from markupsafe import Markup

from ...experiments.study import StudyResult
from .env import plain, render

__all__ = ["rerun_section"]


def rerun_section(result: StudyResult, manifest: Mapping[str, Any], elapsed_s: float) -> Markup:
    """The command that produced the report, its configuration as JSON, and the manifest's
    provenance (revision, platform, versions, everything else it records)."""
    command = str(manifest.get("command", "")) or "(command not recorded)"
    config_json = json.dumps(plain(result.config.to_dict()), indent=2, ensure_ascii=False)
    prov: list[tuple[str, Any]] = []
    for key in ("git_revision", "platform"):
        if key in manifest:
            prov.append((key.replace("_", " "), manifest[key]))
    versions = manifest.get("versions")
    if isinstance(versions, Mapping):
        prov += [(f"version: {k}", v) for k, v in versions.items()]
    for key, value in manifest.items():
        if key in ("command", "config", "versions", "git_revision", "platform", "elapsed_s"):
            continue
        prov.append((key, value if not isinstance(value, Mapping | list | tuple)
                     else json.dumps(plain(value), ensure_ascii=False, default=str)))
    prov.append(("elapsed", f"{elapsed_s:.1f} s"))
    return render("sections/rerun.html.j2", command=command, config_json=config_json,
                  provenance=prov)
