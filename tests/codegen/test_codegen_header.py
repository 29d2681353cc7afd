"""The generated header's comment tells the truth about the statuses the code can return."""

from __future__ import annotations

import dataclasses
import re

import pytest

import it2track
from it2track.codegen import generate_c
from it2track.fuzzy import Reducer

#: Reducers that iterate (and may return the no-convergence status), with their cap.
ITERATIVE = {Reducer.KM, Reducer.EKM, Reducer.EIASC}


def _status_line(header: str) -> str:
    (line,) = [ln for ln in header.splitlines() if "IT2_NO_CONVERGENCE " in ln and "*" in ln]
    return line


@pytest.mark.parametrize("red", list(Reducer), ids=lambda r: r.value.name)
def test_no_convergence_line_matches_the_reducer(red):
    fls = dataclasses.replace(it2track.heading_fls(0.2), reducer=red.value)
    line = _status_line(generate_c(fls).header)
    assert "(not iterative)" not in line and "in None" not in line
    if red in ITERATIVE:
        cap = re.search(r"did not converge in (\d+) iterations$", line)
        assert cap, line
        assert int(cap.group(1)) == red.value._cap(fls.n_rules)
    else:
        assert line.endswith("never returned: this type reducer is not iterative"), line


def test_a_type1_system_says_its_reducer_is_not_iterative():
    line = _status_line(generate_c(it2track.heading_fls(0.0)).header)
    assert line.endswith("never returned: this type reducer is not iterative"), line
