// The paper's interval type-2 fuzzy heading controller (FoU 0.2, exhaustive type reduction) on an
// Arduino Uno (ATmega328P, 16 MHz), steering a two-wheeled differential-drive robot.
//
// it2flc.h / it2flc.c are generated, not written by hand:
//     it2track export c --paper 0.2 --real float --prefix it2flc --out examples/arduino_it2flc
// One step takes at most ~1 ms of the 10 ms control period (simavr cycle counts, see README
// "Deployment: C for microcontrollers"); the tables live in flash (PROGMEM), no RAM is static.
//
// Wiring assumed here (adapt to your robot): two H-bridge channels (e.g. an L298N) with a PWM
// input and a direction input each, motors on a 12 V supply; a heading sensor whose angle
// arrives as an analog voltage on A0 (0..5 V = -pi..pi), e.g. a compass or an IMU with an
// analog output. With wheel encoders instead, integrate the heading from the encoder counts:
// theta += r (dphi_R - dphi_L) / (2 l) each period (l: half the wheel track, r: wheel radius).

#include <math.h>
#include "it2flc.h"

const int PWM_R = 5, DIR_R = 4;      // right motor: PWM pin, direction pin
const int PWM_L = 6, DIR_L = 7;      // left motor
const int HEADING_PIN = A0;          // heading sensor, 0..1023 -> -pi..pi
const float V_SUPPLY = 12.0f;        // motor voltage at full PWM (the paper's +-12 V limit)
const float V0 = 6.0f;               // feed-forward voltage of the reference speed
const float KE = 1.0f, KDE = 1.0f;   // input gains (the paper's 1, 1)
const unsigned long TS_MS = 10;      // the paper's control period, 10 ms

static float theta_d = 0.0f;         // desired heading, rad (straight line along x here; for a
                                     // trajectory: atan2(yd - y, xd - x) from the pose estimate)
static float e_prev = 0.0f;
static unsigned long next_ms;

static float wrap_pi(float a)
{
    while (a > (float)M_PI) a -= 2.0f * (float)M_PI;
    while (a <= -(float)M_PI) a += 2.0f * (float)M_PI;
    return a;
}

static float measured_heading(void)
{
    return ((float)analogRead(HEADING_PIN) / 1023.0f) * 2.0f * (float)M_PI - (float)M_PI;
}

static void drive(int pwm_pin, int dir_pin, float volts)
{
    if (volts > V_SUPPLY) volts = V_SUPPLY;
    if (volts < -V_SUPPLY) volts = -V_SUPPLY;
    digitalWrite(dir_pin, volts >= 0.0f ? HIGH : LOW);
    analogWrite(pwm_pin, (int)(fabs(volts) / V_SUPPLY * 255.0f + 0.5f));
}

void setup()
{
    pinMode(PWM_R, OUTPUT);
    pinMode(DIR_R, OUTPUT);
    pinMode(PWM_L, OUTPUT);
    pinMode(DIR_L, OUTPUT);
    e_prev = wrap_pi(theta_d - measured_heading());
    next_ms = millis();
}

void loop()
{
    if ((long)(millis() - next_ms) < 0) {
        return;  // wait for the next control instant
    }
    next_ms += TS_MS;
    const float e = wrap_pi(theta_d - measured_heading());  // heading error, rad
    const float de = e - e_prev;                            // its change over one period
    e_prev = e;
    float in[IT2FLC_N_IN] = {KE * e, KDE * de};             // clipped to [-1, 1] by the controller
    float u, yl, yr;
    if (it2flc_eval(in, &u, &yl, &yr) != IT2FLC_OK) {
        u = 0.0f;  // only for a NaN or infinite input (a sensor fault)
    }
    drive(PWM_R, DIR_R, V0 + u);  // the paper's mixing: V_R = V0 + u, V_L = V0 - u
    drive(PWM_L, DIR_L, V0 - u);
}
