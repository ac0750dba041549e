// The ranges a scene file's numbers must lie in (docs/scenes.md, the
// "allowed" columns). Each is generous -- a factor of 100 or more around what
// a VSSS robot or ball is (model.md §9), and wide enough for every value the
// desktop app's scene dialog offers -- and still physical: within them every
// product the engine forms (rates like friction/mass, K²/R over an inertia)
// stays a normal, finite double, and a body's initial speed needs at most a
// few thousand collision sub-steps per step. Outside them a scene is refused
// rather than run into NaN or an effective hang. (Within them a step can
// still be beyond an integrator's stability limit: vssim run warns, and stops
// if the state stops being finite.)
#pragma once

#include <limits>

namespace vssim {

// A closed interval [min, max], or (min, max] when `aboveMin`.
struct AllowedRange {
    double min;
    double max;
    bool aboveMin;     // min itself excluded
    const char* unit;  // for messages: "kg", "m/s"; empty for none
};

// The integration step a scene (simulation.dt) or `--dt` may ask for, s
// (default 1 ms): up to 0.1 s, and down to 1 us, which still resolves a motor
// time constant of a few microseconds.
constexpr double kMinSceneTimeStep = 1e-6;
constexpr double kMaxSceneTimeStep = 0.1;

namespace scene_limits {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

constexpr AllowedRange kAny{-kInfinity, kInfinity, false, ""};
constexpr AllowedRange kUnitInterval{0.0, 1.0, false, ""};
constexpr AllowedRange kTimeStep{kMinSceneTimeStep, kMaxSceneTimeStep, false, "s"};

// Field (default 1.50 x 1.30 m): its length and width, and every other
// dimension (goals, corners, centre circle, goal areas, marks; 0 where a
// field has none). Whether they make a field together is checked by
// checkFieldDimensions (vssim/field.h).
constexpr AllowedRange kFieldSize{0.001, 100.0, false, "m"};
constexpr AllowedRange kFieldFeature{0.0, 100.0, false, "m"};

// Robot (defaults: 7.5 cm, 180 g, 1.7e-4 kg m², wheels 6.5 cm apart).
constexpr AllowedRange kRobotSide{1e-4, 10.0, false, "m"};
constexpr AllowedRange kRobotMass{1e-4, 1000.0, false, "kg"};
constexpr AllowedRange kRobotInertia{1e-9, 100.0, false, "kg m²"};
constexpr AllowedRange kWheelBase{1e-4, 10.0, false, "m"};
constexpr AllowedRange kLinearFriction{0.0, 1000.0, false, "N s/m"};
constexpr AllowedRange kAngularFriction{0.0, 100.0, false, "N m s/rad"};
constexpr AllowedRange kMaxVoltage{0.0, 1000.0, true, "V"};

// Motor, as seen at the wheel (defaults: 25 mm, 12 ohm, 0.09 V s/rad, 1e-5 kg m², 1e-4 N m s/rad).
constexpr AllowedRange kWheelRadius{1e-4, 1.0, false, "m"};
constexpr AllowedRange kResistance{0.001, 1e6, false, "Ω"};
constexpr AllowedRange kMotorConstant{1e-5, 100.0, false, "V s/rad"};
constexpr AllowedRange kRotorInertia{0.0, 10.0, false, "kg m²"};
constexpr AllowedRange kMotorFriction{0.0, 100.0, false, "N m s/rad"};

// The on-board speed loop (defaults: 200 Hz, 0.6 V/(rad/s), 10 V/rad, exact
// speed): rates from 1 Hz to 1 MHz (a loop faster than 1/dt samples once a
// step), gains from 0, an encoder of up to 2^24 counts a revolution.
constexpr AllowedRange kLoopRate{1.0, 1e6, false, "Hz"};
constexpr AllowedRange kLoopKp{0.0, 1e4, false, "V s/rad"};
constexpr AllowedRange kLoopKi{0.0, 1e6, false, "V/rad"};
constexpr AllowedRange kEncoderCounts{0.0, 16777216.0, false, "counts/rev"};
// Wheel-speed targets a scene command may give (rad/s); clients' are clamped to the same.
constexpr AllowedRange kWheelSpeedTarget{-1000.0, 1000.0, false, "rad/s"};

// Ball (defaults: 46 g, 21.35 mm, 0.02 N s/m).
constexpr AllowedRange kBallMass{1e-4, 100.0, false, "kg"};
constexpr AllowedRange kBallRadius{1e-5, 10.0, false, "m"};
constexpr AllowedRange kBallFriction{0.0, 1000.0, false, "N s/m"};

// Initial speeds: several times what the motors reach (a default robot's top
// speed is about 1.6 m/s) and what a kick gives a ball; a body far faster
// would need millions of sub-steps per step. A client or a person placing a
// body is held to the same (realtime/engine_request.h).
constexpr double kMaxRobotSpeed = 10.0;  // m/s
constexpr double kMaxYawRate = 100.0;    // rad/s
constexpr double kMaxBallSpeed = 20.0;   // m/s, |(vx, vy)|
constexpr AllowedRange kRobotSpeed{-kMaxRobotSpeed, kMaxRobotSpeed, false, "m/s"};
constexpr AllowedRange kRobotYawRate{-kMaxYawRate, kMaxYawRate, false, "rad/s"};
constexpr AllowedRange kBallVelocity{-kMaxBallSpeed, kMaxBallSpeed, false, "m/s"};

// The bodies may cover at most this fraction of the field's area: beyond it
// the contact passes cannot push them apart, and bodies ended metres outside
// the walls (10,000 robots on the default field). Random placement packs
// squares to about 0.55 of a plane, so half the field is already a crowd.
constexpr double kMaxCoveredFraction = 0.5;

// Command times, s (about 32 years): beyond it step indices lose meaning.
constexpr AllowedRange kCommandTime{0.0, 1e9, false, "s"};

// The game (docs/scenes.md, `game`; defaults: 2 halves of 300 s, STOP 4 s,
// a ball stuck below 0.10 m/s for 5 s, 3 s crowding, 0.20 m at a free ball,
// a tick of 10 ms). A tick must also be a whole number of steps of dt.
constexpr int kMaxHalves = 10;
constexpr AllowedRange kHalfDuration{0.0, 86400.0, true, "s"};
constexpr AllowedRange kStopDuration{0.0, 600.0, false, "s"};
constexpr AllowedRange kStuckBallSpeed{0.0, 10.0, false, "m/s"};
constexpr AllowedRange kRuleTime{0.0, 3600.0, true, "s"};
constexpr AllowedRange kFreeBallDistance{0.0, 1.0, true, "m"};
constexpr AllowedRange kGameTick{0.0, 1.0, true, "s"};

// The camera (docs/scenes.md, `camera`; the ideal camera by default): a
// camera above the robots' tops, a focal length from a pinhole to a long
// lens (0 = automatic), a lens distortion that OpenCV's model still inverts
// over the image, light and colour factors, a blur over up to 0.1 s, and
// delays and probabilities a vision system could still work with.
constexpr AllowedRange kCameraHeight{0.5, 20.0, false, "m"};
constexpr AllowedRange kFocalLength{0.0, 100000.0, false, "px"};
constexpr double kMinFocalLength = 50.0;  // px, unless 0 (automatic)
constexpr AllowedRange kRadialDistortion{-1.0, 1.0, false, ""};
constexpr AllowedRange kTangentialDistortion{-0.1, 0.1, false, ""};
constexpr AllowedRange kVignetting{0.0, 1.0, false, ""};
constexpr AllowedRange kLightGradient{-0.5, 0.5, false, ""};
constexpr AllowedRange kColourGain{0.0, 4.0, false, ""};
constexpr AllowedRange kSensorNoise{0.0, 100.0, false, "grey levels"};
constexpr AllowedRange kExposure{0.0, 0.1, false, "s"};
constexpr AllowedRange kBlurSamples{2.0, 64.0, false, ""};
constexpr AllowedRange kCameraDelay{0.0, 1.0, false, "s"};
constexpr AllowedRange kLossProbability{0.0, 0.9, false, ""};
constexpr AllowedRange kPositionNoise{0.0, 1.0, false, "m"};
constexpr AllowedRange kHeadingNoise{0.0, 3.141592653589793, false, "rad"};
constexpr AllowedRange kCameraSeed{0.0, 9007199254740992.0, false, ""};  // 2^53: exact as a JSON number

}  // namespace scene_limits

}  // namespace vssim
