"""Processor in the loop (AvrInTheLoop): the generated C on simavr embedded as a library.

Reference: the cost benchmark's own run (run_on_avr, simavr as a process with the inputs in
flash; measure_costs on top of it) -- the same outputs bit for bit and the same cycles per
input, whatever the system, arithmetic, reducer, batch split or thread count."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from codegen_helpers import points, random_system, skip_without

import it2track
from it2track.codegen import RealType, generate_c
from it2track.codegen.costs import measure_costs
from it2track.codegen.mcu import cost_grid, run_on_avr
from it2track.codegen.pil import AvrInTheLoop, build_pil_firmware, build_pil_shim
from it2track.codegen.tools import PIL_TOOLS, ToolMissingError
from it2track.fuzzy import Reducer


@pytest.fixture(scope="module")
def build_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("pil")


def _same(pil, ref):
    for name in ("u", "yl", "yr"):
        a, b = getattr(pil, name), getattr(ref, name)
        assert a.dtype == b.dtype and a.tobytes() == b.tobytes(), name
    assert np.array_equal(pil.status, ref.status)
    assert np.array_equal(pil.cycles, ref.cycles)


@pytest.mark.parametrize("real", [RealType.FLOAT, RealType.Q15], ids=lambda r: r.value)
@pytest.mark.parametrize("red", [Reducer.EXHAUSTIVE, Reducer.KM, Reducer.EIASC],
                         ids=lambda r: r.value.name)
def test_paper_controller_equals_the_benchmark_run(red, real, build_dir):
    skip_without(*PIL_TOOLS, "simavr")
    fls = dataclasses.replace(it2track.heading_fls(0.2), reducer=red.value)
    code = generate_c(fls, real=real)
    x = np.concatenate([cost_grid(9, n_random=40, seed=3).astype(np.float64),
                        [[3.0, -2.5], [-1e-30, 0.0], [0.2, 0.2]]])  # clipped, tiny, dead zone
    ref = run_on_avr(code, x, build_dir=build_dir)
    with AvrInTheLoop(code, build_dir=build_dir) as mcu:
        u, raw = mcu.step(x)
    _same(raw, ref)
    want = code.fixed.to_real(ref.u) if code.fixed is not None else ref.u.astype(np.float64)
    assert np.array_equal(u, want)


def test_cycles_equal_measure_costs(build_dir):
    """The cost table's worst and mean cycles per reducer and arithmetic, over its grid."""
    skip_without(*PIL_TOOLS, "simavr", "avr-size")
    reducers = [Reducer.EXHAUSTIVE, Reducer.KM]
    table = measure_costs(reducers=reducers, grid=4, include_type1=True, variants=False,
                          arm=False, build_dir=build_dir)
    x = cost_grid(4).astype(np.float64)
    systems = {"type-1 FLC (FoU 0)": it2track.heading_fls(0.0)}
    for red in reducers:
        systems[f"IT2 {red.value.name}"] = dataclasses.replace(it2track.heading_fls(0.2),
                                                               reducer=red.value)
    assert len(table.rows) == 6
    for row in table.rows:
        label = row.label.removesuffix(", q15")
        with AvrInTheLoop(generate_c(systems[label], real=RealType(row.arithmetic)),
                          build_dir=build_dir) as mcu:
            _, raw = mcu.step(x)
        assert int(raw.cycles.max()) == row.cycles_max, row.label
        assert float(raw.cycles.mean()) == row.cycles_mean, row.label


@pytest.mark.parametrize("seed", [5, 21, 33, 47])
def test_random_systems_equal_the_benchmark_run(seed, build_dir):
    """Any number of inputs, every set shape (Gaussians too: both sides are the AVR), zero
    firing statuses, on points beyond the universes."""
    skip_without(*PIL_TOOLS, "simavr")
    system = random_system(seed)
    code = generate_c(system, real=RealType.FLOAT, prefix=f"r{seed}")
    x = points(system, 40, seed, grid=5)
    ref = run_on_avr(code, x, build_dir=build_dir)
    with AvrInTheLoop(code, build_dir=build_dir) as mcu:
        _, raw = mcu.step(x)
    _same(raw, ref)


def test_threads_and_batch_split_do_not_change_anything(build_dir):
    skip_without(*PIL_TOOLS)
    code = generate_c(it2track.heading_fls(0.1), real=RealType.FLOAT)
    x = cost_grid(7, n_random=30, seed=9)
    with AvrInTheLoop(code, build_dir=build_dir) as one:
        whole = one.step_raw(x)
        halves = [one.step_raw(x[:20]), one.step_raw(x[20:])]
    with AvrInTheLoop(code, threads=3, build_dir=build_dir) as three:
        assert three.threads == 3
        threaded = three.step_raw(x)
        single = three.step_raw(x[:1])
    _same(threaded, whole)
    for name in ("u", "cycles", "status"):
        joined = np.concatenate([getattr(h, name) for h in halves])
        assert np.array_equal(joined, getattr(whole, name))
    assert single.u.tobytes() == whole.u[:1].tobytes()


def test_the_mcu_does_not_run_between_calls(build_dir):
    """Between two calls the simulated clock stands still; a call advances it by more than
    the measured cycles (the exchange and the measurement itself run on the MCU too)."""
    skip_without(*PIL_TOOLS)
    code = generate_c(it2track.heading_fls(0.2), real=RealType.FLOAT)
    with AvrInTheLoop(code, build_dir=build_dir) as mcu:
        start = mcu.cycle()
        assert mcu.cycle() == start
        raw = mcu.step_raw(np.array([[0.5, -0.25]], dtype=np.float32))
        spent = mcu.cycle() - start
    assert raw.cycles[0] < spent < raw.cycles[0] + 400


def test_inputs_are_checked(build_dir):
    skip_without(*PIL_TOOLS)
    code = generate_c(it2track.heading_fls(0.2), real=RealType.Q15)
    mcu = AvrInTheLoop(code, build_dir=build_dir)
    with pytest.raises(ValueError, match="dtype int16"):
        mcu.step_raw(np.zeros((2, 2), dtype=np.float32))
    with pytest.raises(ValueError, match=r"shape \(N, 2\)"):
        mcu.step_raw(np.zeros((2, 3), dtype=np.int16))
    assert mcu.step_raw(np.zeros((0, 2), dtype=np.int16)).u.shape == (0,)
    mcu.close()
    mcu.close()  # idempotent
    with pytest.raises(ValueError, match="closed"):
        mcu.step_raw(np.zeros((1, 2), dtype=np.int16))
    with pytest.raises(ValueError, match="threads=0 must be a positive integer"):
        AvrInTheLoop(code, threads=0, build_dir=build_dir)


def test_builds_are_cached_by_content(build_dir):
    skip_without(*PIL_TOOLS)
    shim = build_pil_shim(build_dir)
    stamp = shim.stat().st_mtime_ns
    assert build_pil_shim(build_dir) == shim and shim.stat().st_mtime_ns == stamp
    a = build_pil_firmware(generate_c(it2track.heading_fls(0.2)), build_dir)
    b = build_pil_firmware(generate_c(it2track.heading_fls(0.2)), build_dir)
    c = build_pil_firmware(generate_c(it2track.heading_fls(0.3)), build_dir)
    assert a == b and a.elf != c.elf
    assert 0x100 <= a.block < 0x900  # in the ATmega328P's SRAM


def test_a_missing_libsimavr_is_named(monkeypatch, build_dir):
    import it2track.codegen.tools as tools

    monkeypatch.setattr(tools, "_libsimavr_present", lambda: False)
    with pytest.raises(ToolMissingError, match="libsimavr-dev"):
        AvrInTheLoop(generate_c(it2track.heading_fls(0.2)), build_dir=build_dir)
