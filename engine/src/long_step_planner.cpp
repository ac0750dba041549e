// The long-step planner of Simulation::advanceTo (world.h): each stretch
// between voltage changes is cut short only where contacts are possible;
// bodies that cannot touch anything (free_bodies.h) take the stretch in one
// exact step while the others take steps of dt.
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "vssim/collision_response.h"
#include "vssim/geometry.h"
#include "vssim/nearly_sorted.h"
#include "vssim/time_of_impact.h"
#include "vssim/world.h"

namespace vssim {

namespace {

// After a failed try at a long step for the bodies near contacts, this many
// steps of dt pass before the next try (a try costs about one step),
// doubling after each failure in a row up to the longest wait.
constexpr std::int64_t kFirstRetryWait = 2;
constexpr std::int64_t kLongestRetryWait = 16;

// The search within a step runs on interpolated paths (time_of_impact.h),
// whose points can move faster than the exact motion's bound by the
// interpolation's error, O(h^5) relative; this slack covers it many times over.
constexpr double kPathSpeedSlack = 1.0 + 1e-6;

// Bodies closer than this at a step's start are usually where a contact on
// the grid left them, separated to touching give or take rounding: whether they
// count as apart (a gap of a few 1e-17 m) or as overlapping (exactly 0), and
// the normal between their nearest points, are then rounding, which differs
// with where a call to advanceTo ended. So they are not answered as
// touching at the step's start; the step's contact passes find them at its
// end, as on the grid. (A contact that a search finds is answered at its
// instant, in impactStep, however small its gap.)
constexpr double kRoundingGap = 1e-10;  // m

// A body's pose among the given robots and ball (the ball's centre in x, y;
// a wall's pose is not used).
RobotState poseAmong(const BodyRef& body, const std::vector<RobotState>& robots, const BallState& ball) {
    if (body.kind == BodyKind::Robot) return robots[body.index];
    return body.kind == BodyKind::Ball ? ballPose(ball) : RobotState{};
}

}  // namespace

double Simulation::bodyReach(std::size_t b) const {
    return b < state_.robots.size() ? boundingRadius(model_.sides[b]) : model_.ball.radius;
}

Eigen::Vector2d Simulation::bodyCentre(std::size_t b) const {
    return b < state_.robots.size() ? Eigen::Vector2d(state_.robots[b].x, state_.robots[b].y)
                                    : Eigen::Vector2d(state_.ball.x, state_.ball.y);
}

double Simulation::bodySpeed(std::size_t b) const {
    return b < state_.robots.size() ? pointSpeedBound(model_.robots[b], state_.robots[b], state_.voltages[b])
                                    : std::hypot(state_.ball.vx, state_.ball.vy);
}

double Simulation::bodyTravel(std::size_t b, double horizon) const {
    return b < state_.robots.size() ? robotTravelForIntegrator(model_, state_, b, horizon, progress_)
                                    : ballTravelForIntegrator(model_, state_, horizon);
}

std::int64_t Simulation::contactFreeSteps(std::int64_t wanted) const {
    // The largest k <= wanted for which every body is free for k steps
    // (freedom only shrinks as the horizon grows): a bisection.
    FreeBodies free;
    auto allFree = [&](std::int64_t k) {
        findFreeBodies(model_, state_, static_cast<double>(k) * model_.settings.dt, free);
        return free.all;
    };
    if (wanted <= 0 || !allFree(1)) return 0;
    if (allFree(wanted)) return wanted;
    std::int64_t lo = 1, hi = wanted;  // allFree(lo), !allFree(hi)
    while (hi - lo > 1) {
        const std::int64_t mid = lo + (hi - lo) / 2;
        (allFree(mid) ? lo : hi) = mid;
    }
    return lo;
}

bool Simulation::frozenStillSafe(const FrozenStart& start, double remaining, double margin) const {
    // A frozen body i, still at its start p_i0, moves at most travel_i in the
    // whole stretch. A stepping body j, now at p_j with its current state (a
    // collision may have sped it up), moves at most its travel bound over
    // the remaining time. Both discs must stay apart.
    const std::size_t n = state_.robots.size();
    if (start.byX.empty() && claims_.empty()) return true;  // nobody frozen, no other group
    auto stillApart = [&](std::size_t j) {
        const Eigen::Vector2d pj = bodyCentre(j);
        const double pjX = pj.x(), pjY = pj.y();
        const double jTravel = bodyTravel(j, remaining) + 2.0 * bodySpeed(j) * margin;
        // Only frozen bodies within the widest reach along x can be too close
        // (start.byX: the frozen bodies by their x; NaN fails below).
        const double window = bodyReach(j) + jTravel + start.widest;  // m
        if (!(window < INFINITY) || std::isnan(pjX)) return false;
        auto k = std::lower_bound(start.byX.begin(), start.byX.end(), pjX - window,
                                  [&start](int i, double x) { return start.x[i] < x; });
        for (; k != start.byX.end() && start.x[*k] <= pjX + window; ++k) {
            const std::size_t i = static_cast<std::size_t>(*k);
            const double dx = pjX - start.x[i], dy = pjY - start.y[i];
            const double distance = std::sqrt(dx * dx + dy * dy);
            if (!(distance - bodyReach(i) - bodyReach(j) > start.travel[i] + jTravel)) return false;
        }
        return claims_.empty() || clearOfOtherGroups(pjX, pjY, bodyReach(j) + jTravel);
    };
    for (const int j : stepping_)
        if (!stillApart(std::size_t(j))) return false;
    return start.frozen[n] != kStepping || stillApart(n);
}

bool Simulation::clearOfOtherGroups(double x, double y, double reach) const {
    // claims_ is sorted by each claim's x at the stretch's start (`key`);
    // a claim's disc now lies within claimsWidest_ of that along x.
    const double window = reach + claimsWidest_;  // m
    auto k = std::lower_bound(claims_.begin(), claims_.end(), x - window,
                              [](const Claim& c, double v) { return c.key < v; });
    for (; k != claims_.end() && k->key <= x + window; ++k)
        if (k->group != currentGroup_ && !(std::hypot(x - k->x, y - k->y) - k->reach > reach))  // (NaN: not clear)
            return false;
    return true;
}

namespace {

// A disc (centre x, y and radius r, m) that holds both given discs: the
// smallest such, grown by a picometre against rounding.
void encloseDisc(double& x, double& y, double& r, double x2, double y2, double r2) {
    const double d = std::hypot(x2 - x, y2 - y);
    if (d + r2 <= r) return;  // the second is inside the first
    if (d + r <= r2) {
        x = x2, y = y2, r = r2;
        return;
    }
    const double enclosing = 0.5 * (d + r + r2);
    const double shift = (enclosing - r) / d;  // (d > 0 here: equal centres fall in a case above)
    x += (x2 - x) * shift;
    y += (y2 - y) * shift;
    r = enclosing + 1e-12;
}

}  // namespace

bool Simulation::apartAfterContact(const FrozenStart& start, double remaining, double margin) {
    if (!frozenStillSafe(start, remaining, margin)) return false;
    if (currentGroup_ < 0) return true;
    // The contact may have changed the group's velocities: its bodies are
    // now bounded by discs around where they are (those of frozenStillSafe,
    // which the other groups were just checked against), which the groups
    // after this one must keep clear of as well. And a body sped up to need
    // sub-steps would make the steps differ from the whole world's.
    // (Each body keeps one claim, grown to hold the new disc as well: the
    // checks then cost the same however many contacts a stretch has.)
    const std::size_t n = state_.robots.size();
    auto slow = [&](std::size_t j) { return bodySpeed(j) <= groupSpeedLimit_; };
    if (!std::all_of(stepping_.begin(), stepping_.end(), [&](int j) { return slow(std::size_t(j)); }) ||
        (start.frozen[n] == kStepping && !slow(n)))
        return false;
    auto claim = [&](std::size_t j) {
        Claim& c = claims_[claimOf_[j]];
        const Eigen::Vector2d now = bodyCentre(j);
        encloseDisc(c.x, c.y, c.reach, now.x(), now.y(),
                    bodyReach(j) + bodyTravel(j, remaining) + 2.0 * bodySpeed(j) * margin);
        claimsWidest_ = std::max(claimsWidest_, std::abs(c.x - c.key) + c.reach);  // (NaN: checks fail)
    };
    for (const int j : stepping_) claim(std::size_t(j));
    if (start.frozen[n] == kStepping) claim(n);
    return true;
}

int Simulation::formGroups(const FrozenStart& start, double smallest) {
    const std::size_t n = state_.robots.size();
    const double dt = model_.settings.dt;
    groupSpeedLimit_ = kMaxTravelFraction * smallest / dt;  // m/s (world.h: sub-steps)
    if (!(start.fastest <= groupSpeedLimit_)) return 0;
    // Each stepping body's disc (start.travel: its travel over the stretch,
    // from findFreeBodies), with the margin of freezeUnconstrained; by x.
    stepReach_.resize(n + 1);
    steppingByX_.clear();
    claims_.clear();
    double widest = 0.0;  // m
    auto disc = [&](std::size_t j) {
        const double speed = bodySpeed(j), travel = start.travel[j];
        const Eigen::Vector2d c = bodyCentre(j);
        if (!(speed <= groupSpeedLimit_) || !std::isfinite(travel) || !c.allFinite()) return false;
        stepReach_[j] = bodyReach(j) + travel + 2.0 * speed * dt;
        widest = std::max(widest, stepReach_[j]);
        steppingByX_.emplace_back(c.x(), int(j));
        claims_.push_back({c.x(), c.x(), c.y(), bodyReach(j) + travel, int(j), -1});
        return true;
    };
    // (By x already: bodiesByX_ was sorted at this stretch's start, and
    // nothing has moved since. So are the claims.)
    for (const auto& [x, b] : bodiesByX_)
        if (start.frozen[std::size_t(b)] == kStepping && !disc(std::size_t(b))) return 0;
    const std::size_t m = steppingByX_.size();
    if (m < 2) return 0;
    // Overlapping discs join (a union-find whose roots are each set's lowest
    // body index): a sweep along x.
    groupRoot_.resize(n + 1);
    for (const auto& entry : steppingByX_) groupRoot_[entry.second] = entry.second;
    auto root = [this](int b) {
        while (groupRoot_[b] != b) b = groupRoot_[b] = groupRoot_[groupRoot_[b]];
        return b;
    };
    for (std::size_t a = 0; a < m; ++a) {
        const int i = steppingByX_[a].second;
        const Eigen::Vector2d ci = bodyCentre(i);
        for (std::size_t b = a + 1; b < m && steppingByX_[b].first - steppingByX_[a].first <= stepReach_[i] + widest;
             ++b) {
            const int j = steppingByX_[b].second;
            if ((ci - bodyCentre(j)).norm() > stepReach_[i] + stepReach_[j]) continue;
            const int ri = root(i), rj = root(j);
            if (ri != rj) groupRoot_[std::max(ri, rj)] = std::min(ri, rj);
        }
    }
    groupOf_.assign(n + 1, -1);
    int groups = 0;
    auto number = [&](std::size_t j) {
        const int r = root(int(j));
        groupOf_[j] = r == int(j) ? groups++ : groupOf_[r];  // (a root comes before its set's other bodies)
    };
    for (const int i : stepping_) number(std::size_t(i));
    if (start.frozen[n] == kStepping) number(n);
    if (groups < 2) {
        claims_.clear();
        return 0;
    }
    // Each group's robots, increasing (a counting sort by group).
    groupFirst_.assign(std::size_t(groups) + 1, 0);
    for (const int i : stepping_) ++groupFirst_[std::size_t(groupOf_[i]) + 1];
    for (int g = 0; g < groups; ++g) groupFirst_[g + 1] += groupFirst_[g];
    groupMembers_.resize(stepping_.size());
    groupFill_.assign(groupFirst_.begin(), groupFirst_.end() - 1);
    for (const int i : stepping_) groupMembers_[groupFill_[groupOf_[i]]++] = i;
    claimsWidest_ = 0.0;
    for (Claim& c : claims_) {
        c.group = groupOf_[c.body];
        claimsWidest_ = std::max(claimsWidest_, c.reach);
    }
    claimOf_.resize(n + 1);
    for (std::size_t k = 0; k < claims_.size(); ++k) claimOf_[claims_[k].body] = k;
    return groups;
}

void Simulation::keepGroupUndo(FrozenStart& start, bool save) {
    GroupUndo& undo = groupUndo_;
    const auto keep = [save](auto& kept, auto& live) {
        if (save)
            kept = live;
        else
            live = kept;
    };
    keep(undo.stepping, stepping_);  // (first: the list below)
    const std::size_t m = stepping_.size(), n = state_.robots.size();
    if (save) {
        undo.robots.resize(m);
        undo.frozenRobots.resize(m);
        undo.since.resize(m + 1);
        undo.x.resize(m + 1);
        undo.y.resize(m + 1);
        undo.travel.resize(m + 1);
    }
    for (std::size_t k = 0; k <= m; ++k) {  // stepping_'s robots, then the ball
        const std::size_t b = k < m ? std::size_t(stepping_[k]) : n;
        if (k < m) {
            keep(undo.robots[k], state_.robots[b]);
            keep(undo.frozenRobots[k], start.robots[b]);
        }
        keep(undo.since[k], start.since[b]);
        keep(undo.x[k], start.x[b]);
        keep(undo.y[k], start.y[b]);
        keep(undo.travel[k], start.travel[b]);
    }
    keep(undo.ball, state_.ball);
    keep(undo.frozenBall, start.ball);
    keep(undo.frozen, start.frozen);
    keep(undo.byX, start.byX);
    keep(undo.widest, start.widest);
    keep(undo.fastest, start.fastest);
    keep(undo.frozenRobotFlags, frozenRobots_);
}

bool Simulation::stepInGroups(FrozenStart& start, const StretchLoop& loop, StepOptions& options,
                              AdvanceReport& report) {
    const std::size_t n = state_.robots.size();
    const int groups = formGroups(start, loop.smallest);
    if (groups < 2) {
        claims_.clear();  // (frozenStillSafe reads them)
        return false;
    }
    // What an undone stretch goes back to.
    keepGroupUndo(start, true);
    const AdvanceReport reportBefore = report;
    const StepOptions optionsBefore = options;
    // Everybody stands aside, then each group steps in turn (those frozen
    // within the stretch stay so: they catch up at its end).
    auto standAside = [&] {
        for (const int i : stepping_) {
            start.frozen[i] = kOtherGroup;
            frozenRobots_[i] = 1;
        }
        if (start.frozen[n] == kStepping) start.frozen[n] = kOtherGroup;
    };
    standAside();
    bool apart = true;
    for (int g = 0; g < groups && apart; ++g) {
        currentGroup_ = g;
        stepping_.assign(groupMembers_.begin() + groupFirst_[g], groupMembers_.begin() + groupFirst_[g + 1]);
        for (const int i : stepping_) {
            start.frozen[i] = kStepping;
            frozenRobots_[i] = 0;
        }
        if (groupOf_[n] == g) start.frozen[n] = kStepping;
        options.freeBall = start.frozen[n] != kStepping;
        bool unsafe = false;
        stepThroughStretch(start, loop, options, report, unsafe);
        apart = !unsafe;
        standAside();
    }
    stepping_.clear();
    currentGroup_ = -1;
    claims_.clear();
    if (apart) {
        options.freeBall = start.frozen[n] == kFrozen;
        ++report.groupedStretches;
        return true;
    }
    keepGroupUndo(start, false);
    report = reportBefore;
    options = optionsBefore;
    ++report.groupFallbacks;
    return false;
}

void Simulation::frozenSpeeds(const FrozenStart& start, std::int64_t done, StepOptions& options) {
    const std::size_t n = state_.robots.size();
    const double dt = model_.settings.dt;
    frozenSpeed_.assign(n, 0.0);
    options.frozenRobotFastest = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (start.frozen[i] != kFrozen) continue;
        const double elapsed = static_cast<double>(done - start.since[i]) * dt;  // s since it froze
        RobotState now = start.robots[i];
        const Eigen::Vector2d u = velocityAfter(model_.robots[i], now, state_.voltages[i], elapsed);
        now.v = u(0);
        now.omega = u(1);
        frozenSpeed_[i] = pointSpeedBound(model_.robots[i], now, state_.voltages[i]);
        options.frozenRobotFastest = std::max(options.frozenRobotFastest, frozenSpeed_[i]);
    }
    const double ballDecay = model_.ball.friction / model_.ball.mass;  // 1/s
    const double ballElapsed = static_cast<double>(done - start.since[n]) * dt;
    options.frozenBallSpeed = std::hypot(start.ball.vx, start.ball.vy) * std::exp(-ballDecay * ballElapsed);
}

void Simulation::addToFrozenOrder(FrozenStart& start, std::vector<int>& added) const {
    const auto byX = [&start](int a, int b) {
        return start.x[a] < start.x[b] || (start.x[a] == start.x[b] && a < b);
    };
    std::sort(added.begin(), added.end(), byX);
    const std::size_t old = start.byX.size();
    start.byX.insert(start.byX.end(), added.begin(), added.end());
    if (old > 0)  // (a merge with nothing still takes a buffer)
        std::inplace_merge(start.byX.begin(), start.byX.begin() + static_cast<std::ptrdiff_t>(old), start.byX.end(),
                           byX);
    for (const int b : added)
        start.widest = std::max(start.widest, bodyReach(static_cast<std::size_t>(b)) + start.travel[b]);
}

void Simulation::sortBodiesByX() {
    const std::size_t n = state_.robots.size();
    const bool fresh = bodiesByX_.size() != n + 1;
    if (fresh) {
        bodiesByX_.resize(n + 1);
        for (std::size_t b = 0; b <= n; ++b) bodiesByX_[b].second = static_cast<int>(b);
    }
    for (auto& [x, b] : bodiesByX_) {
        x = std::size_t(b) < n ? state_.robots[std::size_t(b)].x : state_.ball.x;
        if (std::isnan(x)) x = INFINITY;  // (a strict order even then: no body is lost or repeated)
    }
    // (pair's order: by x, then by index.)
    if (fresh) {
        std::sort(bodiesByX_.begin(), bodiesByX_.end());
        return;
    }
    sortNearlySorted(bodiesByX_, std::less<std::pair<double, int>>());
}

int Simulation::freezeUnconstrained(FrozenStart& start, std::int64_t done, std::int64_t stretch,
                                     StepOptions& options) {
    const std::size_t n = state_.robots.size();
    const double dt = model_.settings.dt;
    const double remaining = static_cast<double>(stretch - done) * dt;  // s
    // The stepping bodies: robots by index, then the ball (as all loops here).
    steppingBodies_.assign(stepping_.begin(), stepping_.end());
    if (start.frozen[n] == kStepping) steppingBodies_.push_back(int(n));
    if (std::all_of(steppingBodies_.begin(), steppingBodies_.end(), [this](int b) { return constrained_[b] != 0; }))
        return 0;  // no candidate
    // Each stepping body's reach plus travel (with the margin), once, and
    // the stepping bodies by x: a candidate looks only at those within the
    // widest such reach along x (a thousand robots would otherwise cost a
    // million pairs a round).
    stepReach_.resize(n + 1);
    steppingByX_.clear();
    double widest = 0.0;  // m
    for (const int body : steppingBodies_) {
        const std::size_t j = std::size_t(body);
        if (std::isnan(bodyCentre(j).x())) return 0;  // (nothing to sort by; such a world is not planned on)
        stepReach_[j] = bodyReach(j) + bodyTravel(j, remaining) + 2.0 * bodySpeed(j) * dt;
        widest = std::max(widest, stepReach_[j]);
        steppingByX_.emplace_back(bodyCentre(j).x(), static_cast<int>(j));
    }
    std::sort(steppingByX_.begin(), steppingByX_.end());
    int frozen = 0;
    newlyFrozen_.clear();
    for (const int body : steppingBodies_) {
        const std::size_t b = std::size_t(body);
        if (constrained_[b]) continue;
        // The discs of frozenStillSafe, with its margin of a step: a body
        // within reach of a stepping one stays stepping (a contact of that
        // one would undo the step and plan again with everybody).
        const double bTravel = bodyTravel(b, remaining);
        const Eigen::Vector2d c = bodyCentre(b);
        const double window = bodyReach(b) + bTravel + widest;  // m
        bool clear = std::isfinite(bTravel) && std::isfinite(window) && !std::isnan(c.x());
        auto k = std::lower_bound(steppingByX_.begin(), steppingByX_.end(), std::make_pair(c.x() - window, -1));
        for (; clear && k != steppingByX_.end() && k->first <= c.x() + window; ++k) {
            const std::size_t j = static_cast<std::size_t>(k->second);
            if (j == b || start.frozen[j]) continue;  // (frozen: earlier in this pass)
            clear = (c - bodyCentre(j)).norm() - bodyReach(b) > bTravel + stepReach_[j];
        }
        if (!clear) continue;
        start.frozen[b] = kFrozen;
        newlyFrozen_.push_back(static_cast<int>(b));
        start.since[b] = done;
        start.x[b] = bodyCentre(b).x();
        start.y[b] = bodyCentre(b).y();
        start.travel[b] = bTravel;
        start.fastest = std::max(start.fastest, bodySpeed(b));
        if (b < n) {
            start.robots[b] = state_.robots[b];
            frozenRobots_[b] = 1;
        } else {
            start.ball = state_.ball;
            options.freeBall = true;
        }
        ++frozen;
    }
    if (frozen == 0) return 0;
    stepping_.erase(
        std::remove_if(stepping_.begin(), stepping_.end(), [&start](int i) { return start.frozen[i] != 0; }),
        stepping_.end());
    addToFrozenOrder(start, newlyFrozen_);
    // Their gaps are no longer searched (impactStep reads the stepping bodies' starts only).
    gaps_.erase(std::remove_if(gaps_.begin(), gaps_.end(),
                               [&start, n](const BodyGap& g) {
                                   for (const BodyRef& body : {g.a, g.b}) {
                                       if (body.kind == BodyKind::Robot && start.frozen[body.index]) return true;
                                       if (body.kind == BodyKind::Ball && start.frozen[n]) return true;
                                   }
                                   return false;
                               }),
                gaps_.end());
    return frozen;
}

void Simulation::catchUpFrozen(const FrozenStart& start, std::int64_t done, bool ballFrozen) {
    const std::size_t n = state_.robots.size();
    const double dt = model_.settings.dt;
    // Those frozen at the stretch's start together (as ever, even for no
    // time), then each of those frozen later from its own step.
    catchUp_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) catchUp_[i] = start.frozen[i] == kFrozen && start.since[i] == 0;
    advanceBodies(static_cast<double>(done) * dt, &catchUp_, ballFrozen && start.since[n] == 0);
    if (ballFrozen && start.since[n] > 0 && done > start.since[n])
        advanceBody(n, static_cast<double>(done - start.since[n]) * dt);
    for (std::size_t i = 0; i < n; ++i)
        if (start.frozen[i] == kFrozen && start.since[i] > 0 && done > start.since[i])
            advanceBody(i, static_cast<double>(done - start.since[i]) * dt);
}

std::int64_t Simulation::steppingFreeSteps(const FrozenStart& start, std::int64_t remaining) {
    const std::size_t n = state_.robots.size();
    std::int64_t steps = 1;
    while (steps * 2 <= remaining) steps *= 2;
    for (; steps >= 2; steps /= 4) {
        const double horizon = static_cast<double>(steps) * model_.settings.dt;
        // Free among themselves and from the walls (the frozen bodies are
        // checked properly below: they are not where findFreeBodies sees them)...
        findFreeBodies(model_, state_, horizon, free_);
        bool allFree = start.frozen[n] || free_.ball;
        for (std::size_t i = 0; i < n && allFree; ++i) allFree = start.frozen[i] || free_.robots[i];
        // ...and out of the frozen bodies' reach.
        if (allFree && frozenStillSafe(start, horizon)) return steps;
    }
    return 0;
}

void Simulation::saveStepping(bool ballMoving) {
    stepStartRobots_.resize(state_.robots.size());
    for (const int i : stepping_) stepStartRobots_[i] = state_.robots[i];
    if (ballMoving) stepStartBall_ = state_.ball;
}

void Simulation::restoreStepping(bool ballMoving) {
    for (const int i : stepping_) state_.robots[i] = stepStartRobots_[i];
    if (ballMoving) state_.ball = stepStartBall_;
}

RobotState Simulation::poseNow(const BodyRef& body) const { return poseAmong(body, state_.robots, state_.ball); }

std::optional<Contact> Simulation::touchingContact(const BodyGap& g) const {
    const Separation s = separationBetween(model_, g.a, poseNow(g.a), g.b, poseNow(g.b));
    // (An overlap is left to a step's contact passes, which describe overlaps.)
    if (s.overlapping || s.distance > kContactSkin) return std::nullopt;
    Contact c;
    c.a = g.a;
    c.b = g.b;
    c.normal = s.normal;
    c.point = s.point;
    return c;
}

std::int64_t Simulation::gapSafeSteps(std::int64_t remaining, bool ballMoving, bool known) {
    const double dt = model_.settings.dt;
    const double horizon = static_cast<double>(remaining) * dt;  // s
    if (known)
        remeasureBodyGaps(model_, state_, horizon, gaps_, gapScratch_);
    else
        findBodyGaps(model_, state_, stepping_, ballMoving, horizon, gaps_, gapScratch_);
    const std::size_t n = state_.robots.size();
    constrained_.resize(n + 1);  // (read for the stepping bodies only)
    for (const int i : stepping_) constrained_[i] = 0;
    constrained_[n] = 0;
    std::int64_t steps = remaining;
    for (const BodyGap& g : gaps_) {
        if (!(g.gap > kContactSkin)) return -1;  // touching now (or NaN)
        // Conservative advancement on the grid: no contact within gap / closing.
        const double free = g.gap / (g.closing * dt);  // steps; +inf when nothing closes
        // Steps until the pair may be within kContactSkin (> 0 here): a body
        // with such a gap before the stretch ends stays stepping (frozen, it
        // would not be looked at where a call cut there looks afresh)...
        const double untilSkin = (g.gap - kContactSkin) / (g.closing * dt);
        if (!(untilSkin >= static_cast<double>(remaining)))
            for (const BodyRef& body : {g.a, g.b})
                if (body.kind != BodyKind::Wall) constrained_[body.kind == BodyKind::Robot ? body.index : n] = 1;
        if (!(free >= static_cast<double>(steps))) steps = free >= 0.0 ? static_cast<std::int64_t>(free) : 0;
        // ...and the long step ends at the first step start at which it may
        // be touching, which is looked at as one that begins a call would be.
        if (untilSkin < static_cast<double>(steps)) steps = static_cast<std::int64_t>(std::ceil(untilSkin));
    }
    // A gap that cannot come within kContactSkin (where a pair counts as
    // touching, above) before the stretch ends now cannot later either (its
    // bounds hold over all that is left of the stretch, under these
    // voltages), unless a contact changes the bodies' velocities: it is
    // measured no more (world.h). The others stay, in order.
    gaps_.erase(std::remove_if(gaps_.begin(), gaps_.end(),
                               [&](const BodyGap& g) {
                                   return (g.gap - kContactSkin) / (g.closing * dt) >= static_cast<double>(remaining);
                               }),
                gaps_.end());
    return steps;
}

Simulation::ImpactStep Simulation::impactStep(bool ballMoving, double stepStart, const StepOptions& options,
                                              AdvanceReport& report) {
    const double dt = model_.settings.dt;
    const std::size_t n = state_.robots.size();
    saveStepping(ballMoving);
    advanceListed(dt, stepping_, ballMoving);  // the exact end of the step, no contacts yet
    // The first instant within the step at which a gap closes, on the paths
    // between the step's two exact ends.
    paths_.resize(n);
    pathReady_.resize(n);
    for (const int i : stepping_) pathReady_[i] = 0;
    auto poseAt = [this](const BodyRef& body, double t) {
        if (body.kind == BodyKind::Robot) return paths_[body.index].at(t);
        if (body.kind == BodyKind::Ball) {
            const Eigen::Vector2d c = ballPositionAfter(model_.ball, stepStartBall_, t);
            return ballPose({c.x(), c.y(), 0.0, 0.0});
        }
        return RobotState{};
    };
    // How fast each gap can close within this step: from the bodies' bounds
    // over the step alone (not over the rest of the stretch, which depends on
    // where the call ends: the search must not). Two speeds (body_gaps.h):
    // the point speeds' sum bounds how fast the gap can change from any
    // instant on, which the search below needs, as it measures the gap
    // again at every instant it reaches; the bound along the gap's normal at
    // the step's start holds from the start only, enough to skip a pair that
    // cannot close within the step at all.
    auto boundWithinStep = [&](const BodyRef& body) {
        if (body.kind == BodyKind::Ball) return ballMotionBound(stepStartBall_);
        const int i = body.index;
        return robotMotionBound(model_.robots[i], stepStartRobots_[i], state_.voltages[i], model_.sides[i],
                                progress_.get(model_.robots[i], dt));
    };
    double first = dt;  // s into the step
    bool touched = false;
    bool restingMeet = false;  // a resting pair meets by the step's end: answered there
    bool unsettled = false;    // a grazing pass the search could not settle: answered at the step's end
    bool touchingPair = false; // a pair touching at the step's start: met at its end, as on the grid
    for (BodyGap& g : gaps_) {
        if (!(g.gap > kContactSkin)) {
            touchingPair = true;
            continue;
        }
        const bool wall = g.b.kind == BodyKind::Wall;
        const MotionBound boundA = boundWithinStep(g.a), boundB = wall ? MotionBound{} : boundWithinStep(g.b);
        g.closing = boundA.pointSpeed + boundB.pointSpeed;  // (read again below, once a contact is found)
        const double alongNormal =
            closingSpeed({g.gap, false, g.normal, g.point}, boundA, wall ? nullptr : &boundB, g.closing);
        if (g.gap > alongNormal * dt) continue;  // cannot close within the step
        // Nor when the gaps at both ends are too wide for the step: a contact
        // at s would need gap(0) <= S s and gap(h) <= S (h - s). (Most steps
        // searched are near misses: a robot along a wall, two passing by.)
        const Separation atEnd = separationBetween(model_, g.a, poseNow(g.a), g.b, poseNow(g.b));
        if (g.gap + atEnd.distance > g.closing * kPathSpeedSlack * dt) continue;
        // Nor for bodies resting on each other (a robot pushing the ball or
        // another robot: within kRestingGap, closing slower than
        // kRestingSpeed): searching them would crawl, and find a new contact
        // at every step. If they meet by the step's end, their contact is
        // answered there, as on the grid (the other pairs are still searched:
        // whether one pair's contact is answered at its instant must not
        // depend on which other bodies share the step). Unless they were
        // parting fast, or meet deep, which resting bodies do not (a spinning
        // robot's corner sweeping into the other within the step): then
        // their contact is searched for like any other.
        if (g.gap <= kRestingGap) {
            // (Their nearest points at the step's start are the gap's, from gapSafeSteps.)
            const Bodies atStart{&stepStartRobots_, &model_.robots, &stepStartBall_, &model_.ball};
            const Eigen::Vector2d relative =
                contactPointVelocity(atStart, g.a, g.point) - contactPointVelocity(atStart, g.b, g.point);  // m/s
            const double closing = -relative.dot(g.normal);  // m/s
            if (closing < kRestingSpeed) {
                if (!atEnd.overlapping) continue;
                if (closing > -kRestingSpeed && overlapDepthBetween(model_, g.a, poseNow(g.a), g.b, poseNow(g.b)) <=
                                                    kRestingDepthSteps * kRestingSpeed * dt) {
                    restingMeet = true;
                    continue;
                }
            }
        }
        for (const BodyRef& body : {g.a, g.b}) {
            if (body.kind != BodyKind::Robot || pathReady_[body.index]) continue;
            const int i = body.index;
            paths_[i] = RobotPath(model_.robots[i], stepStartRobots_[i], state_.robots[i], state_.voltages[i], dt);
            pathReady_[i] = 1;
        }
        const auto gapAt = [&](double t) {
            return separationBetween(model_, g.a, poseAt(g.a, t), g.b, poseAt(g.b, t)).distance;
        };
        // Only a contact before the earliest found so far matters.
        const Advancement a = advanceConservatively(gapAt, g.closing * kPathSpeedSlack, 0.0, first);
        if (a.touched) {
            first = a.t;
            touched = true;
        } else if (!a.finished) {
            // A grazing pass the search could not settle (within a few
            // micrometres for much of the step, kMaxAdvancements): like a
            // resting pair, it sends only itself to the step's end, where a
            // contact of its, if any, is found (the other pairs are still
            // searched, so that whether their contacts are answered at their
            // instant does not depend on which bodies share the step). Should
            // another pair's instant come after where this search stopped,
            // the pair may meet before it: then it is found overlapping at
            // the step's end, as on the grid.
            unsettled = true;
        }
    }
    if (!touched) {
        if (!restingMeet && !unsettled && !touchingPair) return ImpactStep::Free;
        // Only resting, unsettled or touching pairs may meet: an ordinary step, its contacts found at its end.
        restoreStepping(ballMoving);
        return ImpactStep::Unresolved;
    }
    // Again from the start, exactly to the instant of impact; there every
    // gap that has closed is a contact, answered by the collision model as
    // at any contact (its depth is zero: nothing to separate).
    restoreStepping(ballMoving);
    if (first > 0.0) advanceListed(first, stepping_, ballMoving);
    Bodies bodies{&state_.robots, &model_.robots, &state_.ball, &model_.ball};
    for (const BodyGap& g : gaps_) {
        if (g.gap > g.closing * dt || !(g.gap > kContactSkin)) continue;  // (touching: met at the step's end)
        // (The exact state is within the paths' error of the searched one.)
        const std::optional<Contact> c = touchingContact(g);
        if (!c) continue;
        respondToContact(*c, bodies, model_.settings.collision_model, model_.settings.restitution);
        ++report.contacts;
        ++report.impacts;
        if (!(report.firstImpact <= stepStart + first)) report.firstImpact = stepStart + first;
    }
    // The rest of the step as an ordinary one: contacts that persist (a
    // robot pushing on) are found and resolved at its end, on the grid.
    const StepReport rest = stepWorld(model_, state_, dt - first, options);
    report.contacts += rest.contacts;
    ++report.stepCalls;
    return ImpactStep::Contact;
}

int Simulation::answerTouchingGaps(double now, AdvanceReport& report) {
    int answered = 0;
    Bodies bodies{&state_.robots, &model_.robots, &state_.ball, &model_.ball};
    for (const BodyGap& g : gaps_) {
        if (g.gap > kContactSkin || g.gap < kRoundingGap) continue;
        const std::optional<Contact> c = touchingContact(g);
        if (!c || !respondToContact(*c, bodies, model_.settings.collision_model, model_.settings.restitution))
            continue;
        ++report.contacts;
        ++report.impacts;
        ++answered;
        if (!(report.firstImpact <= now)) report.firstImpact = now;
    }
    return answered;
}

std::int64_t Simulation::stepThroughStretch(FrozenStart& start, const StretchLoop& loop, StepOptions& options,
                                            AdvanceReport& report, bool& unsafe) {
    const double dt = model_.settings.dt;
    const std::int64_t stretch = loop.stretch;
    const bool skip = loop.skip, impacts = loop.impacts, nobodyFrozen = loop.nobodyFrozen;
    const double smallest = loop.smallest;
    unsafe = false;
    std::int64_t done = 0, nextTry = 0, wait = kFirstRetryWait;
    bool touching = false;
    bool gapsKnown = false;  // gaps_ holds this stretch's gaps that may come within the skin, and no contact came since
    while (done < stretch) {
        int answered = 0;  // touching pairs answered before this step (their velocities changed)
        // A step that may sub-step needs the frozen bodies' speeds now.
        const auto prepareStep = [&] {
            if (!skip || start.fastest * dt <= kMaxTravelFraction * smallest) return;
            frozenSpeeds(start, done, options);
        };
        // A contact that impactStep answered at its instant stands unless it
        // sent a body towards a frozen one: then the step is undone (false),
        // and the stretch is planned again with everybody.
        const auto contactKept = [&] {
            if (apartAfterContact(start, static_cast<double>(stretch - done - 1) * dt, dt)) return true;
            restoreStepping(!options.freeBall);
            return false;
        };
        if (impacts) {
            // Conservative advancement (time_of_impact.h): as many whole
            // steps as no gap can close in, in one step; when a gap may
            // close within the next step, that step finds the instant.
            const std::int64_t steps = gapSafeSteps(stretch - done, !options.freeBall, gapsKnown);
            gapsKnown = steps >= 0;
            // (Stepping bodies that can no longer touch anything before the
            // stretch ends freeze, as if they had at its start.)
            // Not in the step after a replan, in which nobody is frozen (it
            // must make progress), nor for a last step (nothing to gain).
            if (steps >= 0 && !nobodyFrozen && stretch - done >= 2)
                report.freezes += freezeUnconstrained(start, done, stretch, options);
            const bool ballMoving = !options.freeBall;
            if (steps >= 1) {
                advanceListed(static_cast<double>(steps) * dt, stepping_, ballMoving);
                done += steps;
                ++report.longSteps;
                continue;
            }
            if (steps == 0) {
                prepareStep();
                const double stepStart = static_cast<double>(state_.step + done) * dt;  // s
                const ImpactStep outcome = impactStep(ballMoving, stepStart, options, report);
                if (outcome == ImpactStep::Free) {  // (no contact: the gaps stay known)
                    ++done;
                    ++report.longSteps;
                    continue;
                }
                gapsKnown = false;
                if (outcome == ImpactStep::Contact) {
                    if (!contactKept()) {
                        unsafe = true;
                        break;
                    }
                    ++done;  // (while the bodies touch, the next steps meet them at their ends: gapSafeSteps)
                    continue;
                }
            }
            // Touching now, or a pass the search could not settle: a step on
            // the grid (unless another pair's contact is found at its
            // instant, below), after answering the touching pairs that approach.
            gapsKnown = false;  // (a step on the grid follows)
            if (steps < 0) {
                answered = answerTouchingGaps(static_cast<double>(state_.step + done) * dt, report);
                // The touching pairs meet at the step's end, but the other
                // pairs are searched as in a step without them: whether a
                // contact is answered at its instant must not depend on which
                // bodies share the step, which a cut changes (groups,
                // freezes). After an answer the gaps are measured again over
                // this step alone: gapSafeSteps' predate the new velocities,
                // and which pairs they hold depends on how far the stretch
                // reaches. (Without one they hold every pair a look over this
                // step would, closing no slower; impactStep bounds each
                // within the step itself and skips one that cannot close.)
                if (answered > 0) findBodyGaps(model_, state_, stepping_, ballMoving, dt, gaps_, gapScratch_);
                if (std::any_of(gaps_.begin(), gaps_.end(), [dt](const BodyGap& g) {
                        return g.gap > kContactSkin && !(g.gap / (g.closing * dt) >= 1.0);
                    })) {
                    prepareStep();
                    const double stepStart = static_cast<double>(state_.step + done) * dt;  // s
                    const ImpactStep outcome = impactStep(ballMoving, stepStart, options, report);
                    if (outcome == ImpactStep::Contact) {
                        if (!contactKept()) {
                            unsafe = true;
                            break;
                        }
                        ++done;
                        continue;
                    }
                    // Free: the gaps measured again may have left out the
                    // answered pair (parting, or too slow to close in the
                    // step); its step was taken, but the grid's contact
                    // passes and the check after an answer were not: back to
                    // the step's start, and the step on the grid below.
                    if (outcome == ImpactStep::Free) restoreStepping(ballMoving);
                }
            }
        } else if (skip && !impacts && !touching && done >= nextTry && stretch - done >= 2) {
            // The stepping bodies, too, may be free for a while (a robot
            // nearing a wall, not yet at it): a long step of a power of two
            // times dt for them. Not while touching; after a failed try, wait
            // (twice as long after each failure in a row).
            const std::int64_t steps = steppingFreeSteps(start, stretch - done);
            if (steps >= 2) {
                advanceListed(static_cast<double>(steps) * dt, stepping_, !options.freeBall);
                done += steps;
                ++report.longSteps;
                wait = kFirstRetryWait;
                continue;
            }
            nextTry = done + wait;
            wait = std::min(2 * wait, kLongestRetryWait);
        }
        prepareStep();
        // (With long steps only the stepping bodies move in it.)
        if (skip)
            saveStepping(!options.freeBall);
        else
            beforeStep_ = state_;
        const StepReport r = stepWorld(model_, state_, dt, options);
        // A contact may have sent a stepping body towards a free one (the
        // contact tests skip free bodies): then undo this step, bring the
        // free bodies to the present and take the step again with
        // everybody. The margin covers what a body can move within the
        // step after a contact.
        // (So may the touching pairs answered before it, even when the
        // step itself then finds no contact.)
        if ((r.contacts > 0 || answered > 0) &&
            !apartAfterContact(start, static_cast<double>(stretch - done - 1) * dt, dt)) {
            if (skip)
                restoreStepping(!options.freeBall);
            else
                state_ = beforeStep_;
            unsafe = true;
            break;
        }
        report.contacts += r.contacts;
        ++report.stepCalls;
        ++done;
        touching = r.contacts > 0;
    }
    return done;
}

AdvanceReport Simulation::advanceTo(std::int64_t target) {
    AdvanceReport report;
    const std::int64_t first = state_.step;
    // The exact integrator plans each stretch between voltage changes; with
    // long steps it also skips the free bodies' steps.
    // Robots off the field take ordinary steps only (ordinaryStep leaves them out).
    const bool plan = model_.settings.integrator == Integrator::Exact && !anyOffField();
    const bool skip = plan && model_.settings.long_steps;
    const bool impacts = skip && model_.settings.time_of_impact;  // contacts at their instant
    const double dt = model_.settings.dt;
    const std::size_t n = state_.robots.size();
    while (state_.step < target) {
        applyDueCommands();
        runSpeedLoops();
        std::int64_t next = nextLoopStep(target);  // the loops' samples change voltages too
        if (nextCommand_ < schedule_.size()) next = std::min(next, schedule_[nextCommand_].step);
        // After a replan: an ordinary step with everybody, or with contacts at
        // their instant, one step in which nobody is frozen, then plans as
        // usual (an ordinary step would answer the contact on the grid, and
        // the results would depend on where the calls are cut; a whole
        // stretch of everybody stepping costs a thousand robots dearly).
        const bool nobodyFrozen = forceOrdinaryStep_ && impacts;
        if (nobodyFrozen) next = std::min(next, state_.step + 1);
        const std::int64_t stretch = next - state_.step;  // steps until the voltages can change
        if (!plan || (forceOrdinaryStep_ && !impacts)) {
            forceOrdinaryStep_ = false;
            report.contacts += ordinaryStep().contacts;
            ++report.stepCalls;
            continue;
        }
        const double horizon = static_cast<double>(stretch) * dt;  // s
        findFreeBodies(model_, state_, horizon, free_);
        if (nobodyFrozen) {
            forceOrdinaryStep_ = false;
            free_.robots.assign(n, 0);
            free_.ball = false;
            free_.all = false;
        }
        if (free_.all && skip) {  // nothing can touch anything: one step to the next voltage change
            advanceBodies(horizon, nullptr, true);
            finishStep(stretch);
            ++report.longSteps;
            continue;
        }
        const bool someFree =
            free_.ball || std::any_of(free_.robots.begin(), free_.robots.end(), [](char f) { return f != 0; });
        if (!someFree && !impacts) {
            // Everybody may touch something before the stretch ends, but maybe
            // not soon: try shorter steps of a power of two times dt (few step
            // lengths, so their tables stay cached), else one ordinary step.
            std::int64_t steps = 1;
            if (skip) {
                while (steps * 2 < stretch) steps *= 2;
                for (; steps >= 2; steps /= 4) {
                    findFreeBodies(model_, state_, static_cast<double>(steps) * dt, free_);
                    if (free_.all) break;
                }
            }
            if (steps >= 2) {
                advanceBodies(static_cast<double>(steps) * dt, nullptr, true);
                finishStep(steps);
                ++report.longSteps;
            } else {
                report.contacts += ordinaryStep().contacts;
                ++report.stepCalls;
            }
            continue;
        }
        // Some bodies are free for the whole stretch: they stay where they are
        // while the others take steps of dt (no contact with them is possible
        // on the way), then they take the whole stretch in one step. Should a
        // contact among the others bring one of them near a free body after
        // all, that step is undone, the free ones catch up to the present, and
        // the step is taken again with everybody. The sub-steps count the free
        // bodies at their true current speeds, so every step is the one
        // step() would take. Without long steps the free bodies are
        // integrated with the others, step by step, under the same plan.
        FrozenStart& start = frozenStart_;
        start.frozen.assign(free_.robots.begin(), free_.robots.end());
        start.frozen.push_back(free_.ball);
        start.since.assign(n + 1, 0);
        start.x.resize(n + 1);
        start.y.resize(n + 1);
        start.travel.assign(free_.robotTravel.begin(), free_.robotTravel.end());
        start.travel.push_back(free_.ballTravel);
        for (std::size_t i = 0; i < n; ++i) start.x[i] = state_.robots[i].x, start.y[i] = state_.robots[i].y;
        start.x[n] = state_.ball.x;
        start.y[n] = state_.ball.y;
        start.robots = state_.robots;
        start.ball = state_.ball;
        // The frozen bodies by x (as addToFrozenOrder would sort them).
        sortBodiesByX();
        start.byX.clear();
        start.widest = 0.0;
        for (const auto& [x, b] : bodiesByX_) {
            if (!start.frozen[std::size_t(b)]) continue;
            start.byX.push_back(b);
            start.widest = std::max(start.widest, bodyReach(std::size_t(b)) + start.travel[std::size_t(b)]);
        }
        frozenRobots_.assign(start.frozen.begin(), start.frozen.begin() + static_cast<std::ptrdiff_t>(n));
        StepOptions options;
        options.freeRobots = &frozenRobots_;
        options.freeBall = start.frozen[n] != 0;
        options.frozen = skip;
        options.tables = tables();
        options.broadPhase = &broadPhase_;
        options.frozenRobotSpeed = &frozenSpeed_;
        // A frozen body's speed bound only falls along its free trajectory
        // (each mode's share moves towards its end), so when the bounds at
        // the time they froze cannot ask for sub-steps, none later can, and
        // the frozen bodies' current speeds are not needed.
        double smallest = model_.ball.radius;
        start.fastest = start.frozen[n] ? bodySpeed(n) : 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            smallest = std::min(smallest, 0.5 * model_.sides[i]);
            if (start.frozen[i]) start.fastest = std::max(start.fastest, bodySpeed(i));
        }
        frozenSpeed_.assign(n, 0.0);
        options.frozenBallSpeed = 0.0;
        stepping_.clear();
        for (std::size_t i = 0; i < n; ++i)
            if (!frozenRobots_[i]) stepping_.push_back(int(i));
        // With long steps a step looks at the stepping robots only.
        if (skip) {
            options.steppingRobots = &stepping_;
            options.smallestHalfSize = smallest;
        }
        const StretchLoop loop{stretch, skip, impacts, nobodyFrozen, smallest};
        std::int64_t done = stretch;
        // Group by group where the moving bodies fall apart (not in the step
        // after a replan: it takes everybody), else all together.
        if (!(impacts && !nobodyFrozen && stepInGroups(start, loop, options, report))) {
            bool unsafe = false;
            done = stepThroughStretch(start, loop, options, report, unsafe);
            if (unsafe) {  // again with everybody
                forceOrdinaryStep_ = true;
                ++report.replans;
            }
        }
        if (skip) {  // the frozen bodies catch up: by the whole stretch, or to the present
            catchUpFrozen(start, done, start.frozen[n] == kFrozen);
            ++report.longSteps;
        }
        finishStep(done);
    }
    report.steps = state_.step - first;
    return report;
}

}  // namespace vssim
