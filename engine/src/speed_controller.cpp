#include "vssim/speed_controller.h"

#include <algorithm>
#include <cmath>

namespace vssim {

namespace {
constexpr double kTwoPi = 6.283185307179586476925286766559;
}

double measureWheelSpeed(const SpeedControllerParams& params, WheelLoopState& wheel, double speed, double period) {
    if (params.encoder_counts <= 0 || !std::isfinite(speed)) return speed;
    // Counts turned in the period: the speed at the sample
    // times the period, plus what was left over from the last period.
    const double countsPerRad = static_cast<double>(params.encoder_counts) / kTwoPi;
    const double turned = speed * period * countsPerRad + wheel.countFraction;
    const double whole = std::floor(turned);
    wheel.countFraction = turned - whole;
    return whole / (countsPerRad * period);
}

double updateWheelLoop(const SpeedControllerParams& params, WheelLoopState& wheel, double target, double measured,
                       double maxVoltage) {
    if (!std::isfinite(target) || !std::isfinite(measured)) return 0.0;
    const double period = 1.0 / params.rate;
    const double error = target - measured;  // rad/s
    // Conditional integration: the integrator takes this
    // period's error only if the output it would give is not saturated, or
    // if the error pulls a saturated output back towards the range.
    const double integrated = std::clamp(wheel.integral + params.ki * error * period, -maxVoltage, maxVoltage);
    const double unclamped = params.kp * error + integrated;
    const bool saturated = std::abs(unclamped) > maxVoltage;
    const bool pullsBack = (unclamped > 0) != (error > 0);
    if (!saturated || pullsBack) wheel.integral = integrated;
    return std::clamp(params.kp * error + wheel.integral, -maxVoltage, maxVoltage);
}

void updateSpeedLoop(const SpeedControllerParams& params, SpeedLoopState& loop, const WheelSpeeds& speeds,
                     double maxVoltage) {
    const double period = 1.0 / params.rate;
    const double right = measureWheelSpeed(params, loop.right, speeds.right, period);
    const double left = measureWheelSpeed(params, loop.left, speeds.left, period);
    loop.output.right = updateWheelLoop(params, loop.right, loop.target.right, right, maxVoltage);
    loop.output.left = updateWheelLoop(params, loop.left, loop.target.left, left, maxVoltage);
}

WheelSpeeds clampWheelSpeeds(const WheelSpeeds& target, double limit) {
    auto accept = [limit](double w) { return std::isnan(w) ? 0.0 : std::clamp(w, -limit, limit); };
    return {accept(target.right), accept(target.left)};
}

}  // namespace vssim
