#include "stress_scenes.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "vssim/geometry.h"
#include "vssim/robot_model.h"

namespace vssim::stress {

namespace {

// Numbers from std::mt19937 (whose output the standard fixes) by explicit
// arithmetic, identical on every standard library.
class Random {
public:
    Random(std::uint32_t seed, std::uint32_t stream) {
        std::seed_seq sequence{seed, stream};
        engine_.seed(sequence);
    }
    // A seed for an independent generator (one draw from this one).
    std::uint32_t seed() { return static_cast<std::uint32_t>(engine_()); }
    // [0, 1) with 53 random bits.
    double uniform() {
        const std::uint32_t high = engine_() >> 5;  // 27 bits
        const std::uint32_t low = engine_() >> 6;   // 26 bits
        return (high * 67108864.0 + low) / 9007199254740992.0;
    }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    double logUniform(double lo, double hi) { return lo * std::exp(std::log(hi / lo) * uniform()); }
    // lo..hi, both included.
    int integer(int lo, int hi) { return std::min(hi, lo + static_cast<int>(std::floor(uniform() * (hi - lo + 1)))); }
    bool coin() { return uniform() < 0.5; }
    double angle() { return uniform(-M_PI, M_PI); }

private:
    std::mt19937 engine_;
};

// A rectangle of the field frame, m.
struct Region {
    double x0, x1, y0, y1;
};

constexpr double kFullVoltage = 7.4;  // V: the default e_max, commanded as it is (the engine clamps)
constexpr int kPlacementAttempts = 4000;

// The field's bounding box (the goals included).
Region wholeField(const Scene& scene) {
    const double hx = 0.5 * scene.field.length, hy = 0.5 * scene.field.width;
    if (hasGoals(scene.field)) return {scene.field.lower.x(), scene.field.upper.x(), -hy, hy};
    return {-hx, hx, -hy, hy};
}

// Whether a robot lies on the floor `gap` clear of the walls. The box keeps
// its rectangle test (so that its scenes stay what they were); a field with
// goals tests the robot's square grown by the gap against the chain.
bool robotOnFloor(const Scene& scene, const RobotState& pose, double side, double gap) {
    if (hasGoals(scene.field)) return robotInsideField(scene.field, side + 2.0 * gap, pose.x, pose.y, pose.theta);
    const double extent = 0.5 * side * (std::abs(std::cos(pose.theta)) + std::abs(std::sin(pose.theta)));
    return std::abs(pose.x) <= 0.5 * scene.field.length - extent - gap &&
           std::abs(pose.y) <= 0.5 * scene.field.width - extent - gap;
}

bool robotFits(const Scene& scene, const RobotState& pose, double side, double gap) {
    if (!robotOnFloor(scene, pose, side, gap)) return false;
    for (const RobotSpec& other : scene.robots)
        if (squareOverlap(pose, side + gap, other.initial, other.params.side + gap).overlapping) return false;
    const Eigen::Vector2d ball(scene.ball.x, scene.ball.y);
    return !pointInRobot(pose, side, ball, scene.ball_params.radius + gap);
}

bool ballFits(const Scene& scene, double x, double y, double gap) {
    const double r = scene.ball_params.radius;
    if (hasGoals(scene.field)) {
        if (!discInsideField(scene.field, r + gap, x, y)) return false;
    } else if (std::abs(x) > 0.5 * scene.field.length - r - gap || std::abs(y) > 0.5 * scene.field.width - r - gap) {
        return false;
    }
    for (const RobotSpec& robot : scene.robots)
        if (pointInRobot(robot.initial, robot.params.side, {x, y}, r + gap)) return false;
    return true;
}

// Adds a robot at a random free place in `region` (grown by 10 % after each
// run of failed attempts, so that it always ends somewhere). Assumes the
// ball is already placed.
void addRobot(Random& rng, Scene& scene, const RobotParams& params, Region region, double gap) {
    RobotSpec robot;
    robot.params = params;
    robot.name = "robot" + std::to_string(scene.robots.size() + 1);
    robot.team = scene.robots.size() % 2 == 0 ? Team::Yellow : Team::Blue;
    for (;;) {
        for (int attempt = 0; attempt < kPlacementAttempts; ++attempt) {
            robot.initial.x = rng.uniform(region.x0, region.x1);
            robot.initial.y = rng.uniform(region.y0, region.y1);
            robot.initial.theta = rng.angle();
            if (robotFits(scene, robot.initial, params.side, gap)) {
                scene.robots.push_back(robot);
                return;
            }
        }
        const double cx = 0.5 * (region.x0 + region.x1), cy = 0.5 * (region.y0 + region.y1);
        region = {cx + 1.1 * (region.x0 - cx), cx + 1.1 * (region.x1 - cx), cy + 1.1 * (region.y0 - cy),
                  cy + 1.1 * (region.y1 - cy)};
    }
}

// Places the ball at a random free place of the field (robots already placed).
void placeBall(Random& rng, Scene& scene, double gap) {
    const Region field = wholeField(scene);
    for (int attempt = 0; attempt < 100 * kPlacementAttempts; ++attempt) {
        const double x = rng.uniform(field.x0, field.x1), y = rng.uniform(field.y0, field.y1);
        if (ballFits(scene, x, y, gap)) {
            scene.ball.x = x;
            scene.ball.y = y;
            return;
        }
    }
    scene.ball.x = scene.ball.y = 0.0;  // not reached with the scenes below (at most 16 robots)
}

void setBallVelocity(Random& rng, Scene& scene, double maxSpeed) {
    const double speed = rng.uniform(0.0, maxSpeed), heading = rng.angle();
    scene.ball.vx = speed * std::cos(heading);
    scene.ball.vy = speed * std::sin(heading);
}

// Full voltage on both wheels of `robot`, signs drawn at t = 0 and changed
// (to one of the three other sign pairs) every `interval` seconds. The signs
// come from their own generator, seeded by one draw of `rng`, so that the
// rest of the scene does not depend on how long it runs.
void addFlippingCommands(Random& sceneRng, Scene& scene, int robot, double interval, double seconds) {
    Random rng(sceneRng.seed(), static_cast<std::uint32_t>(robot));
    double right = rng.coin() ? kFullVoltage : -kFullVoltage;
    double left = rng.coin() ? kFullVoltage : -kFullVoltage;
    for (std::int64_t k = 0; static_cast<double>(k) * interval < seconds; ++k) {
        scene.commands.push_back({static_cast<double>(k) * interval, robot, {right, left}});
        const int flip = rng.integer(1, 3);  // bit 0: right, bit 1: left
        if (flip & 1) right = -right;
        if (flip & 2) left = -left;
    }
}

// +-e_max alternating every `period` seconds, the wheels together (forward,
// backward) or opposed (spinning one way, then the other).
void addAlternatingCommands(Scene& scene, int robot, double period, bool opposed, double seconds) {
    for (std::int64_t k = 0; static_cast<double>(k) * period < seconds; ++k) {
        const double e = k % 2 == 0 ? kFullVoltage : -kFullVoltage;
        scene.commands.push_back({static_cast<double>(k) * period, robot, {e, opposed ? -e : e}});
    }
}

void setRandomVelocity(Random& rng, RobotState& robot, double maxSpeed, double maxYawRate) {
    robot.v = rng.uniform(-maxSpeed, maxSpeed);
    robot.omega = rng.uniform(-maxYawRate, maxYawRate);
}

void makePile(Random& rng, StressScene& s, double seconds) {
    Scene& scene = s.scene;
    const int n = rng.integer(6, 16);
    // m: 0.12 for 6 robots, 0.17 for 16 (grown by addRobot when too tight)
    const double half = 0.035 * std::sqrt(static_cast<double>(n)) + 0.03;
    // The centre anywhere, so that some piles are pressed against a wall or into a corner.
    const Region field = wholeField(scene);
    const double cx = rng.uniform(field.x0 + 0.1, field.x1 - 0.1), cy = rng.uniform(field.y0 + 0.1, field.y1 - 0.1);
    const Region region{cx - half, cx + half, cy - half, cy + half};
    const double r = scene.ball_params.radius;
    scene.ball.x = std::clamp(cx, field.x0 + r, field.x1 - r);
    scene.ball.y = std::clamp(cy, field.y0 + r, field.y1 - r);
    setBallVelocity(rng, scene, 3.0);
    for (int i = 0; i < n; ++i) addRobot(rng, scene, RobotParams{}, region, 0.002);
    for (int i = 0; i < n; ++i) addFlippingCommands(rng, scene, i, rng.uniform(0.1, 0.5), seconds);

    // The zero-voltage twin: same places, no commands, everything moving.
    s.hasZeroVoltage = true;
    s.zeroVoltage = scene;
    s.zeroVoltage.commands.clear();
    for (RobotSpec& robot : s.zeroVoltage.robots) setRandomVelocity(rng, robot.initial, 2.0, 40.0);
    const double speed = rng.uniform(1.0, 5.0), heading = rng.angle();
    s.zeroVoltage.ball.vx = speed * std::cos(heading);
    s.zeroVoltage.ball.vy = speed * std::sin(heading);
}

void makeAlternating(Random& rng, StressScene& s, double seconds) {
    Scene& scene = s.scene;
    const int n = rng.integer(2, 8);
    for (int i = 0; i < n; ++i) addRobot(rng, scene, RobotParams{}, wholeField(scene), 0.002);
    for (int i = 0; i < n; ++i) {
        setRandomVelocity(rng, scene.robots[i].initial, 1.0, 20.0);
        const double period = rng.logUniform(0.002, 0.1);  // s
        const bool opposed = rng.coin();
        addAlternatingCommands(scene, i, period, opposed, seconds);
    }
    placeBall(rng, scene, 0.002);
    setBallVelocity(rng, scene, 3.0);
}

void makeCornerShots(Random& rng, StressScene& s, double seconds) {
    Scene& scene = s.scene;
    scene.ball_params.friction = rng.uniform(0.002, 0.02);  // N s/m: some balls keep bouncing for long
    const double hx = 0.5 * scene.field.length, hy = 0.5 * scene.field.width;
    constexpr double kCornerRegion = 0.3;  // m
    scene.ball.x = 10.0;                   // out of the way until the robots are placed
    for (double sx : {-1.0, 1.0})
        for (double sy : {-1.0, 1.0}) {
            const Region corner{sx > 0 ? hx - kCornerRegion : -hx, sx > 0 ? hx : -hx + kCornerRegion,
                                sy > 0 ? hy - kCornerRegion : -hy, sy > 0 ? hy : -hy + kCornerRegion};
            const int n = rng.integer(1, 2);
            for (int i = 0; i < n; ++i) addRobot(rng, scene, RobotParams{}, corner, 0.001);
        }
    for (int i = 0; i < static_cast<int>(scene.robots.size()); ++i)
        addFlippingCommands(rng, scene, i, rng.uniform(0.1, 0.5), seconds);
    placeBall(rng, scene, 0.002);
    // Aim at a random corner, up to 5 cm inside it, at 5-10 m/s.
    // (One draw per statement: the order of two draws in one expression is unspecified.)
    const double sx = rng.coin() ? 1.0 : -1.0;
    const double sy = rng.coin() ? 1.0 : -1.0;
    const double tx = sx * (hx - rng.uniform(0.0, 0.05));
    const double ty = sy * (hy - rng.uniform(0.0, 0.05));
    const double dx = tx - scene.ball.x, dy = ty - scene.ball.y;
    const double distance = std::max(1e-9, std::hypot(dx, dy));
    const double speed = rng.uniform(5.0, 10.0);
    scene.ball.vx = speed * dx / distance;
    scene.ball.vy = speed * dy / distance;
}

MotorParams extremeMotor(Random& rng, double side) {
    MotorParams m;
    m.wheel_radius = rng.uniform(0.012, std::min(0.04, 0.5 * side));
    m.resistance = rng.logUniform(0.5, 30.0);
    m.k = rng.logUniform(0.02, 0.2);
    m.rotor_inertia = rng.logUniform(1e-8, 1e-4);
    m.friction = rng.uniform(0.0, 5e-4);
    return m;
}

// A robot with extreme but physically plausible parameters: each one drawn
// from a wide range, the two motors independently, and the set kept only when
// the robot's mechanical time constants are at least kMinTimeConstant and its
// top speeds plausible (<= 6 m/s, <= 200 rad/s at full voltage).
RobotParams extremeRobot(Random& rng) {
    for (int attempt = 0; attempt < 10000; ++attempt) {
        RobotParams p;
        p.side = rng.uniform(0.04, 0.10);
        p.mass = rng.logUniform(0.05, 0.6);
        p.inertia = p.mass * p.side * p.side / 6.0 * rng.uniform(0.5, 1.5);
        p.wheel_base = p.side * rng.uniform(0.5, 0.95);
        p.friction_linear = rng.uniform(0.0, 0.2);
        p.friction_angular = rng.uniform(0.0, 1e-3);
        p.right = extremeMotor(rng, p.side);
        p.left = extremeMotor(rng, p.side);
        const RobotModel model = makeRobotModel(p);
        const Eigen::Vector2d forward = model.steadyGain * Eigen::Vector2d(p.max_voltage, p.max_voltage);
        const Eigen::Vector2d spin = model.steadyGain * Eigen::Vector2d(p.max_voltage, -p.max_voltage);
        if (model.fastestRate * kMinTimeConstant <= 1.0 && std::abs(forward(0)) <= 6.0 && std::abs(spin(1)) <= 200.0)
            return p;
    }
    return RobotParams{};
}

void makeExtreme(Random& rng, StressScene& s, double seconds) {
    Scene& scene = s.scene;
    scene.ball_params.mass = rng.logUniform(0.02, 0.15);
    scene.ball_params.radius = rng.uniform(0.015, 0.035);
    scene.ball_params.friction = rng.uniform(0.002, 0.05);
    scene.ball.x = 10.0;  // out of the way until the robots are placed
    const int n = rng.integer(2, 8);
    for (int i = 0; i < n; ++i) addRobot(rng, scene, extremeRobot(rng), wholeField(scene), 0.002);
    for (int i = 0; i < n; ++i) {
        setRandomVelocity(rng, scene.robots[i].initial, 1.0, 10.0);
        addFlippingCommands(rng, scene, i, rng.logUniform(0.005, 0.5), seconds);
    }
    placeBall(rng, scene, 0.002);
    setBallVelocity(rng, scene, 5.0);
}

// An official field, 3 vs 3 or 5 vs 5.
void useOfficialField(Random& rng, Scene& scene) {
    scene.field = makeField(officialDimensions(rng.coin() ? FieldType::Vsss3v3 : FieldType::Vsss5v5));
}

// Robots driven into the goals' back corners and the corner triangles:
// 1-2 robots in and at the mouth of each goal, one near each corner
// triangle, full voltage with flipping signs; the ball fired at 5-10 m/s at
// a back corner of a goal.
void makeGoalCorners(Random& rng, StressScene& s, double seconds) {
    Scene& scene = s.scene;
    useOfficialField(rng, scene);
    const FieldDimensions& d = scene.field.dimensions;
    const double hx = 0.5 * d.length, hy = 0.5 * d.width, g = 0.5 * d.goal_width;
    scene.ball.x = 100.0;  // out of the way until the robots are placed
    for (double sx : {-1.0, 1.0}) {
        const Region goal{sx > 0 ? hx - 0.05 : -hx - d.goal_depth, sx > 0 ? hx + d.goal_depth : -hx + 0.05, -g, g};
        const int n = rng.integer(1, 2);
        for (int i = 0; i < n; ++i) addRobot(rng, scene, RobotParams{}, goal, 0.001);
        for (double sy : {-1.0, 1.0}) {
            const double reach = d.corner_leg + 0.12;  // m
            const Region corner{sx > 0 ? hx - reach : -hx, sx > 0 ? hx : -hx + reach, sy > 0 ? hy - reach : -hy,
                                sy > 0 ? hy : -hy + reach};
            addRobot(rng, scene, RobotParams{}, corner, 0.001);
        }
    }
    for (int i = 0; i < static_cast<int>(scene.robots.size()); ++i)
        addFlippingCommands(rng, scene, i, rng.uniform(0.1, 0.5), seconds);
    placeBall(rng, scene, 0.002);
    const double sx = rng.coin() ? 1.0 : -1.0;
    const double sy = rng.coin() ? 1.0 : -1.0;
    const double tx = sx * (hx + d.goal_depth - rng.uniform(0.0, 0.03));
    const double ty = sy * (g - rng.uniform(0.0, 0.03));
    const double dx = tx - scene.ball.x, dy = ty - scene.ball.y;
    const double distance = std::max(1e-9, std::hypot(dx, dy));
    const double speed = rng.uniform(5.0, 10.0);
    scene.ball.vx = speed * dx / distance;
    scene.ball.vy = speed * dy / distance;
}

// The ball wedged between a post and a robot: the ball touching a random
// post from a random side (from the field, along the goal line, from inside
// the goal), a robot right behind it facing the post at full forward
// voltage, backing off for 0.1 s every 0.3-1.5 s; 0-2 more robots around
// that goal with flipping signs.
void makePostWedge(Random& rng, StressScene& s, double seconds) {
    Scene& scene = s.scene;
    useOfficialField(rng, scene);
    const FieldDimensions& d = scene.field.dimensions;
    const double sx = rng.coin() ? 1.0 : -1.0;
    const double sy = rng.coin() ? 1.0 : -1.0;
    const Eigen::Vector2d post(sx * 0.5 * d.length, sy * 0.5 * d.goal_width);
    const double r = scene.ball_params.radius;
    const RobotParams params;
    RobotSpec robot;
    robot.params = params;
    robot.name = "robot1";
    for (int attempt = 0;; ++attempt) {
        // a = 0: straight out into the field; a > 0 towards the goal's middle
        // and into the goal (up to 2.5 rad); a < 0 along the goal line.
        const double a = rng.uniform(-1.2, 2.5);
        const Eigen::Vector2d u(-sx * std::cos(a), -sy * std::sin(a));
        const Eigen::Vector2d ball = post + (r + 0.0005) * u;
        const Eigen::Vector2d centre = ball + (r + 0.5 * params.side + 0.002) * u;
        scene.ball.x = ball.x(), scene.ball.y = ball.y();
        robot.initial.x = centre.x(), robot.initial.y = centre.y();
        robot.initial.theta = std::atan2(-u.y(), -u.x()) + rng.uniform(-0.3, 0.3);
        scene.robots.clear();
        if ((ballFits(scene, ball.x(), ball.y(), 0.0) && robotFits(scene, robot.initial, params.side, 0.0)) ||
            attempt == kPlacementAttempts) {
            if (attempt == kPlacementAttempts) scene.ball.x = scene.ball.y = 0.0, robot.initial = RobotState{};
            scene.robots.push_back(robot);
            break;
        }
    }
    Random pushes(rng.seed(), 0);
    for (double t = 0.0; t < seconds;) {
        scene.commands.push_back({t, 0, {kFullVoltage, kFullVoltage}});
        t += pushes.uniform(0.3, 1.5);
        if (t < seconds) scene.commands.push_back({t, 0, {-kFullVoltage, -kFullVoltage}});
        t += 0.1;
    }
    const Region around{post.x() - 0.3, post.x() + 0.1, post.y() - 0.3, post.y() + 0.3};
    const int n = rng.integer(0, 2);
    for (int i = 0; i < n; ++i) addRobot(rng, scene, RobotParams{}, around, 0.002);
    for (int i = 1; i <= n; ++i) addFlippingCommands(rng, scene, i, rng.uniform(0.1, 0.5), seconds);
}

// A robot inside each goal and 1-3 in front of it, full voltage with
// flipping signs; the ball in a goal or anywhere.
void makeInGoal(Random& rng, StressScene& s, double seconds) {
    Scene& scene = s.scene;
    useOfficialField(rng, scene);
    const FieldDimensions& d = scene.field.dimensions;
    const double hx = 0.5 * d.length, g = 0.5 * d.goal_width;
    scene.ball.x = 100.0;  // out of the way until the robots are placed
    for (double sx : {-1.0, 1.0}) {
        const Region goal{sx > 0 ? hx : -hx - d.goal_depth, sx > 0 ? hx + d.goal_depth : -hx, -g, g};
        addRobot(rng, scene, RobotParams{}, goal, 0.001);
        const Region front{sx > 0 ? hx - 0.3 : -hx, sx > 0 ? hx : -hx + 0.3, -g - 0.1, g + 0.1};
        const int n = rng.integer(1, 3);
        for (int i = 0; i < n; ++i) addRobot(rng, scene, RobotParams{}, front, 0.002);
    }
    for (int i = 0; i < static_cast<int>(scene.robots.size()); ++i) {
        setRandomVelocity(rng, scene.robots[i].initial, 1.0, 10.0);
        addFlippingCommands(rng, scene, i, rng.uniform(0.05, 0.5), seconds);
    }
    bool placed = false;
    if (rng.coin()) {
        const double sx = rng.coin() ? 1.0 : -1.0;
        for (int attempt = 0; attempt < kPlacementAttempts && !placed; ++attempt) {
            const double x = sx * rng.uniform(hx, hx + d.goal_depth), y = rng.uniform(-g, g);
            if (ballFits(scene, x, y, 0.002)) scene.ball.x = x, scene.ball.y = y, placed = true;
        }
    }
    if (!placed) placeBall(rng, scene, 0.002);
    setBallVelocity(rng, scene, 3.0);
}

}  // namespace

const char* sceneKindName(SceneKind kind) {
    switch (kind) {
        case SceneKind::Pile: return "pile";
        case SceneKind::Alternating: return "alternating";
        case SceneKind::CornerShots: return "corners";
        case SceneKind::Extreme: return "extreme";
        case SceneKind::GoalCorners: return "goal-corners";
        case SceneKind::PostWedge: return "post-wedge";
        case SceneKind::InGoal: return "in-goal";
    }
    return "?";
}

StressScene makeStressScene(std::uint32_t seed, int number, double seconds) {
    Random rng(seed, static_cast<std::uint32_t>(number));
    StressScene s;
    s.number = number;
    s.kind = static_cast<SceneKind>((number - 1) % kSceneKinds);
    s.restitution = rng.uniform();
    s.dtEuler = rng.logUniform(kMinDt, kMaxDt);
    s.dtRk4 = rng.logUniform(kMinDt, kMaxDt);
    s.dtExact = rng.logUniform(kMinDt, kMaxExactDt);
    switch (s.kind) {
        case SceneKind::Pile: makePile(rng, s, seconds); break;
        case SceneKind::Alternating: makeAlternating(rng, s, seconds); break;
        case SceneKind::CornerShots: makeCornerShots(rng, s, seconds); break;
        case SceneKind::Extreme: makeExtreme(rng, s, seconds); break;
        case SceneKind::GoalCorners: makeGoalCorners(rng, s, seconds); break;
        case SceneKind::PostWedge: makePostWedge(rng, s, seconds); break;
        case SceneKind::InGoal: makeInGoal(rng, s, seconds); break;
    }
    return s;
}

}  // namespace vssim::stress
