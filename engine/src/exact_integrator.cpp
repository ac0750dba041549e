#include "vssim/exact_integrator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <tuple>

#include "double_pair.h"
#include "vssim/geometry.h"

namespace vssim {

namespace {

// Gauss-Legendre nodes and weights on [0, 1].
constexpr std::array<double, kGaussNodes> kNodeOffsets = {
    0.5 - 0.5 * 0.9061798459386639927976269, 0.5 - 0.5 * 0.5384693101056830910363144, 0.5,
    0.5 + 0.5 * 0.5384693101056830910363144, 0.5 + 0.5 * 0.9061798459386639927976269,
};
constexpr std::array<double, kGaussNodes> kNodeWeights = {
    0.5 * 0.2369268850561890875142640, 0.5 * 0.4786286704993664680412915, 0.5 * 0.5688888888888888888888889,
    0.5 * 0.4786286704993664680412915, 0.5 * 0.2369268850561890875142640,
};

constexpr int kMaxPanels = 1 << 20;

static_assert(kGaussNodes == 5, "integrateRobotExact takes the nodes as two pairs and one more");

// Nodes within this angle (rad) of the middle node take their sine and cosine
// from the middle node's by angle addition, with the small angle's by
// series (sinCosNearZero, valid to pi/4): no range reduction for them.
constexpr double kSmallTurn = 0.5;

}  // namespace

namespace {

ExactPanel makePanel(const RobotModel& model, double length, int repeat) {
    ExactPanel p;
    p.length = length;
    p.repeat = repeat;
    // The flows from the panel's start to each node and to its end, from
    // one shared series (a new table is built for every odd step length,
    // such as a contact's instant: in a match, a tenth of the engine's work).
    std::array<double, kGaussNodes + 1> fractions;
    std::copy(kNodeOffsets.begin(), kNodeOffsets.end(), fractions.begin());
    fractions[kGaussNodes] = 1.0;
    std::array<LinearFlow, kGaussNodes + 1> flows;
    linearFlowsAlong(model.A, length, fractions.data(), kGaussNodes + 1, flows.data());
    p.flow = flows[kGaussNodes];
    for (int i = 0; i < kGaussNodes; ++i) {
        const LinearFlow& node = flows[i];  // from the panel's start
        p.weights[i] = kNodeWeights[i] * length;
        p.speedFromV[i] = node.Phi(0, 0);
        p.speedFromW[i] = node.Phi(0, 1);
        p.headingFromV[i] = node.Psi(1, 0);
        p.headingFromW[i] = node.Psi(1, 1);
        p.speedFromG0[i] = node.Psi(0, 0);
        p.speedFromG1[i] = node.Psi(0, 1);
        p.headingFromG0[i] = node.Omega(1, 0);
        p.headingFromG1[i] = node.Omega(1, 1);
    }
    return p;
}

}  // namespace

ExactStepTable makeExactStepTable(const RobotModel& model, double h, int panels) {
    ExactStepTable t;
    t.h = h;
    t.panels = std::max(1, panels);
    const double even = h / t.panels;  // s, the heading criterion's panel
    double start = 0.0;                // s, where the equal panels begin
    if (model.fastestRate * even > kPanelDecay) {
        // Graded panels over the fast transient: each one twice as long.
        double length = kPanelDecay / model.fastestRate;
        while (length < even && start + length < h) {
            t.kinds.push_back(makePanel(model, length, 1));
            start += length;
            length *= 2.0;
        }
    }
    const double rest = h - start;
    const int count = std::max(1, static_cast<int>(std::ceil(rest / even - 1e-9)));
    t.kinds.push_back(makePanel(model, rest / count, count));
    return t;
}

int exactPanelsFor(const RobotModel& model, const RobotState& state, const Voltages& e, double h) {
    const double yawRate = yawRateBound(model, state, e);  // rad/s, over the whole step
    const double need = yawRate * h / kPanelTurn;
    // Also NaN or infinite (a state already broken: no number of panels
    // makes it accurate, and the most would only stall the run).
    if (!(need > 1.0) || !std::isfinite(need)) return 1;
    return static_cast<int>(std::min<double>(kMaxPanels, std::ceil(need)));
}

namespace {

// Whether a table is the one for (h, panels): the same bits of h (a NaN
// length matches nothing, so it is never reused, as before any caching).
bool tableIs(const ExactStepTable& t, double h, int panels) { return t.h == h && t.panels == panels; }

std::size_t slotOf(double h, int panels, std::size_t slots) {
    std::uint64_t bits;
    std::memcpy(&bits, &h, sizeof bits);
    bits ^= static_cast<std::uint64_t>(static_cast<std::uint32_t>(panels)) * 0x9E3779B97F4A7C15ull;
    bits ^= bits >> 29;
    bits *= 0xBF58476D1CE4E5B9ull;  // a splitmix64 finaliser step: spreads the mantissa over the slot bits
    bits ^= bits >> 32;
    return static_cast<std::size_t>(bits) & (slots - 1);
}

}  // namespace

const ExactStepTable& ExactTableCache::lookUp(int robot, const RobotModel& model, double h, int panels) {
    panels = std::max(1, panels);  // as makeExactStepTable reads it
    if (h == 0.0) h = 0.0;         // -0 as +0: one key, one slot
    if (robot >= static_cast<int>(robots_.size())) robots_.resize(robot + 1);
    RobotEntry& entry = robots_[robot];
    if (entry.dynamics < 0 || !sameA(dynamics_[entry.dynamics].A, model.A)) {
        entry.dynamics = -1;
        entry.last = -1;
        for (std::size_t d = 0; d < dynamics_.size() && entry.dynamics < 0; ++d)
            if (sameA(dynamics_[d].A, model.A)) entry.dynamics = static_cast<int>(d);
        if (entry.dynamics < 0) {
            Dynamics fresh;
            fresh.A = model.A;
            fresh.index.assign(kSlots, -1);
            dynamics_.push_back(std::move(fresh));
            entry.dynamics = static_cast<int>(dynamics_.size()) - 1;
        }
    }
    Dynamics& mine = dynamics_[entry.dynamics];
    std::size_t slot = slotOf(h, panels, kSlots);
    for (; mine.index[slot] >= 0; slot = (slot + 1) & (kSlots - 1))  // linear probing; never full (kSlots > kMaxPerModel)
        if (tableIs(mine.built[mine.index[slot]], h, panels)) return mine.built[entry.last = mine.index[slot]];
    if (mine.built.size() >= kMaxPerModel) {
        mine.built.clear();
        std::fill(mine.index.begin(), mine.index.end(), -1);
        for (RobotEntry& r : robots_)  // their last tables are gone
            if (r.dynamics == entry.dynamics) r.last = -1;
        slot = slotOf(h, panels, kSlots);
    }
    mine.built.push_back(makeExactStepTable(model, h, panels));
    mine.index[slot] = entry.last = static_cast<int>(mine.built.size()) - 1;
    return mine.built.back();
}

void integrateRobotExact(const RobotModel& model, const ExactStepTable& table, RobotState& state, const Voltages& e) {
    const Eigen::Vector2d g = model.G * Eigen::Vector2d(e.right, e.left);  // u' = A u + g
    Eigen::Vector2d u(state.v, state.omega);
    double x = state.x, y = state.y, theta = state.theta;
    for (const ExactPanel& panel : table.kinds) {
        // The input's share of each node's flow is the same on every panel of a kind.
        // (The outer nodes two at a time, in the pairs they are read in
        // below: a pair read back from two separate stores would stall.)
        constexpr int mid = kGaussNodes / 2;
        std::array<double, kGaussNodes> nodeSpeedInput, nodeTurnInput;
        const Pair G0 = {g(0), g(0)}, G1 = {g(1), g(1)};
        for (const int i : {0, mid + 1}) {
            storePair(&nodeSpeedInput[i], loadPair(&panel.speedFromG0[i]) * G0 + loadPair(&panel.speedFromG1[i]) * G1);
            storePair(&nodeTurnInput[i],
                      loadPair(&panel.headingFromG0[i]) * G0 + loadPair(&panel.headingFromG1[i]) * G1);
        }
        nodeSpeedInput[mid] = panel.speedFromG0[mid] * g(0) + panel.speedFromG1[mid] * g(1);
        nodeTurnInput[mid] = panel.headingFromG0[mid] * g(0) + panel.headingFromG1[mid] * g(1);
        const Eigen::Vector2d panelVelocityInput = panel.flow.Psi * g;
        const double panelTurnInput = panel.flow.Omega.row(1).dot(g);
        for (int p = 0; p < panel.repeat; ++p) {
            const double v0 = u(0), w0 = u(1);
            // Each node's speed and heading; the outer nodes two at a time
            // (0 and 1, 3 and 4), the same operations in the same order as
            // one at a time.
            std::array<double, kGaussNodes> v, heading;
            const Pair V0 = {v0, v0}, W0 = {w0, w0};
            for (const int i : {0, mid + 1}) {
                storePair(&v[i], (loadPair(&panel.speedFromV[i]) * V0 + loadPair(&panel.speedFromW[i]) * W0) +
                                     loadPair(&nodeSpeedInput[i]));
                storePair(&heading[i],
                          (theta + (loadPair(&panel.headingFromV[i]) * V0 + loadPair(&panel.headingFromW[i]) * W0)) +
                              loadPair(&nodeTurnInput[i]));
            }
            v[mid] = (panel.speedFromV[mid] * v0 + panel.speedFromW[mid] * w0) + nodeSpeedInput[mid];
            heading[mid] = (theta + (panel.headingFromV[mid] * v0 + panel.headingFromW[mid] * w0)) + nodeTurnInput[mid];
            const CosSin midRotation = cosSin(heading[mid]);
            const double midCos = midRotation.c, midSin = midRotation.s;
            // The quadrature's terms w v cos(heading) and w v sin(heading),
            // with the nodes' cosine and sine from the middle node's by angle
            // addition, the small angle's by series (sinCosNearZero), or,
            // beyond kSmallTurn, their own.
            std::array<double, kGaussNodes> alongX, alongY;
            alongX[mid] = panel.weights[mid] * v[mid] * midCos;
            alongY[mid] = panel.weights[mid] * v[mid] * midSin;
            const Pair turnLow = loadPair(&heading[0]) - heading[mid],
                       turnHigh = loadPair(&heading[mid + 1]) - heading[mid];
            const Pair qLow = turnLow * turnLow, qHigh = turnHigh * turnHigh;
            if (qLow[0] <= 0.04 && qLow[1] <= 0.04 && qHigh[0] <= 0.04 && qHigh[1] <= 0.04) {
                // Most panels: every turn within 0.2 rad, one short series for all.
                for (const auto& [i, turn, q] : {std::tuple{0, turnLow, qLow}, std::tuple{mid + 1, turnHigh, qHigh}}) {
                    Pair s, c;
                    sinCosSmall(turn, q, s, c);
                    const Pair weighted = loadPair(&panel.weights[i]) * loadPair(&v[i]);
                    storePair(&alongX[i], weighted * (midCos * c - midSin * s));
                    storePair(&alongY[i], weighted * (midSin * c + midCos * s));
                }
            } else {
                for (int i = 0; i < kGaussNodes; ++i) {
                    if (i == mid) continue;
                    const double turn = heading[i] - heading[mid];  // rad
                    double cosine, sine;
                    if (std::abs(turn) <= kSmallTurn) {
                        double s, c;
                        sinCosNearZero(turn, s, c);
                        cosine = midCos * c - midSin * s;
                        sine = midSin * c + midCos * s;
                    } else {
                        const CosSin h = cosSin(heading[i]);
                        cosine = h.c, sine = h.s;
                    }
                    alongX[i] = panel.weights[i] * v[i] * cosine;
                    alongY[i] = panel.weights[i] * v[i] * sine;
                }
            }
            // Summed in node order.
            double dx = 0.0, dy = 0.0;
            for (int i = 0; i < kGaussNodes; ++i) {
                dx += alongX[i];
                dy += alongY[i];
            }
            x += dx;
            y += dy;
            theta += panel.flow.Psi.row(1).dot(u) + panelTurnInput;
            u = panel.flow.Phi * u + panelVelocityInput;
        }
    }
    state.x = x;
    state.y = y;
    state.theta = theta;
    state.v = u(0);
    state.omega = u(1);
}

void integrateBallExact(const BallParams& params, BallState& state, double h) {
    const double k = params.friction / params.mass;  // 1/s
    // (1 - e^(-k h)) / k without cancellation; h when there is no friction.
    const double travelTime = k > 0.0 ? -std::expm1(-k * h) / k : h;  // s
    const double decay = std::exp(-k * h);
    state.x += state.vx * travelTime;
    state.y += state.vy * travelTime;
    state.vx *= decay;
    state.vy *= decay;
}

}  // namespace vssim
