#include "vssim/body_gaps.h"

#include <algorithm>
#include <cmath>

#include "vssim/collision_detect.h"
#include "vssim/geometry.h"

namespace vssim {

namespace {

// Below this gap (m) the closing speed is the point speeds' sum only. The
// normal between nearest points found to about 1e-16 m, a micrometre apart,
// is good to about 1e-10 rad, which moves a projection across a body or a
// wall's length by well under a nanometre. (The planner treats gaps under
// kContactSkin, 2 um, as touching before it reads a closing speed, so in
// practice this guard only matters to other callers.)
constexpr double kNormalTrustGap = 1e-6;

constexpr double kPi = 3.14159265358979323846;

}  // namespace

RobotState ballPose(const BallState& ball) {
    RobotState p;
    p.x = ball.x;
    p.y = ball.y;
    return p;
}

Separation separationBetween(const WorldModel& model, const BodyRef& a, const RobotState& poseA, const BodyRef& b,
                             const RobotState& poseB) {
    const Eigen::Vector2d centreA(poseA.x, poseA.y);
    if (b.kind == BodyKind::Wall) {
        const Wall& wall = model.field.walls[b.index];
        return a.kind == BodyKind::Ball ? ballWallSeparation(centreA, model.ball.radius, wall)
                                        : robotWallSeparation(poseA, model.sides[a.index], wall);
    }
    if (a.kind == BodyKind::Ball) return ballRobotSeparation(centreA, model.ball.radius, poseB, model.sides[b.index]);
    return robotRobotSeparation(poseA, model.sides[a.index], poseB, model.sides[b.index]);
}

double overlapDepthBetween(const WorldModel& model, const BodyRef& a, const RobotState& poseA, const BodyRef& b,
                           const RobotState& poseB) {
    const BallState ballA{poseA.x, poseA.y, 0.0, 0.0};  // (read when a is the ball)
    std::optional<Contact> c;
    if (b.kind == BodyKind::Wall) {
        const Wall& wall = model.field.walls[b.index];
        c = a.kind == BodyKind::Ball ? ballWallContact(ballA, model.ball.radius, wall, b.index)
                                     : robotWallContact(poseA, model.sides[a.index], a.index, wall, b.index);
    } else if (a.kind == BodyKind::Ball) {
        c = robotBallContact(poseB, model.sides[b.index], b.index, ballA, model.ball.radius);
    } else {
        c = robotRobotContact(poseA, model.sides[a.index], a.index, poseB, model.sides[b.index], b.index);
    }
    return c ? c->depth : 0.0;
}

MotionBound robotMotionBound(const RobotModel& model, const RobotState& state, const Voltages& e, double side,
                             const ModeProgress& progress) {
    const VelocityRange range = velocityRangeWithin(model, state, e, progress);
    MotionBound m;
    m.linear = range.magnitude(0);
    m.forwardLow = range.low(0);
    m.forwardHigh = range.high(0);
    m.turning = range.magnitude(1);
    m.swing = range.magnitude(1) * progress.T;
    // The heading's turn by t <= T is t times w's mean over [0, t].
    m.swingLow = std::min(0.0, range.low(1) * progress.T);
    m.swingHigh = std::max(0.0, range.high(1) * progress.T);
    if (!std::isfinite(m.linear) || !std::isfinite(m.turning))  // a state or model not finite: no signed ranges
        m.forwardLow = m.forwardHigh = m.swingLow = m.swingHigh = NAN;
    m.heading = cosSin(state.theta);
    m.side = side;
    m.pointSpeed = m.linear + boundingRadius(side) * m.turning;
    if (!std::isfinite(m.pointSpeed)) m.pointSpeed = INFINITY;
    return m;
}

MotionBound ballMotionBound(const BallState& ball) {
    MotionBound m;
    m.ball = true;
    m.velocity = Eigen::Vector2d(ball.vx, ball.vy);
    m.pointSpeed = std::hypot(ball.vx, ball.vy);
    return m;
}

namespace {

// How a body can move towards the other body of its pair along the unit
// vector `towards`, held fixed (body_gaps.h). A robot's centre moves along
// it at v cos(phi), phi the angle between the heading and `towards`, which
// stays within `swing` of phi0 (now): |cos| on that interval is at most
// cos(|phi0| - swing) <= |cos phi0| + |sin phi0| swing (phi0 folded into
// [0, pi/2]; cos(x - d) = cos x cos d + sin x sin d), and at most 1, which
// that sum also covers when the interval reaches phi = 0 (cos x + x sin x
// >= 1 on [0, pi/2]). The square's extent along it is (s/2)(|cos phi| +
// |sin phi|) = (s/sqrt2) cos z, z in [0, pi/4] the angle from phi to the
// nearest diagonal; after turning by at most tau it is at most
// (s/sqrt2) cos(max(0, z0 - tau)), which is within (s/sqrt2) sin(z0) tau of
// where it is now (cos is concave there) and never beyond s/sqrt2;
// (s/sqrt2) sin z0 = (s/2) ||cos phi0| - |sin phi0||; with the turn's
// signed range known, it can grow only as far as that range takes phi
// towards a diagonal (extentRoom). The ball goes
// straight, slowing down: its speed along `towards` only falls, and its
// extent is its radius.
struct Approach {
    double linear = 0.0;  // m/s: the centre's speed towards the other body, at most (< 0: away, at least that fast)
    double spin = 0.0;    // m/s: how fast the extent towards it can grow
    double room = 0.0;    // m: how much the extent towards it can grow at all
};

// How much a robot's extent along `towards` can grow while its heading
// turns by d within [a, b] (rad, a <= 0 <= b; NaN: not known), m. The
// extent is (s/sqrt2) cos z, z the angle from phi = phi0 + d to the nearest
// diagonal (phi = pi/4 mod pi/2), z0 = z at d = 0; it grows only while phi
// nears a diagonal. Turning by beta one way, phi either:
//  - heads for a diagonal z0 away: the extent grows by (s/sqrt2)
//    (cos(z0 - beta) - cos z0) <= rate beta (cos is concave on [-pi/2,
//    pi/2]; past the diagonal too, as 1 - cos z0 <= z0 sin z0 there);
//  - or heads away from it: the extent shrinks until phi is face on (at
//    pi/4 - z0), then grows back and is where it started only at
//    pi/2 - 2 z0 =: back; past that it is beyond by at most
//    rate (beta - back) (the first case again, mirrored).
// And never by more than `full`, the room to s/sqrt2. The larger of the
// two ways' growths is the room. z0 itself is not computed: sin z0 =
// |along - across| / sqrt2 =: q, and z0 <= q pi / (2 sqrt2) (sin is
// concave on [0, pi/4]), a picoradian more against rounding; that end
// makes `back` shorter, which allows more growth. Which way heads for the
// diagonal: the sign of d|extent|/dphi = (s/2)(sgn(sin phi0) cos phi0 -
// sgn(cos phi0) sin phi0); both ways when it is 0 (face on: both head for
// one; on a diagonal nothing can grow anyway).
double extentRoom(double along, double across, double cosine, double sine, double full, double rate, double a,
                  double b) {
    if (!(std::isfinite(a) && std::isfinite(b)) || !(full > 0.0)) return full;
    constexpr double kSinToAngle = 1.1107207345395915;  // (pi/4) / sin(pi/4)
    const double zHigh = std::abs(along - across) / std::sqrt(2.0) * kSinToAngle + 1e-12;  // rad, >= z0
    const double back = 0.5 * kPi - 2.0 * zHigh;  // rad: turned by this away from the diagonal, the extent is back
    auto growth = [&](double beta, bool towardsDiagonal) {  // m, after turning by beta >= 0 one way
        return std::min(full, rate * (towardsDiagonal ? beta : std::max(0.0, beta - back)));
    };
    const double sign = (sine > 0.0 ? cosine : sine < 0.0 ? -cosine : 0.0) -
                        (cosine > 0.0 ? sine : cosine < 0.0 ? -sine : 0.0);  // d|extent|/dphi's sign
    return std::max(growth(b, sign >= 0.0), growth(-a, sign <= 0.0));
}

Approach approachAlong(const MotionBound& body, const Eigen::Vector2d& towards) {
    if (body.ball) return Approach{std::max(0.0, towards.dot(body.velocity))};
    const CosSin& h = body.heading;
    const double cosine = towards.x() * h.c + towards.y() * h.s;  // cos phi0
    const double sine = towards.x() * h.s - towards.y() * h.c;    // sin phi0 (phi grows as the heading turns left)
    const double along = std::abs(cosine);                        // |cos phi0|
    const double across = std::abs(sine);                         // |sin phi0|
    const double half = 0.5 * body.side;
    // Signed: cos(phi0 + d) = cos phi0 cos d - sin phi0 sin d with d in
    // [swingLow, swingHigh] (which holds 0): sin d lies in that range too
    // (|sin d| <= |d|, same sign) as long as d stays within +-pi; a turn
    // past pi one way (a long stretch at full spin) reaches sin d = -+1 on
    // the other side. cos d lies within d^2 / 2 of 1, which only matters on
    // the side where it pulls cos phi0 towards 0. The approach v cos(phi)
    // is then at most the largest product of the two ranges' ends.
    // (A state that is not finite keeps |v| |cos|, infinite or NaN.)
    double linear = body.linear * std::min(1.0, along + across * body.swing);  // m/s, |v| |cos|
    const double a = body.swingLow, b = body.swingHigh;  // rad
    if (std::isfinite(body.forwardLow) && std::isfinite(body.forwardHigh) && std::isfinite(a) && std::isfinite(b)) {
        const double widest = std::max(-a, b), curve = 0.5 * widest * widest;
        const double sinLow = b > kPi ? std::min(a, -1.0) : a, sinHigh = a < -kPi ? std::max(b, 1.0) : b;
        const double turnedLow = std::min(-sine * sinLow, -sine * sinHigh);
        const double turnedHigh = std::max(-sine * sinLow, -sine * sinHigh);
        const double cosHigh = std::min(1.0, cosine + turnedHigh + (cosine < 0.0 ? along * curve : 0.0));
        const double cosLow = std::max(-1.0, cosine + turnedLow - (cosine > 0.0 ? along * curve : 0.0));
        const double signedLinear = std::max(std::max(body.forwardLow * cosLow, body.forwardLow * cosHigh),
                                             std::max(body.forwardHigh * cosLow, body.forwardHigh * cosHigh));
        if (signedLinear < linear) linear = signedLinear;
    }
    const double rate = half * std::abs(along - across);  // m/rad: (s/sqrt2) sin z0, the extent's growth per radian at most
    const double full = std::max(0.0, boundingRadius(body.side) - half * (along + across));  // m
    return Approach{linear, rate * body.turning, extentRoom(along, across, cosine, sine, full, rate, a, b)};
}

}  // namespace

// gap / t with t the later of the two bounds' earliest contacts. Along the
// normal, the gap along it after t is at least gap - L t - min(W t, R) (L,
// W, R the two bodies' linear, spin and room summed), which first reaches 0
// at gap / (L + W) when W gap / (L + W) <= R, else at (gap - R) / L. Body a
// moves towards b along -normal, b towards a along +normal. Only for a gap
// clear of rounding in the normal's direction (the nearest points are found
// to about 1e-16 m; kNormalTrustGap is far above that).
double closingSpeed(const Separation& s, const MotionBound& a, const MotionBound* b, double pointSpeeds) {
    if (s.overlapping || !(s.distance > kNormalTrustGap)) return pointSpeeds;
    const Approach p = approachAlong(a, -s.normal), q = b ? approachAlong(*b, s.normal) : Approach{};
    const double L = p.linear + q.linear, W = p.spin + q.spin, R = p.room + q.room;
    if (std::isnan(L + W + R)) return pointSpeeds;
    const double gap = s.distance;
    // L may be negative (the centres draw apart all along): then only the
    // extents' growth closes the gap, and once R is used up nothing does.
    double t = L + W > 0.0 ? gap / (L + W) : INFINITY;  // s
    if (W * t > R) t = L > 0.0 ? (gap - R) / L : INFINITY;
    const double closing = gap / t;                         // m/s
    return closing < pointSpeeds ? closing : pointSpeeds;  // (NaN: the point speeds)
}

void findBodyGaps(const WorldModel& model, const WorldState& state, const std::vector<int>& movingRobots,
                  bool ballMoving, double horizon, std::vector<BodyGap>& out, BodyGapScratch& scratch) {
    out.clear();
    const std::size_t n = state.robots.size();
    std::vector<MotionBound>& bounds = scratch.bounds;
    bounds.resize(n + 1);  // (only the moving bodies' entries are set and read)
    double fastest = 0.0;  // m/s
    for (const int i : movingRobots) {
        bounds[i] = robotMotionBound(model.robots[i], state.robots[i], state.voltages[i], model.sides[i],
                                     scratch.progress.get(model.robots[i], horizon));
        fastest = std::max(fastest, bounds[i].pointSpeed);
    }
    bounds[n] = ballMoving ? ballMotionBound(state.ball) : MotionBound{};
    auto speed = [&](std::size_t i) { return bounds[i].pointSpeed; };
    auto reach = [&](std::size_t i) { return i < n ? boundingRadius(model.sides[i]) : model.ball.radius; };
    auto centre = [&](std::size_t i) {
        return i < n ? Eigen::Vector2d(state.robots[i].x, state.robots[i].y)
                     : Eigen::Vector2d(state.ball.x, state.ball.y);
    };
    auto pose = [&](std::size_t i) { return i < n ? state.robots[i] : ballPose(state.ball); };
    auto ref = [n](std::size_t i) { return i < n ? BodyRef{BodyKind::Robot, int(i)} : BodyRef{BodyKind::Ball, 0}; };
    // Bodies i (a) and j (b): kept when their bounding discs can meet within the horizon.
    auto offer = [&](std::size_t i, std::size_t j) {
        const double closing = speed(i) + speed(j);
        const double discGap = (centre(i) - centre(j)).norm() - reach(i) - reach(j);
        if (discGap > closing * horizon) return;
        const Separation s = separationBetween(model, ref(i), pose(i), ref(j), pose(j));
        out.push_back({ref(i), ref(j), s.distance, closingSpeed(s, bounds[i], &bounds[j], closing), s.normal, s.point});
    };
    // Robot pairs, both moving (a frozen body is out of every moving one's
    // reach: long_step_planner.cpp): among the moving robots only, so that a
    // few moving among a thousand cost little. In index order either way.
    const std::vector<int>& moving = movingRobots;
    scratch.pairs.clear();
    listedCandidatePairs(moving, state.robots, model.sides, fastest * horizon, model.settings.broad_phase,
                         scratch.listed, scratch.pairs);
    for (const auto& [i, j] : scratch.pairs) offer(std::size_t(i), std::size_t(j));
    if (ballMoving)
        for (const int i : moving) offer(n, std::size_t(i));
    // Walls: skipped at once for a body clear of all of them by its reach and travel.
    auto offerWalls = [&](std::size_t i) {
        const double travel = speed(i) * horizon;
        const Eigen::Vector2d c = centre(i);
        if (clearOfWalls(model.field, c, reach(i) + travel)) return;
        for (std::size_t w = 0; w < model.field.walls.size(); ++w) {
            const Wall& wall = model.field.walls[w];
            // Far in front of the wall's line (cheap), or far from the segment.
            if (wall.normal.dot(c - wall.a) - reach(i) > travel) continue;
            if (closestPointOnSegment(wall.a, wall.b, c).distance - reach(i) > travel) continue;
            const BodyRef wallRef{BodyKind::Wall, int(w)};
            const Separation s = separationBetween(model, ref(i), pose(i), wallRef, RobotState{});
            out.push_back({ref(i), wallRef, s.distance, closingSpeed(s, bounds[i], nullptr, speed(i)), s.normal, s.point});
        }
    };
    for (const int i : moving) offerWalls(std::size_t(i));
    if (ballMoving) offerWalls(n);
}

void remeasureBodyGaps(const WorldModel& model, const WorldState& state, double horizon, std::vector<BodyGap>& gaps,
                       BodyGapScratch& scratch) {
    const std::size_t n = state.robots.size();
    std::vector<MotionBound>& bounds = scratch.bounds;
    bounds.resize(n + 1);
    scratch.bounded.assign(n + 1, 0);
    // Each body's bound once, however many of the gaps it is in.
    auto boundOf = [&](const BodyRef& body) -> const MotionBound* {
        if (body.kind == BodyKind::Wall) return nullptr;
        const std::size_t i = body.kind == BodyKind::Robot ? std::size_t(body.index) : n;
        if (!scratch.bounded[i]) {
            bounds[i] = i < n ? robotMotionBound(model.robots[i], state.robots[i], state.voltages[i], model.sides[i],
                                                 scratch.progress.get(model.robots[i], horizon))
                              : ballMotionBound(state.ball);
            scratch.bounded[i] = 1;
        }
        return &bounds[i];
    };
    auto pose = [&](const BodyRef& body) {
        if (body.kind == BodyKind::Robot) return state.robots[body.index];
        return body.kind == BodyKind::Ball ? ballPose(state.ball) : RobotState{};
    };
    for (BodyGap& g : gaps) {
        const MotionBound* a = boundOf(g.a);
        const MotionBound* b = boundOf(g.b);
        const Separation s = separationBetween(model, g.a, pose(g.a), g.b, pose(g.b));
        // (As findBodyGaps: a's point speed, plus b's unless b is a wall.)
        const double pointSpeeds = b ? a->pointSpeed + b->pointSpeed : a->pointSpeed;
        g = {g.a, g.b, s.distance, closingSpeed(s, *a, b, pointSpeeds), s.normal, s.point};
    }
}

}  // namespace vssim
