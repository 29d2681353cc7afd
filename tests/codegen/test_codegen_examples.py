"""The committed example controller is what the generator writes today, and the Arduino sketch
builds for the ATmega328P.

Without the Arduino core (not a Debian package this project installs) the sketch is compiled as
C++ with avr-g++ against a minimal stand-in for <Arduino.h> declaring the few functions it calls
(pinMode, digitalWrite, analogWrite, analogRead, millis) and linked with stub definitions and a
main() that calls setup() and loop(), as the Arduino core does."""

from __future__ import annotations

import subprocess
from pathlib import Path

from codegen_helpers import skip_without

import it2track
from it2track.authorship import seal_header
from it2track.codegen import RealType, generate_c

SKETCH = Path(__file__).resolve().parents[2] / "examples" / "arduino_it2flc"

ARDUINO_H = """\
#ifndef ARDUINO_H
#define ARDUINO_H
#include <math.h>
#define HIGH 1
#define LOW 0
#define OUTPUT 1
#define A0 14
#ifdef __cplusplus
extern "C" {
#endif
void pinMode(unsigned char pin, unsigned char mode);
void digitalWrite(unsigned char pin, unsigned char value);
void analogWrite(unsigned char pin, int value);
int analogRead(unsigned char pin);
unsigned long millis(void);
#ifdef __cplusplus
}
#endif
void setup(void);
void loop(void);
#endif
"""

STUBS = """\
#include "Arduino.h"
#include <avr/io.h>
static unsigned long ms;
void pinMode(unsigned char pin, unsigned char mode) { (void)pin; (void)mode; }
void digitalWrite(unsigned char pin, unsigned char value) { (void)pin; (void)value; }
void analogWrite(unsigned char pin, int value) { OCR0A = (unsigned char)(value + pin); }
int analogRead(unsigned char pin) { (void)pin; return ADC; }
unsigned long millis(void) { return ms += 10; }
int main(void) { setup(); for (;;) { loop(); } }
"""


def test_example_controller_is_current():
    code = generate_c(it2track.heading_fls(0.2), real=RealType.FLOAT, prefix="it2flc")
    for name, text in code.files().items():
        assert (SKETCH / name).read_text() == seal_header(text), (
            f"examples/arduino_it2flc/{name} is stale: regenerate it with\n"
            "  it2track export c --paper 0.2 --real float --prefix it2flc "
            "--out examples/arduino_it2flc")


def test_sketch_builds_for_the_atmega328p(tmp_path):
    skip_without("avr-gcc", "avr-g++", "avr-libc", "avr-size")
    (tmp_path / "Arduino.h").write_text(ARDUINO_H)
    (tmp_path / "stubs.cpp").write_text(STUBS)
    flags = ["-mmcu=atmega328p", "-Os", "-Wall", "-Wextra", "-Werror", f"-I{SKETCH}",
             f"-I{tmp_path}"]
    subprocess.run(["avr-gcc", *flags, "-std=c99", "-pedantic", "-c",
                    str(SKETCH / "it2flc.c"), "-o", "it2flc.o"],
                   cwd=tmp_path, check=True, capture_output=True)
    for src, obj in ((SKETCH / "arduino_it2flc.ino", "sketch.o"), (tmp_path / "stubs.cpp",
                                                                    "stubs.o")):
        proc = subprocess.run(["avr-g++", *flags, "-x", "c++", "-include", "Arduino.h", "-c",
                               str(src), "-o", obj], cwd=tmp_path, capture_output=True,
                              text=True)
        assert proc.returncode == 0, proc.stderr
    proc = subprocess.run(["avr-g++", "-mmcu=atmega328p", "-o", "sketch.elf", "sketch.o",
                           "stubs.o", "it2flc.o", "-lm"], cwd=tmp_path, capture_output=True,
                          text=True)
    assert proc.returncode == 0, proc.stderr
    out = subprocess.run(["avr-size", "sketch.elf"], cwd=tmp_path, capture_output=True,
                         text=True, check=True).stdout.splitlines()[1].split()
    assert int(out[0]) + int(out[1]) < 32 * 1024  # fits the Uno's flash
