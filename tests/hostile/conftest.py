"""Fixtures of the bad-input suite (helpers: ``hostile_helpers``)."""

from __future__ import annotations

import pytest

#: The memory limit the suite runs under (it2track._limits reads it): the memory checks give
#: the same verdicts on every machine, and a case that slipped through could not start a
#: simulation bigger than this.
MEMORY_LIMIT = "4G"


@pytest.fixture(autouse=True)
def _memory_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("IT2TRACK_MEMORY_LIMIT", MEMORY_LIMIT)
