"""The generated C on microcontrollers: it compiles warning-free for the ATmega328P and the
Cortex-M4F, runs on the cycle-accurate simavr with outputs bit-equal to the host float build,
and the exhaustive IT2 step of the paper's controller stays under 1 ms at 16 MHz.

simavr executes the AVR instruction by instruction with each instruction's datasheet cycle
count, and nothing in the program depends on the host: cycle counts are deterministic, which is
why a cycle bound may be asserted here (it is not a timing measurement of this machine)."""

from __future__ import annotations

import dataclasses
import subprocess

import numpy as np
import pytest
from codegen_helpers import random_system, skip_without

import it2track
from it2track.codegen import RealType, generate_c
from it2track.codegen.costs import measure_costs
from it2track.codegen.host import HostLibrary, build_host_library
from it2track.codegen.mcu import (
    ARM_FLAGS,
    AVR_CLOCK_HZ,
    AVR_FLAGS,
    arm_sizes,
    avr_sizes,
    cost_grid,
    run_on_avr,
)
from it2track.fuzzy import Reducer


@pytest.fixture(scope="module")
def build_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("c-builds")


@pytest.fixture(scope="module")
def avr():
    skip_without("avr-gcc", "avr-size", "avr-libc", "simavr")


def _host_float(code, x, build_dir):
    skip_without("gcc")
    return HostLibrary(code, build_host_library(code, build_dir)).evaluate(x)


def _bits(a):
    return np.asarray(a, dtype=np.float32).view(np.uint32)


def test_paper_controller_on_the_avr_equals_the_host_float_build(avr, build_dir):
    """A few hundred inputs (a grid, random points, points outside the universe, repeats)."""
    fls = it2track.heading_fls(0.2)
    code = generate_c(fls, real=RealType.FLOAT)
    x = np.concatenate([cost_grid(11, lo=-1.3, hi=1.3, n_random=150, seed=3),
                        cost_grid(11, lo=-1.3, hi=1.3)[:40]])
    run = run_on_avr(code, x, build_dir=build_dir)
    u, yl, yr, status = _host_float(code, x, build_dir)
    assert np.all(run.status == 0) and np.all(status == 0)
    for name, a, b in (("u", run.u, u), ("yl", run.yl, yl), ("yr", run.yr, yr)):
        diff = np.flatnonzero(_bits(a) != _bits(b))
        assert diff.size == 0, f"{name} differs at x={x[diff[:3]].tolist()}"
    # repeated inputs take exactly the same cycles: the simulator is deterministic
    np.testing.assert_array_equal(run.cycles[-40:], run.cycles[:40])
    assert np.all(run.cycles > 1000)
    ref = fls(x[:, 0].astype(np.float64), x[:, 1].astype(np.float64))
    assert np.max(np.abs(run.u - ref)) < 1e-5


@pytest.mark.parametrize("red", list(Reducer), ids=lambda r: r.value.name)
def test_every_reducer_runs_on_the_avr(avr, build_dir, red):
    fls = it2track.heading_fls(0.3, reducer=red.value)
    code = generate_c(fls, real=RealType.FLOAT)
    x = cost_grid(7, n_random=20, seed=4)
    run = run_on_avr(code, x, build_dir=build_dir)
    u, _, _, status = _host_float(code, x, build_dir)
    assert np.array_equal(run.status, status)
    assert np.array_equal(_bits(run.u), _bits(u))


def test_rule_language_features_on_the_avr(avr, build_dir):
    """NOT, OR (probabilistic or max) and weights: the AVR equals the host float build."""
    system = random_system(301, features=True, on_zero_firing=0.0,
                           shapes=("triangle", "trapezoid", "left", "right"))
    assert system.tables.features & {"not", "or", "weights"}
    code = generate_c(system, real=RealType.FLOAT)
    lo = [i.universe[0] for i in system.inputs]
    hi = [i.universe[1] for i in system.inputs]
    x = np.random.default_rng(1).uniform(lo, hi, size=(150, system.n_inputs)).astype(np.float32)
    run = run_on_avr(code, x, build_dir=build_dir)
    u, _, _, status = _host_float(code, x, build_dir)
    assert np.array_equal(run.status, status)
    assert np.array_equal(_bits(run.u), _bits(u))


def test_avr_error_statuses(avr, build_dir):
    from it2track.fuzzy import Input, IT2Set, IT2Sugeno, Rule
    n = IT2Set.triangle([-1, -1, -0.1], [-1, -1, -0.5], "N")
    p = IT2Set.triangle([0.1, 1, 1], [0.5, 1, 1], "P")
    fls = IT2Sugeno(inputs=[Input("x", (-1, 1), [n, p])],
                    rules=[Rule(["N"], -2.0), Rule(["P"], 2.0)])
    run = run_on_avr(generate_c(fls, real=RealType.FLOAT), np.array([[0.0], [0.7]]),
                     build_dir=build_dir)
    assert run.status.tolist() == [2, 0] and run.u[0] == 0.0 and run.u[1] == 2.0


def test_gaussian_system_on_the_avr(avr, build_dir):
    """Gaussian sets need exp: avr-libc's expf is not glibc's, so the AVR may differ from the
    host float build in the last bits; it stays within the derived float bound of Python."""
    from it2track.codegen.errorbound import float_error_bound
    system = random_system(7, reducer=Reducer.EXHAUSTIVE, on_zero_firing=0.0,
                           shapes=("gauss-std", "gauss-mean"))
    code = generate_c(system, real=RealType.FLOAT)
    assert "expf" in code.source
    x = np.random.default_rng(0).uniform(
        [i.universe[0] for i in system.inputs], [i.universe[1] for i in system.inputs],
        size=(120, system.n_inputs)).astype(np.float32)
    run = run_on_avr(code, x, build_dir=build_dir)
    x64 = x.astype(np.float64)
    ref = system(*x64.T)
    _, _, b_u = float_error_bound(system, x64)
    ok = np.isfinite(b_u)
    assert ok.mean() > 0.5
    assert np.all(np.abs(run.u[ok] - ref[ok]) <= b_u[ok])


def test_two_controllers_link_into_one_avr_program(avr, tmp_path):
    a = generate_c(it2track.heading_fls(0.2), real=RealType.FLOAT, prefix="left")
    b = generate_c(it2track.heading_fls(0.0, ), real=RealType.FLOAT, prefix="right")
    for code in (a, b):
        for name, text in code.files().items():
            (tmp_path / name).write_text(text)
    (tmp_path / "main.c").write_text(
        '#include "left.h"\n#include "right.h"\nvolatile float v[2], out;\n'
        "int main(void) {\n    float in[2], u, yl, yr;\n    in[0] = v[0];\n    in[1] = v[1];\n"
        "    left_eval(in, &u, &yl, &yr);\n    out = u;\n    right_eval(in, &u, &yl, &yr);\n"
        "    out += u;\n    return 0;\n}\n")
    subprocess.run(["avr-gcc", *AVR_FLAGS, "-o", "two.elf", "main.c", "left.c", "right.c"],
                   cwd=tmp_path, check=True, capture_output=True)


def test_double_build_compiles_for_the_avr(avr, tmp_path):
    """avr-gcc's double is 32-bit: a double build is a float build there (and still warns
    about nothing)."""
    code = generate_c(it2track.heading_fls(0.1, reducer=Reducer.KM.value))
    for name, text in code.files().items():
        (tmp_path / name).write_text(text)
    subprocess.run(["avr-gcc", *AVR_FLAGS, "-c", code.source_name], cwd=tmp_path, check=True,
                   capture_output=True)


@pytest.mark.parametrize("red", list(Reducer), ids=lambda r: r.value.name)
def test_cortex_m4f_build_and_sizes(build_dir, red):
    skip_without("arm-none-eabi-gcc", "arm-none-eabi-size", "newlib")
    code = generate_c(it2track.heading_fls(0.2, reducer=red.value), real=RealType.FLOAT)
    size = arm_sizes(code, build_dir=build_dir)
    assert 300 < size.text < 8000 and size.ram == 0
    assert "-mfloat-abi=hard" in ARM_FLAGS and "-mfpu=fpv4-sp-d16" in ARM_FLAGS


def test_avr_sizes(avr, build_dir):
    size = avr_sizes(generate_c(it2track.heading_fls(0.2), real=RealType.FLOAT),
                     build_dir=build_dir)
    assert size.ram == 0, "the tables are in flash and the controller keeps no state"
    assert 1000 < size.flash < size.program_flash < 32 * 1024
    assert 0 < size.stack < 1024


def test_cost_table_and_the_one_millisecond_aim(avr, build_dir):
    """measure_costs: every reducer measured in float and (but the Wu-Mendel bounds) in q15;
    the AVR output equals the host build of the same C; each error within its derived bound;
    the exact exhaustive reducer's worst float step stays under 1 ms at 16 MHz (16,000 cycles;
    measured 15,655 on the benchmark's 61 x 61 grid plus 2,000 random points)."""
    table = measure_costs(grid=9, n_random=40, arm=False, build_dir=build_dir)
    labels = [r.label for r in table.rows]
    assert labels[0].startswith("type-1") and len(labels) == 2 * (1 + len(Reducer)) - 1
    assert "IT2 wu-mendel (approx.), q15" not in labels
    for row in table.rows:
        assert 0 < row.cycles_mean <= row.cycles_max
        assert row.ram == 0 and row.stack > 0, row.label
        assert row.error <= row.bound, row.label
        assert row.error < (1e-5 if row.arithmetic == "float" else 1e-3), row.label
        assert row.us_max == pytest.approx(row.cycles_max / AVR_CLOCK_HZ * 1e6)
        assert row.equals_host, row.label
    exhaustive = next(r for r in table.rows if r.reducer == "exhaustive")
    assert exhaustive.arithmetic == "float" and exhaustive.cycles_max <= 16_000
    assert "| IT2 exhaustive | float |" in table.as_markdown()
    assert "| IT2 exhaustive, q15 | q15 |" in table.as_markdown()
    assert "IT2 exhaustive" in table.as_text()
    with pytest.raises(ValueError, match="arithmetics"):
        measure_costs(arithmetics=[RealType.DOUBLE], build_dir=build_dir)


def test_measure_costs_refuses_a_bad_grid():
    with pytest.raises(ValueError, match="n=1"):
        cost_grid(1)
    with pytest.raises(ValueError, match="shape"):
        run_on_avr(generate_c(it2track.heading_fls(0.2)), np.zeros((3, 3)))


def test_missing_tools_name_their_debian_packages(monkeypatch):
    import shutil

    from it2track.codegen import tools
    monkeypatch.setattr(shutil, "which", lambda name: None)
    monkeypatch.setattr(tools, "_avr_libc_present", lambda: False)
    with pytest.raises(tools.ToolMissingError) as info:
        tools.require(["avr-gcc", "avr-size", "avr-libc", "simavr"])
    msg = str(info.value)
    for package in ("gcc-avr", "binutils-avr", "avr-libc", "simavr"):
        assert package in msg
    assert tools.missing_tools(["arm-none-eabi-gcc"]) == ["gcc-arm-none-eabi"]
    _ = dataclasses


def test_cortex_m4f_gaussian_float_build_stays_single_precision(build_dir):
    """-Wdouble-promotion with -Werror: expf, float literals, no implicit double anywhere."""
    skip_without("arm-none-eabi-gcc", "arm-none-eabi-size", "newlib")
    system = random_system(9, features=True, shapes=("gauss-std", "gauss-mean"))
    code = generate_c(system, real=RealType.FLOAT)
    assert "-Wdouble-promotion" in ARM_FLAGS
    assert arm_sizes(code, build_dir=build_dir).text > 0
