// The instant at which two moving bodies first touch within a step, by
// conservative advancement (model.md §5 shapes, §2 and §4 motion): the long-step
// planner (long_step_planner.cpp) resolves each contact at that instant
// instead of at the end of the step it falls in.
//
// Conservative advancement: if the gap d(t) between two bodies can close at
// most at speed S (the sum of the fastest any point of either can move), no
// contact is possible before t + d(t)/S; advancing by that much each time
// never passes the first contact, and stops when the gap is below
// kTouchDistance. Proof of safety: |d(t) - d(s)| <= S |t - s| because d is
// the distance between two sets each of whose points moves at most at its
// body's speed bound, so d(s) >= d(t) - S (s - t) > 0 for s < t + d(t)/S.
//
// Within a step of h the robots' motion is known at its two ends exactly (the
// exact integrator, with velocities and accelerations from eq. 8); in between
// the search uses the quintic Hermite interpolant of x, y and theta on those
// ends, which differs from the exact motion by O(h^6) (under 1e-12 m for
// steps of 1 ms and the default robots; see docs/model.md). The ball's
// motion is evaluated in closed form.
#pragma once

#include <array>
#include <cmath>

#include "vssim/ball.h"
#include "vssim/field.h"
#include "vssim/robot_model.h"
#include "vssim/robot_state.h"

namespace vssim {

// A contact is declared once two bodies are closer than this, m: far below
// anything visible or measurable (a camera pixel is about 2 mm), and large
// enough that the advancement converges in a few dozen iterations.
constexpr double kTouchDistance = 1e-6;
// Bodies within this of each other at the start of a step are touching: a
// contact just answered, or a robot pushing on a wall. The step is an
// ordinary one (its contacts found at its end); a pair that approaches is
// answered first, at that instant, unless it is closer than 1e-10 m
// (long_step_planner.cpp, kRoundingGap: then only at the step's end).
// Whether a step is searched depends on
// the state alone, so the results do not depend on how a run is cut into
// calls. m.
constexpr double kContactSkin = 2.0 * kTouchDistance;
// Bodies within kRestingGap of each other whose nearest points close slower
// than kRestingSpeed rest on each other (a robot pushing the ball or another
// robot): a step is not searched for them (the search would crawl, and find
// a new contact at every step); if they meet by its end, their contact is
// found there, as fixed steps would (and one that only dips in and out within
// the step is not answered, as with fixed steps). A pair that was parting
// faster than kRestingSpeed yet meets by the step's end, or meets deeper than
// kRestingDepthSteps steps of kRestingSpeed, did not rest (a spinning
// robot's corner swept into the other within the step): the step is
// searched for its contact like any other.
constexpr double kRestingGap = 1e-3;        // m
constexpr double kRestingSpeed = 0.05;      // m/s
constexpr double kRestingDepthSteps = 2.0;  // steps of dt: resting bodies, closing under kRestingSpeed, meet shallower
// Iterations of one search, at most: beyond it the search reports how far it
// got safely (a grazing pass that neither touches nor leaves). The planner
// then treats that pair as a resting one: its contact, if any, is found at
// the step's end, and the step's other pairs are still searched.
constexpr int kMaxAdvancements = 256;

// A robot's pose over one step [0, h]: the quintic Hermite interpolant of x, y
// and theta through both ends' values and first and second derivatives.
class RobotPath {
public:
    RobotPath() = default;
    // `start` and `end` are the robot's exact states at 0 and h under the
    // constant voltages e.
    RobotPath(const RobotModel& model, const RobotState& start, const RobotState& end, const Voltages& e, double h);
    RobotState at(double t) const;  // pose at t in [0, h] (v and omega are not interpolated)
    double length() const { return h_; }

private:
    double h_ = 0.0;                            // s
    std::array<std::array<double, 6>, 3> c_{};  // per coordinate x, y, theta: polynomial coefficients in s = t/h
};

// The ball's position t seconds after `start` in free flight (eq. 9 in closed form), m.
Eigen::Vector2d ballPositionAfter(const BallParams& params, const BallState& start, double t);

// Conservative advancement on a gap function over [from, to]: `gap(t)` is the
// separation (m) at t, `closing` (m/s) a bound on how fast it can shrink.
struct Advancement {
    double t = 0.0;        // s: the first instant found with gap <= kTouchDistance, or how far it is safe
    bool touched = false;  // the gap closed at t
    bool finished = false;  // no contact before `to` (t == to)
    int iterations = 0;
};
template <class Gap>
Advancement advanceConservatively(const Gap& gap, double closing, double from, double to) {
    Advancement r;
    r.t = from;
    if (std::isnan(closing)) return r;  // nothing proven
    for (; r.iterations < kMaxAdvancements; ++r.iterations) {
        const double d = gap(r.t);
        if (std::isnan(d)) return r;
        if (d <= kTouchDistance) {
            r.touched = true;
            return r;
        }
        const double next = closing > 0.0 ? r.t + d / closing : INFINITY;
        if (!(next < to)) {  // no contact possible before `to`
            r.t = to;
            r.finished = true;
            return r;
        }
        if (!(next > r.t)) return r;  // below the resolution of t (or an infinite bound): the safe instant
        r.t = next;
    }
    return r;  // out of iterations: r.t is safe
}

}  // namespace vssim
