// The "exact" integrator (model.md §2, §7): the velocity part of eq. 8 is
// linear with constant input between voltage changes, so (v, w) and the
// heading theta are advanced by their closed form (linear_flow.h) for any
// step, and only the position x' = v cos(theta), y' = v sin(theta) is a
// quadrature: 5-point Gauss-Legendre (order 10) on panels short enough that
// the heading turns at most kPanelTurn and the fastest velocity mode decays
// by at most e^-kPanelDecay across one panel. The step is unconditionally
// stable and its error does not grow with the step length the way Euler's or
// RK4's does; see docs/model.md and docs/performance.md.
//
// Alternatives rejected: a Magnus/Lie-group rule for the pose (no better
// accuracy per cost here, since theta(t) is known in closed form), and
// adaptive Runge-Kutta (its error control is a tolerance, not the exact
// solution, and it costs many more evaluations per 30 ms interval).
#pragma once

#include <algorithm>
#include <array>
#include <cstring>
#include <utility>
#include <vector>

#include "vssim/ball.h"
#include "vssim/linear_flow.h"
#include "vssim/robot_model.h"
#include "vssim/robot_state.h"

namespace vssim {

constexpr int kGaussNodes = 5;
constexpr double kPanelTurn = 1.0;   // rad: the most the heading may turn in one panel
constexpr double kPanelDecay = 1.0;  // the most |lambda| h_panel may be (fastest mode)

// One kind of panel: its length, its flow, and what the quadrature reads of
// the flows from the panel's start to each of its nodes: their rows, node
// by node (so that the exact step can take two nodes at a time). At node i,
// v = speedFromV[i] v0 + speedFromW[i] w0 + speedFromG0[i] g0 + speedFromG1[i] g1
// (Phi's and Psi's first rows; g = G e), and the heading has turned by
// headingFromV[i] v0 + headingFromW[i] w0 + headingFromG0[i] g0 + headingFromG1[i] g1
// (Psi's and Omega's second rows).
struct ExactPanel {
    double length = 0.0;                        // s
    int repeat = 1;                             // how many such panels follow each other
    LinearFlow flow;                            // flow over the whole panel
    std::array<double, kGaussNodes> weights{};  // quadrature weights times the length, s
    std::array<double, kGaussNodes> speedFromV{}, speedFromW{}, headingFromV{}, headingFromW{};  // (units: linear_flow.h)
    std::array<double, kGaussNodes> speedFromG0{}, speedFromG1{}, headingFromG0{}, headingFromG1{};
};

// Everything the exact step of one robot needs for a step of h seconds;
// depends only on the robot's model, h and the panel count, so it is
// computed once and reused. The panels: `panels` equal ones (the heading
// criterion), except that when the fastest mode would decay by more than
// e^-kPanelDecay across one, the step starts with panels of 1, 2, 4, ...
// times kPanelDecay/|lambda| (a stiff motor's transient) until they are as
// long as the equal ones, then goes on with equal ones. Every mode's panels
// then stay short while it is still large.
struct ExactStepTable {
    double h = 0.0;                 // whole step, s
    int panels = 1;                 // panels asked for (the heading criterion)
    std::vector<ExactPanel> kinds;  // in order
};

ExactStepTable makeExactStepTable(const RobotModel& model, double h, int panels);

// Panels needed for a step of h from `state` under voltages e: enough that
// the heading turns (velocityBound) at most kPanelTurn in one. (The fastest
// mode is handled by the table's graded first panels.)
int exactPanelsFor(const RobotModel& model, const RobotState& state, const Voltages& e, double h);

// Tables already built, keyed by (step length, panels), one set per robot
// dynamics: a table depends on nothing but its key and the model's velocity
// matrix A (makeExactStepTable), so robots of bit-identical A (a team of
// the same robot: every robot of a default scene) share theirs. A cache
// only: the results are the same whether a table is reused or rebuilt.
// A lookup is a hash probe (a step of any length, such as the instant of a
// contact, gets its own key), after a check of the key the same robot asked
// for last, which is what it asks for again in most steps (its panel count
// changes seldom), inline.
class ExactTableCache {
public:
    // The table stays valid until the next call.
    const ExactStepTable& table(int robot, const RobotModel& model, double h, int panels) {
        if (robot >= 0 && static_cast<std::size_t>(robot) < robots_.size()) {
            const RobotEntry& r = robots_[robot];
            // (The A check, four compares, on every call: a robot whose model
            // were replaced could never be handed another model's tables.)
            if (r.last >= 0 && sameA(dynamics_[r.dynamics].A, model.A)) {
                const ExactStepTable& t = dynamics_[r.dynamics].built[r.last];
                if (t.h == h && t.panels == std::max(1, panels)) return t;
            }
        }
        return lookUp(robot, model, h, panels);
    }

private:
    const ExactStepTable& lookUp(int robot, const RobotModel& model, double h, int panels);
    // Whether two velocity matrices are the same bits: a matrix with a NaN is
    // then the same as itself, so it gets one set of tables, not one per call.
    static bool sameA(const Eigen::Matrix2d& a, const Eigen::Matrix2d& b) {
        return std::memcmp(a.data(), b.data(), 4 * sizeof(double)) == 0;
    }
    // A scene of many step lengths must not grow it forever (a table is
    // about 1 to 3 kB): when full, a model's tables are dropped and rebuilt
    // as they are asked for again.
    static constexpr std::size_t kMaxPerModel = 1024;
    static constexpr std::size_t kSlots = 4 * kMaxPerModel;  // a power of two: probes stay short
    struct Dynamics {
        Eigen::Matrix2d A;                  // the model's velocity matrix, the tables' only input besides the key
        std::vector<ExactStepTable> built;  // at most kMaxPerModel (may move when one is added)
        std::vector<int> index;             // kSlots entries: an index into built, or -1
    };
    struct RobotEntry {
        int dynamics = -1;  // index into dynamics_, -1 before the robot's first table
        int last = -1;      // index into that one's built: the table the robot asked for last, or -1
    };
    std::vector<RobotEntry> robots_;
    std::vector<Dynamics> dynamics_;  // distinct A matrices, in order of first use
};

// Advances one robot by table.h under constant (already clamped) voltages.
void integrateRobotExact(const RobotModel& model, const ExactStepTable& table, RobotState& state, const Voltages& e);

// The ball's eq. 9 solved exactly: v(h) = v0 e^(-k h), x(h) = x0 + v0 (1 - e^(-k h)) / k,
// k = beta_b / m_b.
void integrateBallExact(const BallParams& params, BallState& state, double h);

}  // namespace vssim
