#include "keyboard_driver.h"

#include <Qt>
#include <algorithm>
#include <cmath>

#include "drive_mapping.h"

namespace vssim {

namespace {

enum KeyBit : unsigned {
    KeyUp = 1u << 0,
    KeyW = 1u << 1,
    KeyDown = 1u << 2,
    KeyS = 1u << 3,
    KeyLeft = 1u << 4,
    KeyA = 1u << 5,
    KeyRight = 1u << 6,
    KeyD = 1u << 7,
};

constexpr unsigned kForward = KeyUp | KeyW;
constexpr unsigned kBackward = KeyDown | KeyS;
constexpr unsigned kTurnLeft = KeyLeft | KeyA;
constexpr unsigned kTurnRight = KeyRight | KeyD;

unsigned bitFor(int qtKey) {
    switch (qtKey) {
        case Qt::Key_Up: return KeyUp;
        case Qt::Key_W: return KeyW;
        case Qt::Key_Down: return KeyDown;
        case Qt::Key_S: return KeyS;
        case Qt::Key_Left: return KeyLeft;
        case Qt::Key_A: return KeyA;
        case Qt::Key_Right: return KeyRight;
        case Qt::Key_D: return KeyD;
        default: return 0;
    }
}

// +1 if any key of `positive` is held, -1 for `negative`, 0 for both or none.
double axis(unsigned held, unsigned positive, unsigned negative) {
    return ((held & positive) ? 1.0 : 0.0) - ((held & negative) ? 1.0 : 0.0);
}

}  // namespace

bool KeyboardDriver::handleKey(int qtKey, bool pressed) {
    const unsigned bit = bitFor(qtKey);
    if (bit == 0) return false;
    if (pressed)
        held_ |= bit;
    else
        held_ &= ~bit;
    return true;
}

Voltages KeyboardDriver::voltages(double maxVoltage, double fraction) const {
    if (std::isnan(fraction)) fraction = 0.0;
    fraction = std::clamp(fraction, 0.0, 1.0);
    const double forward = axis(held_, kForward, kBackward);  // +1 ahead
    double turn = axis(held_, kTurnRight, kTurnLeft);         // +1 clockwise
    if (forward != 0.0) turn *= kTurnWhileMoving;
    // Arcade mixing: (1, -0.5) gives right 1, left 1/3 after scaling.
    return stickToVoltages(turn, forward, DriveMapping::Arcade, fraction * maxVoltage);
}

}  // namespace vssim
