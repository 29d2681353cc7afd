"""The q15 build on the microcontrollers: on the simulated ATmega328P (its multiplications in
assembly) it returns the host build's bits -- integer C is deterministic -- and so does the
portable C compiled for the AVR; it builds for the Cortex-M4F; and its cycles per step stand
beside the float build's.

simavr executes the AVR instruction by instruction with each instruction's datasheet cycle
count, so cycle counts are deterministic and a cycle bound may be asserted (it is not a timing
measurement of this machine)."""

from __future__ import annotations

import dataclasses
import re
import subprocess

import numpy as np
import pytest
from codegen_helpers import random_system, skip_without

import it2track
from it2track.codegen import RealType, generate_c
from it2track.codegen.host import HostLibrary, build_host_library
from it2track.codegen.mcu import AVR_FLAGS, arm_sizes, avr_sizes, cost_grid, run_on_avr
from it2track.fuzzy import Reducer

FIXED_REDUCERS = [r for r in Reducer if r.value.name != "wu-mendel"]
PL_SHAPES = ("triangle", "trapezoid", "left", "right")


@pytest.fixture(scope="module")
def build_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("c-builds")


@pytest.fixture(scope="module")
def avr():
    skip_without("avr-gcc", "avr-size", "avr-libc", "simavr")


def host(code, build_dir):
    skip_without("gcc")
    return HostLibrary(code, build_host_library(code, build_dir))


def inputs(n_random, seed):
    """Real inputs over and beyond the square, the square's corners and edges, and points
    whose rounding to Q15 saturates."""
    x = cost_grid(9, lo=-1.3, hi=1.3, n_random=n_random, seed=seed).astype(np.float64)
    return np.concatenate([x, [[1.0, 1.0], [-1.0, -1.0], [1.0, -1.0], [0.99999, 0.0]]])


def same_bits(run, lib):
    u, yl, yr, status = lib.evaluate_raw(run.x)
    assert np.array_equal(run.status, status)
    for name, a, b in (("u", run.u, u), ("yl", run.yl, yl), ("yr", run.yr, yr)):
        diff = np.flatnonzero(a != b)
        assert diff.size == 0, f"{name} differs at q={run.x[diff[:3]].tolist()}"


@pytest.mark.parametrize("red", FIXED_REDUCERS, ids=lambda r: r.value.name)
def test_paper_controller_on_the_avr_equals_the_host_build(avr, build_dir, red):
    code = generate_c(it2track.heading_fls(0.2, reducer=red.value), real=RealType.Q15)
    run = run_on_avr(code, inputs(120, 2), build_dir=build_dir)
    assert run.u.dtype == np.int16 and run.x.dtype == np.int16
    same_bits(run, host(code, build_dir))
    assert np.all(run.status == 0)


@pytest.mark.parametrize("seed", [800, 801, 802])
def test_random_systems_on_the_avr_equal_the_host_build(avr, build_dir, seed):
    """Interval consequents, both t-norms, 1-3 inputs, a zero-firing value."""
    system = random_system(seed, reducer=FIXED_REDUCERS[seed % 5], shapes=PL_SHAPES,
                           on_zero_firing=0.75 if seed % 2 else None)
    code = generate_c(system, real=RealType.Q15)
    lo = np.array([i.universe[0] for i in system.inputs])
    hi = np.array([i.universe[1] for i in system.inputs])
    x = np.random.default_rng(seed).uniform(lo - 0.2, hi + 0.2, size=(150, system.n_inputs))
    same_bits(run_on_avr(code, x, build_dir=build_dir), host(code, build_dir))


def test_portable_c_on_the_avr_equals_the_assembly(avr, build_dir, tmp_path):
    """With <PREFIX>_PORTABLE defined the AVR build uses the plain C products: the same bits,
    more cycles -- so the assembly computes exactly what the C specifies."""
    code = generate_c(it2track.heading_fls(0.3, reducer=Reducer.EXHAUSTIVE.value),
                      real=RealType.Q15)
    x = inputs(150, 5)
    asm = run_on_avr(code, x, build_dir=build_dir)
    portable = dataclasses.replace(code, source="#define IT2_PORTABLE 1\n" + code.source)
    c = run_on_avr(portable, x, build_dir=build_dir)
    for a, b in ((asm.u, c.u), (asm.yl, c.yl), (asm.yr, c.yr)):
        np.testing.assert_array_equal(a, b)
    assert c.cycles.max() > asm.cycles.max()
    assert "__asm__" in code.source and "#if defined(__AVR__)" in code.source


def test_fixed_point_cycles_beside_the_float_build(avr, build_dir):
    """The exhaustive reducer's worst step over a 21 x 21 grid plus 300 random inputs: q15
    measured 6,049 cycles (0.38 ms at 16 MHz), the float build 15,6xx; the guard leaves 5 %."""
    x = cost_grid(21, n_random=300, seed=1).astype(np.float64)
    fls = it2track.heading_fls(0.2)
    fixed = run_on_avr(generate_c(fls, real=RealType.Q15), x, build_dir=build_dir)
    flt = run_on_avr(generate_c(fls, real=RealType.FLOAT), x, build_dir=build_dir)
    assert fixed.cycles.max() <= 6_400
    assert fixed.cycles.max() * 2.4 < flt.cycles.max()
    t1 = run_on_avr(generate_c(it2track.heading_fls(0.0), real=RealType.Q15), x,
                    build_dir=build_dir)
    assert t1.cycles.max() <= 2_500


def test_sizes_and_the_cortex_m4f_build(avr, build_dir):
    code = generate_c(it2track.heading_fls(0.2), real=RealType.Q15)
    size = avr_sizes(code, build_dir=build_dir)
    assert size.ram == 0 and 0 < size.stack < 512
    assert size.flash < size.program_flash < 32 * 1024
    skip_without("arm-none-eabi-gcc", "arm-none-eabi-size", "newlib")
    arm = arm_sizes(code, build_dir=build_dir)
    assert 500 < arm.text < 16_000 and arm.ram == 0


def test_no_floating_point_reaches_the_avr_program(avr, tmp_path):
    """The q15 program links no software-float routine."""
    code = generate_c(it2track.heading_fls(0.2), real=RealType.Q15)
    for name, text in code.files().items():
        (tmp_path / name).write_text(text)
    (tmp_path / "main.c").write_text(
        '#include "it2.h"\nvolatile it2_real v[2], o;\nint main(void) {\n'
        "    it2_real in[2], u, yl, yr;\n    in[0] = v[0];\n    in[1] = v[1];\n"
        "    it2_eval(in, &u, &yl, &yr);\n    o = u;\n    return 0;\n}\n")
    subprocess.run(["avr-gcc", *AVR_FLAGS, "-o", "p.elf", "main.c", "it2.c"], cwd=tmp_path,
                   check=True, capture_output=True)
    syms = subprocess.run(["avr-nm", "p.elf"], cwd=tmp_path, capture_output=True, text=True,
                          check=True).stdout
    assert not re.search(r"__(add|sub|mul|div|fix|float)[a-z]*sf", syms), syms
