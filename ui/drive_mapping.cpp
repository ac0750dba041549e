#include "drive_mapping.h"

#include <algorithm>
#include <cmath>

namespace vssim {

namespace {

// Clamps a stick value to [-1, 1]; NaN (a broken device) counts as centred.
double clampUnit(double v) {
    if (std::isnan(v)) return 0.0;
    return std::clamp(v, -1.0, 1.0);
}

}  // namespace

Voltages stickToVoltages(double x, double y, DriveMapping mapping, double maxVoltage) {
    const double vmax = (std::isfinite(maxVoltage) && maxVoltage > 0.0) ? maxVoltage : 0.0;  // V
    x = clampUnit(x);
    y = clampUnit(y);

    Voltages out;
    switch (mapping) {
        case DriveMapping::Tank:
            out.left = y * vmax;
            out.right = x * vmax;
            break;
        case DriveMapping::Arcade: {
            const double forward = y;  // + ahead
            const double turn = x;     // + clockwise: right wheel slower
            double right = forward - turn;
            double left = forward + turn;
            // Largest side is |forward| + |turn|: scale both down together.
            const double sum = std::abs(forward) + std::abs(turn);
            if (sum > 1.0) {
                right /= sum;
                left /= sum;
            }
            out.right = right * vmax;
            out.left = left * vmax;
            break;
        }
    }
    return out;
}

double applyDeadzone(double value, double deadzone) {
    value = clampUnit(value);
    if (std::isnan(deadzone) || deadzone >= 1.0) return 0.0;
    if (deadzone <= 0.0) return value;
    const double magnitude = std::abs(value);
    if (magnitude <= deadzone) return 0.0;
    const double scaled = (magnitude - deadzone) / (1.0 - deadzone);
    return std::copysign(std::min(scaled, 1.0), value);
}

WheelSpeeds voltagesToWheelSpeeds(const Voltages& volts, double maxVoltage, double freeWheelSpeed) {
    if (!(maxVoltage > 0.0) || !(freeWheelSpeed >= 0.0)) return {};
    auto side = [&](double e) {
        const double fraction = std::isnan(e) ? 0.0 : std::clamp(e / maxVoltage, -1.0, 1.0);
        return fraction * freeWheelSpeed;
    };
    return {side(volts.right), side(volts.left)};
}

}  // namespace vssim
