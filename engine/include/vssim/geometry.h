// Planar geometry of the bodies (model.md §5): a robot is a square of side s
// centred on its pose; the ball is a disc. All in the field frame, metres.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>

#include "vssim/robot_state.h"

namespace vssim {

// The cosine and sine of an angle (rad), by the engine's own code rather
// than the C library's: about 60 % of the instructions of glibc's sincos()
// (headings are turned at every integration stage and every gap or contact
// test, so this is a good part of a step), within 2.5 units in the last
// place of the exact values (2.1 measured; glibc: about 0.5;
// tests/test_geometry.cpp), and the same bits with any C library for
// |angle| <= 1e6 rad (plain double arithmetic, no contraction into fused
// multiply-adds: the project compiles with -ffp-contract=off), which keeps
// runs identical across machines.
struct CosSin {
    double c = 1.0;
    double s = 0.0;
};

// sin and cos of |d| <= pi/4 by their Taylor series to d^17 and d^18: the
// remainders, below (pi/4)^19/19! ~ 8e-20 and (pi/4)^20/20! ~ 3e-21, are
// under rounding; for |d| <= 0.2 (most turns within an integration panel)
// to d^11 and d^10 only, whose remainders are below 0.2^13/13! ~ 1e-19 and
// 0.2^12/12! ~ 9e-18. Summed from the small terms up (Horner); the leading
// 1 of the cosine is added last, with 1 - d^2/2's rounding error carried.
// sinCosNearZero's short series, for q = d * d <= 0.04 only. Branch-free,
// and for T = double or a vector of doubles (the exact integrator takes two
// angles at a time), the same operations in the same order either way.
template <typename T>
inline void sinCosSmall(T d, T q, T& s, T& c) {
    const T half = 0.5 * q;
    const T head = 1.0 - half;  // rounded; (1 - head) - half is what the rounding lost
    const T sinTail = -1.0 / 6 + q * (1.0 / 120 + q * (-1.0 / 5040 + q * (1.0 / 362880 + q * (-1.0 / 39916800))));
    const T cosTail = 1.0 / 24 + q * (-1.0 / 720 + q * (1.0 / 40320 + q * (-1.0 / 3628800)));
    s = d + (d * q) * sinTail;
    c = head + (((1.0 - head) - half) + (q * q) * cosTail);
}

inline void sinCosNearZero(double d, double& s, double& c) {
    const double q = d * d;
    if (q <= 0.04) {
        sinCosSmall(d, q, s, c);
        return;
    }
    const double half = 0.5 * q;
    const double head = 1.0 - half;
    const double sinTail = -1.0 / 6 + q * (1.0 / 120 + q * (-1.0 / 5040 + q * (1.0 / 362880 + q * (-1.0 / 39916800 +
                           q * (1.0 / 6227020800 + q * (-1.0 / 1307674368000 + q * (1.0 / 355687428096000.0)))))));
    const double cosTail = 1.0 / 24 + q * (-1.0 / 720 + q * (1.0 / 40320 + q * (-1.0 / 3628800 + q * (1.0 / 479001600 +
                           q * (-1.0 / 87178291200.0 + q * (1.0 / 20922789888000.0 + q * (-1.0 / 6402373705728000.0)))))));
    s = d + (d * q) * sinTail;
    c = head + (((1.0 - head) - half) + (q * q) * cosTail);
}

inline CosSin cosSin(double angle) {
    CosSin r;
    // Beyond 1e6 rad (and for NaN and infinities) the C library's, whose
    // reduction handles any angle: a robot spinning at 50 rad/s gets there
    // after five and a half hours.
    if (!(std::abs(angle) <= 1e6)) {
        r.c = std::cos(angle);
        r.s = std::sin(angle);
        return r;
    }
    // angle = k pi/2 + d, |d| <= pi/4 (Cody and Waite's reduction): pi/2 in
    // three parts, the first two of at most 33 significant bits, so that k
    // times them is exact for |k| < 2^20 (|angle| < 1.6e6 rad) and only the
    // last product rounds.
    constexpr double kTwoOverPi = 0.63661977236758134308;
    constexpr double kHalfPiHigh = 1.57079632673412561417e+00;
    constexpr double kHalfPiMiddle = 6.07710050630396597660e-11;
    constexpr double kHalfPiLow = 2.02226624879595063154e-21;
    constexpr double kRoundingShift = 6755399441055744.0;  // 1.5 * 2^52: adding it rounds to an integer
    const double k = (angle * kTwoOverPi + kRoundingShift) - kRoundingShift;
    const double d = ((angle - k * kHalfPiHigh) - k * kHalfPiMiddle) - k * kHalfPiLow;
    double s, c;
    sinCosNearZero(d, s, c);
    // The quarter turn k mod 4: swap for odd k, signs by quadrant (selects, not branches).
    const long long quarter = static_cast<long long>(k);
    const double sine = (quarter & 1) ? c : s, cosine = (quarter & 1) ? s : c;
    r.s = (quarter & 2) ? -sine : sine;
    r.c = ((quarter + 1) & 2) ? -cosine : cosine;
    return r;
}

// The radius of the disc around a robot's centre that holds the square at any
// heading: half its diagonal, s / sqrt2, m (model.md §5).
inline double boundingRadius(double side) { return side / std::sqrt(2.0); }

// Half the side of the axis-aligned box around a robot of side `side` at
// heading theta: (s/2)(|cos theta| + |sin theta|), m.
inline double robotHalfExtent(double side, double theta) {
    const CosSin r = cosSin(theta);
    return 0.5 * side * (std::abs(r.c) + std::abs(r.s));
}

// Vertex j = 0..3 at (s/sqrt2)(cos, sin)(theta + 45deg + 90deg j) from the centre.
std::array<Eigen::Vector2d, 4> robotVertices(const RobotState& pose, double side);

// The closest point of segment [a, b] to p (paper eqs. 10-11): lambda of the
// projection clamped to [0, 1].
struct SegmentClosestPoint {
    double lambda = 0.0;                              // clamped parameter along a -> b
    Eigen::Vector2d point = Eigen::Vector2d::Zero();  // a + lambda (b - a), m
    double distance = 0.0;                            // |p - point|, m
};
// (Inline: the separations and the walls' tests call it in their inner loops.)
inline SegmentClosestPoint closestPointOnSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                                 const Eigen::Vector2d& p) {
    const Eigen::Vector2d ab = b - a;
    const double len2 = ab.squaredNorm();
    SegmentClosestPoint c;
    c.lambda = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    c.point = a + c.lambda * ab;
    c.distance = (p - c.point).norm();
    return c;
}

// p expressed in the robot's frame (x forward, y to the left), m.
Eigen::Vector2d toRobotFrame(const RobotState& pose, const Eigen::Vector2d& p);
Eigen::Vector2d fromRobotFrame(const RobotState& pose, const Eigen::Vector2d& local);

// The paper's test: |x_r| <= s/2 + margin and |y_r| <= s/2 + margin in the robot's frame.
bool pointInRobot(const RobotState& pose, double side, const Eigen::Vector2d& p, double margin = 0.0);

// Separating-axis test of two squares. When they overlap, `normal` is the
// unit axis of least penetration, oriented from B towards A (the direction A
// must move to separate), and `depth` the penetration along it (m).
struct SquareOverlap {
    bool overlapping = false;
    Eigen::Vector2d normal = Eigen::Vector2d::Zero();
    double depth = 0.0;
};
SquareOverlap squareOverlap(const RobotState& a, double sideA, const RobotState& b, double sideB);
// The same with the headings' cosines and sines already computed (cosSin(a.theta), cosSin(b.theta)).
SquareOverlap squareOverlap(const RobotState& a, const CosSin& headingA, double sideA, const RobotState& b,
                            const CosSin& headingB, double sideB);

}  // namespace vssim
