// Driving a robot with the keyboard: which drive keys are held, and the
// voltages they ask for. Deterministic (no timers, no key repeat): the
// caller forwards key presses and releases and reads voltages() when it
// sends them. Not a QObject.
#pragma once

#include "vssim/robot_state.h"

namespace vssim {

class KeyboardDriver {
public:
    // Fraction of the maximum voltage the keys apply by default.
    static constexpr double kDefaultFraction = 0.6;
    // While driving forward or backward a turn key only slows one side
    // (a gentle arc) instead of spinning in place: the turn is this fraction
    // of the forward command before mixing (see voltages()).
    static constexpr double kTurnWhileMoving = 0.5;

    // qtKey is a Qt::Key. Drive keys: Up or W forward, Down or S backward,
    // Left or A turn left (counter-clockwise), Right or D turn right
    // (clockwise). Each physical key is tracked on its own (releasing W
    // while Up is held keeps driving forward); repeated presses are
    // harmless. Returns whether qtKey is a drive key (the caller may then
    // consider the event handled). Callers should ignore auto-repeat events
    // or not; the result is the same.
    bool handleKey(int qtKey, bool pressed);

    // Whether any drive key is held (even if opposite keys cancel out).
    bool active() const { return held_ != 0; }

    // Voltages (V) for the keys held. fraction (dimensionless, clamped to
    // [0, 1]) of maxVoltage (V) is what a single key applies:
    //   forward:  right = left = +fraction*maxVoltage; backward: both -.
    //   left alone:  right = +f*max, left = -f*max (spin counter-clockwise);
    //   right alone: right = -f*max, left = +f*max (spin clockwise).
    //   forward + left: right = +f*max, left = +f*max/3 (left slower: an arc
    //   to the left); forward + right mirrors it; backward + a turn key runs
    //   the same arc backwards, the turn key still naming the direction the
    //   heading rotates (backward + right: clockwise, left wheel slower
    //   backwards). Opposite keys (forward + backward, left + right) cancel.
    //   Nothing held: 0, 0.
    Voltages voltages(double maxVoltage, double fraction = kDefaultFraction) const;

    // Forgets every held key (e.g. when the window loses focus, or the
    // selected robot changes).
    void releaseAll() { held_ = 0; }

private:
    unsigned held_ = 0;  // one bit per drive key (see keyboard_driver.cpp)
};

}  // namespace vssim
