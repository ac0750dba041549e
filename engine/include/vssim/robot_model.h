// Matrices of the robot's motor dynamics, M u' + B u = K e (model.md §2,
// eq. 7), precomputed once from RobotParams, plus the derived outputs.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "vssim/robot_params.h"
#include "vssim/robot_state.h"

namespace vssim {

struct RobotModel {
    RobotParams params;
    Eigen::Matrix2d Tw;          // wheel speeds (w_d, w_e) -> body velocity (v, w)
    Eigen::Matrix2d TwInv;       // body velocity -> wheel speeds
    Eigen::Matrix2d M;           // generalized mass matrix, [kg, kg m; kg m, kg m^2]
    Eigen::Matrix2d B;           // generalized damping matrix
    Eigen::Matrix2d K;           // voltage input matrix
    Eigen::Matrix2d Minv;        // M^-1
    Eigen::Matrix2d A;           // -M^-1 B: u' = A u + G e
    Eigen::Matrix2d G;           // M^-1 K
    Eigen::Matrix2d steadyGain;  // B^-1 K: u_inf = steadyGain e, [m/(V s); rad/(V s)]

    // The two modes of the velocity dynamics: exp(A t) = sum_k e^(rate_k t) P_k.
    // A = -M^-1 B with M and B symmetric positive definite is similar to a
    // symmetric negative definite matrix, so the rates are real and negative
    // and A is diagonalizable. Used to bound speeds and travel (below) when
    // choosing step lengths (exact_integrator.h, world.h).
    std::array<double, 2> modeRate{};              // lambda_k, 1/s (<= 0), slowest first
    std::array<Eigen::Matrix2d, 2> modeProjector;  // P_k, P_1 + P_2 = I
    double fastestRate = 0.0;                      // max |lambda_k|, 1/s
};

RobotModel makeRobotModel(const RobotParams& params);

// Voltages clamped to +-max_voltage; NaN becomes 0 V (a dead input, never a NaN state).
inline Voltages clampVoltages(const RobotParams& params, const Voltages& e) {
    auto clampOne = [limit = params.max_voltage](double v) { return std::isnan(v) ? 0.0 : std::clamp(v, -limit, limit); };
    return {clampOne(e.right), clampOne(e.left)};
}

// u' = A u + G e, the velocity part of eq. 8.
Eigen::Vector2d velocityDerivative(const RobotModel& model, const Eigen::Vector2d& u, const Voltages& e);

// u_inf = B^-1 K e, the steady state under constant voltages.
Eigen::Vector2d steadyStateVelocity(const RobotModel& model, const Voltages& e);

// u(t) = u_inf + sum_k e^(rate_k t) P_k (u0 - u_inf): the body velocity t
// seconds after `state` under constant voltages e with nothing touching it.
Eigen::Vector2d velocityAfter(const RobotModel& model, const RobotState& state, const Voltages& e, double t);

// Bounds on |v(t)| and |w(t)| for all t >= 0 while the voltages stay e and
// nothing touches the robot: with u(t) = sum_k [e^(rate_k t) P_k u0 +
// (1 - e^(rate_k t)) P_k u_inf], each mode's share lies between its start
// and its end, so |u_j(t)| <= sum_k max(|(P_k u0)_j|, |(P_k u_inf)_j|).
// (m/s, rad/s); infinite when the state or the model is not finite.
Eigen::Vector2d velocityBound(const RobotModel& model, const RobotState& state, const Voltages& e);

// velocityBound's second component alone, rad/s (the same number; what the
// exact step's panel count reads, at every step of every robot).
double yawRateBound(const RobotModel& model, const RobotState& state, const Voltages& e);

// A bound on the speed of every point of the robot, |v| + |w| s/sqrt2, m/s,
// at every time t >= 0 under the same conditions (from velocityBound).
double pointSpeedBound(const RobotModel& model, const RobotState& state, const Voltages& e);
// How far each velocity mode has gone from its start towards its steady
// state T seconds on, 1 - e^(rate_k T): all that the bounds over [0, T]
// below need of T. Computed once, it serves every robot of the same rates
// (a team of one robot: every robot of a default scene) for the same T.
struct ModeProgress {
    double T = NAN;                   // s (NaN until computed: then it fits nothing)
    std::array<double, 2> rate{};     // the rates it is for, 1/s
    std::array<double, 2> covered{};  // 1 - e^(rate_k T), in [0, 1)
    bool fits(const RobotModel& model, double horizon) const {
        return T == horizon && rate == model.modeRate;
    }
};
ModeProgress modeProgress(const RobotModel& model, double T);
// `cache`, computed again for this model's rates and T only when it does
// not fit them already (for a loop over robots).
inline const ModeProgress& modeProgressFor(const RobotModel& model, double T, ModeProgress& cache) {
    if (!cache.fits(model, T)) cache = modeProgress(model, T);
    return cache;
}
// The progress over the few horizons a caller asks for again and again (the
// long-step planner: a stretch of 30 steps, what remains of it, one step),
// kept between calls instead of two exponentials per robot loop. A cache
// only: the values are modeProgress's, bit for bit.
class ModeProgressCache {
public:
    const ModeProgress& get(const RobotModel& model, double T) {
        std::uint64_t bits;
        std::memcpy(&bits, &T, sizeof bits);
        bits *= 0x9E3779B97F4A7C15ull;  // Fibonacci hashing: the top bits depend on the whole mantissa
        return modeProgressFor(model, T, slots_[static_cast<std::size_t>(bits >> 60) & (kSlots - 1)]);
    }

private:
    static constexpr std::size_t kSlots = 16;  // a power of two; a stretch's remainders are up to ~30 values
    std::array<ModeProgress, kSlots> slots_;   // by T's bits; a slot holds the horizon asked for last
};

// Where u = (v, w) lies over [0, T] only, T = progress.T
// (progress.fits(model, T)): each mode's share moves along a segment from
// P_k u0 towards P_k u_inf and has covered the fraction 1 - e^(rate_k T)
// of it at T, so u_j(t) lies between the sums over k of the smaller and
// the larger of (P_k u0)_j and (P_k u(T))_j, and |u_j(t)| <= sum_k
// max(|(P_k u0)_j|, |(P_k u(T))_j|), for t <= T. Much tighter than
// velocityBound over a millisecond for a robot far from its steady state
// (under new voltages).
struct VelocityRange {
    Eigen::Vector2d low = Eigen::Vector2d::Zero();        // (v, w) at least, m/s and rad/s
    Eigen::Vector2d high = Eigen::Vector2d::Zero();       // (v, w) at most
    Eigen::Vector2d magnitude = Eigen::Vector2d::Zero();  // (|v|, |w|) at most; infinite when the state or the model is not finite
};
VelocityRange velocityRangeWithin(const RobotModel& model, const RobotState& state, const Voltages& e,
                                  const ModeProgress& progress);

// A bound on how far a point of the robot at distance `arm` (m) from its
// centre can move within T seconds while the voltages stay e and nothing
// touches it, m: the integral over [0, T] of sum_k [e^(rate_k t) |D P_k u0|_1
// + (1 - e^(rate_k t)) |D P_k u_inf|_1], D = diag(1, arm), in closed form.
// arm = 0 bounds the centre's path: what matters for a disc that holds the
// robot at any heading. Exact for a robot whose modes each keep one sign;
// much tighter than a speed bound times T for a robot that starts slow.
// Infinite when the state or the model is not finite.
double robotTravelBound(const RobotModel& model, const RobotState& state, const Voltages& e, double T, double arm);
// The same with the modes' progress over T already computed (progress.fits(model, T)).
double robotTravelBound(const RobotModel& model, const RobotState& state, const Voltages& e,
                        const ModeProgress& progress, double arm);

// Quantities a user wants to see; not part of the state.
struct RobotOutputs {
    double wheel_speed_right = 0.0;  // w_d, rad/s
    double wheel_speed_left = 0.0;   // w_e, rad/s
    double current_right = 0.0;      // i_d, A
    double current_left = 0.0;       // i_e, A
    double torque_right = 0.0;       // tau_d delivered to the wheel, N m
    double torque_left = 0.0;        // tau_e, N m
};

RobotOutputs computeRobotOutputs(const RobotModel& model, const RobotState& state, const Voltages& e);

}  // namespace vssim
