// The robot's on-board wheel-speed loop (docs/model.md, "The on-board speed
// loop"): what turns a wheel-speed command (FIRASim's clients, the TCP
// WHEEL_SPEEDS message, a scene's wheel_speeds commands) into the armature
// voltages that the motor model needs, as a real VSSS robot's firmware does. One discrete PI loop
// per wheel, sampled every 1/rate seconds of simulated time on the measured
// wheel speed (optionally through an incremental encoder of finite
// resolution), its output held until the next sample (zero-order hold),
// clamped to the battery voltage, with anti-windup by conditional
// integration. Plain functions over plain data: no clock, no state of its own.
#pragma once

#include <cstdint>

#include "vssim/robot_state.h"

namespace vssim {

// Wheel angular speeds, rad/s, positive driving the robot forward.
struct WheelSpeeds {
    double right = 0.0;  // w_d
    double left = 0.0;   // w_e
};

// The loop's parameters (scene: robot_defaults.speed_controller, and per robot).
// The defaults suit the default robot (robot_params.h): docs/model.md gives
// their step response (rise time, overshoot) and docs/firasim.md plots it.
struct SpeedControllerParams {
    double rate = 200.0;  // sampling rate, Hz (> 0): one update every 1/rate s of simulated time
    double kp = 0.6;      // proportional gain, V per rad/s of speed error
    double ki = 10.0;     // integral gain, V per rad of accumulated error (V/(rad/s)/s)
    // Encoder counts per wheel revolution (at the wheel, after the gearbox);
    // 0 measures the exact wheel speed. With N counts the measured speed is
    // a whole number of counts times 2 pi / (N T): the counts turned in the
    // period, estimated as the speed at the sample times T (not its average
    // over the period), with the fraction of a count carried over.
    int encoder_counts = 0;
};

// One wheel's loop state.
struct WheelLoopState {
    double integral = 0.0;  // ki times the accumulated error, V (the integrator's share of the output)
    double countFraction = 0.0;  // encoder: the part of a count turned and not yet counted, counts in [0, 1)
};

// One robot's loop state: whether it drives the motors, its targets, and
// when it samples next.
struct SpeedLoopState {
    bool active = false;  // the robot follows wheel-speed targets (false: voltages set directly)
    WheelSpeeds target;   // rad/s, held until the next command
    WheelLoopState right, left;
    Voltages output;              // the last update's voltages, V (held until the next update)
    std::int64_t sample = 0;      // index k of the next sample, at time k / rate
    std::int64_t nextStep = 0;    // the step at which sample k takes effect (first boundary at or after k / rate)
};

// The largest wheel-speed target accepted, rad/s (larger ones are clamped):
// far beyond any VSSS motor (the default robot's free speed is about 80 rad/s).
constexpr double kMaxWheelSpeedTarget = 1000.0;

// What drives a robot's motors from now on: voltages directly, or
// wheel-speed targets through its speed loop.
struct DriveCommand {
    bool wheelSpeeds = false;  // true: `speeds` through the loop; false: `voltages`
    Voltages voltages;         // V
    WheelSpeeds speeds;        // rad/s
    static DriveCommand ofVoltages(const Voltages& e) { return {false, e, {}}; }
    static DriveCommand ofWheelSpeeds(const WheelSpeeds& w) { return {true, {}, w}; }
};

// Encoder resolution above which counting makes no difference worth modelling.
constexpr int kMaxEncoderCounts = 1 << 24;

// What the encoder reports for a wheel turning at `speed` (rad/s) over one
// period T (s): the exact speed with encoder_counts 0, otherwise whole
// counts (the fraction kept in `wheel`) converted back to rad/s.
double measureWheelSpeed(const SpeedControllerParams& params, WheelLoopState& wheel, double speed, double period);

// One PI update of one wheel: returns the voltage (V), clamped to
// +-maxVoltage; the integrator moves only when the output is not saturated
// or the error pulls it back (conditional integration), and stays within
// +-maxVoltage itself. Non-finite targets or measurements give 0 V and leave
// the integrator alone.
double updateWheelLoop(const SpeedControllerParams& params, WheelLoopState& wheel, double target, double measured,
                       double maxVoltage);

// One sample of a robot's loop: measures both wheels (`speeds`: the true
// wheel speeds now, rad/s) and sets loop.output. Does not touch loop.sample.
void updateSpeedLoop(const SpeedControllerParams& params, SpeedLoopState& loop, const WheelSpeeds& speeds,
                     double maxVoltage);

// Targets as accepted: NaN becomes 0 rad/s (a dead input, as for voltages),
// and each is clamped to +-limit (rad/s).
WheelSpeeds clampWheelSpeeds(const WheelSpeeds& target, double limit);

}  // namespace vssim
