// Benchmark "box2d": vssim's real-time factor beside a Box2D 2.4 baseline of
// the same work, timed in the same run. The scene is the realtime
// benchmark's "random voltages" case (the shipped 3-vs-3 kick-off, new
// random voltages in +-7.4 V for every robot every 30 ms) on the official
// 3 vs 3 field, 60 s advanced frame by frame (30 ms) as a server would:
// eight such games (seeds 7 to 14; --quick: seed 7, 5 s), with the first
// game's figure on its own as well (the one measured alone before). Three
// settings, timed in interleaved rounds so that a busy host slows all of
// them alike:
//   - Box2D, a top-down (zero gravity) world stepped at 1 ms with its
//     default 8 velocity and 3 position iterations;
//   - vssim, RK4 at 1 ms;
//   - vssim, the exact integrator with long steps (its default).
//
// The Box2D world models what vssim models (model.md), the way a Box2D
// top-down game would:
//   - walls: the field's wall segments as static two-sided edges;
//   - robots: square dynamic bodies of the robot's side; each wheel pushes
//     with its DC motor's force, (K/R e - (K^2/R + beta_k) w_k) / r, from the
//     voltage and the wheel's current speed w_k = (its point's forward speed)
//     / r, applied at the wheel; the body's viscous friction beta_l v and
//     beta_theta w as a force and a torque; the wheels' lateral grip as an
//     impulse that cancels the lateral velocity before every step;
//   - the ball: a circle, its viscous friction as Box2D's linear damping
//     beta_b / m_b;
//   - contacts: frictionless and elastic like vssim's default (the paper's
//     exchange along the normal, restitution 1).
// A sanity check, printed and written to the CSV, shows that the Box2D robot
// is the same robot: one robot at full voltage from rest on an empty field,
// its top speed and yaw rate and their time constants, in both engines.
#include <box2d/box2d.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "bench_timing.h"
#include "benchmarks.h"
#include "vssim/robot_model.h"
#include "vssim/world.h"

namespace vssim::bench {

namespace {

// Box2D's tolerances are tuned for bodies of 0.1 to 10 length units (its
// linear slop is 0.005 units, the skin around polygons 0.01 units): in
// metres a 7.5 cm robot would carry a 1 cm skin. One Box2D length unit is
// therefore a decimetre here: the robot is 0.75 units, the ball 0.21 units,
// the skin 1 mm. Masses stay in kg and times in s, so a force in N is
// kUnitsPerMetre times larger in Box2D's units and a torque (or an inertia)
// kUnitsPerMetre^2 times.
constexpr double kUnitsPerMetre = 10.0;
constexpr int kVelocityIterations = 8;  // Box2D's documented defaults
constexpr int kPositionIterations = 3;
// Below this approach speed Box2D makes a contact inelastic, so that bodies
// pushed against each other by their motors rest instead of bouncing. m/s.
constexpr double kRestitutionThreshold = 0.1;
constexpr double kFramePeriod = 0.03;  // s, the camera's period: one advance per frame

b2Vec2 toBox2d(double x, double y) {
    return b2Vec2(static_cast<float>(x * kUnitsPerMetre), static_cast<float>(y * kUnitsPerMetre));
}

// Counts the contacts that begin touching (a body meeting a wall, a robot
// or the ball), the nearest Box2D figure to vssim's contact count.
class ContactCounter : public b2ContactListener {
public:
    void BeginContact(b2Contact*) override { ++count; }
    std::int64_t count = 0;
};

// A scene as a Box2D world: its field, robots and ball, its voltages applied
// by the caller.
class Box2dWorld {
public:
    explicit Box2dWorld(const Scene& scene) : world_(b2Vec2(0.0f, 0.0f)) {
        world_.SetContactListener(&contacts_);
        b2BodyDef wallsDef;  // static by default
        b2Body* walls = world_.CreateBody(&wallsDef);
        for (const Wall& w : scene.field.walls) {
            b2EdgeShape edge;
            edge.SetTwoSided(toBox2d(w.a.x(), w.a.y()), toBox2d(w.b.x(), w.b.y()));
            const b2FixtureDef def = fixtureDef(&edge, scene);
            walls->CreateFixture(&def);
        }
        for (const RobotSpec& spec : scene.robots) robots_.push_back(makeRobot(spec, scene));
        ball_ = makeBall(scene);
    }
    Box2dWorld(const Box2dWorld&) = delete;
    Box2dWorld& operator=(const Box2dWorld&) = delete;

    void setVoltages(int robot, const Voltages& e) { robots_[robot].e = clampVoltages(robots_[robot].model.params, e); }

    // One step of dt seconds: every robot's lateral grip and forces, then Box2D's step.
    void step(double dt) {
        for (Robot& r : robots_) drive(r);
        world_.Step(static_cast<float>(dt), kVelocityIterations, kPositionIterations);
    }

    // Robot i's forward speed (m/s) and yaw rate (rad/s).
    double forwardSpeed(int i) const {
        const b2Body* b = robots_[i].body;
        return b2Dot(b->GetWorldVector(b2Vec2(1.0f, 0.0f)), b->GetLinearVelocity()) / kUnitsPerMetre;
    }
    double yawRate(int i) const { return robots_[i].body->GetAngularVelocity(); }
    int robotCount() const { return static_cast<int>(robots_.size()); }
    // The ball's centre, m.
    Eigen::Vector2d ballPosition() const {
        const b2Vec2 p = ball_->GetPosition();
        return {p.x / kUnitsPerMetre, p.y / kUnitsPerMetre};
    }

    std::int64_t contactsBegun() const { return contacts_.count; }

    // How many bodies' centres are off the floor (escaped through a wall or
    // not finite): 0 in a sound run.
    int bodiesOffFloor(const Field& field) const {
        int off = 0;
        auto check = [&](const b2Body* b) {
            const b2Vec2 p = b->GetPosition();
            const Eigen::Vector2d c(p.x / kUnitsPerMetre, p.y / kUnitsPerMetre);
            if (!std::isfinite(c.x()) || !std::isfinite(c.y()) || !onFloor(field, c)) ++off;
        };
        for (const Robot& r : robots_) check(r.body);
        check(ball_);
        return off;
    }

private:
    struct Robot {
        b2Body* body = nullptr;
        RobotModel model;
        Voltages e;  // applied (clamped) voltages, V
    };

    static b2FixtureDef fixtureDef(const b2Shape* shape, const Scene& scene) {
        b2FixtureDef def;
        def.shape = shape;
        def.friction = 0.0f;  // vssim's contacts exchange momentum along the normal only
        // The paper's exchange is elastic; the impulse model takes the scene's restitution.
        def.restitution = static_cast<float>(
            scene.simulation.collision_model == CollisionModel::Paper ? 1.0 : scene.simulation.restitution);
        def.restitutionThreshold = static_cast<float>(kRestitutionThreshold * kUnitsPerMetre);
        def.density = 1.0f;  // replaced by SetMassData
        return def;
    }

    Robot makeRobot(const RobotSpec& spec, const Scene& scene) {
        Robot r;
        r.model = makeRobotModel(spec.params);
        b2BodyDef def;
        def.type = b2_dynamicBody;
        def.position = toBox2d(spec.initial.x, spec.initial.y);
        def.angle = static_cast<float>(spec.initial.theta);
        def.linearVelocity =
            toBox2d(spec.initial.v * std::cos(spec.initial.theta), spec.initial.v * std::sin(spec.initial.theta));
        def.angularVelocity = static_cast<float>(spec.initial.omega);
        r.body = world_.CreateBody(&def);
        // Box2D rounds a polygon's corners with a skin of b2_polygonRadius:
        // the box is that much smaller so that its outline is the robot's side.
        const float half = static_cast<float>(0.5 * spec.params.side * kUnitsPerMetre) - b2_polygonRadius;
        b2PolygonShape box;
        box.SetAsBox(half, half);
        const b2FixtureDef fixture = fixtureDef(&box, scene);
        r.body->CreateFixture(&fixture);
        // vssim's generalized mass M = diag(m, J) + T_w^-T diag(J_d, J_e)
        // T_w^-1 includes the rotors' inertia (0.18 kg + 0.032 kg by default):
        // the Box2D body gets M's diagonal, so that it accelerates as vssim's
        // robot does (M is diagonal for a robot whose two sides match, as in
        // this scene; Box2D has no mass coupling speed and yaw rate).
        b2MassData mass;
        mass.mass = static_cast<float>(r.model.M(0, 0));                                 // kg
        mass.center = b2Vec2(0.0f, 0.0f);                                                // centre of mass
        mass.I = static_cast<float>(r.model.M(1, 1) * kUnitsPerMetre * kUnitsPerMetre);  // kg unit^2
        r.body->SetMassData(&mass);
        return r;
    }

    b2Body* makeBall(const Scene& scene) {
        b2BodyDef def;
        def.type = b2_dynamicBody;
        def.position = toBox2d(scene.ball.x, scene.ball.y);
        def.linearVelocity = toBox2d(scene.ball.vx, scene.ball.vy);
        // model.md eq. 9: m_b v' = -beta_b v, i.e. damping beta_b / m_b, 1/s
        // (Box2D applies it as v /= 1 + h c, the same to first order in h).
        def.linearDamping = static_cast<float>(scene.ball_params.friction / scene.ball_params.mass);
        def.fixedRotation = true;  // vssim's ball has no spin (and frictionless contacts give it none)
        b2Body* ball = world_.CreateBody(&def);
        b2CircleShape circle;
        circle.m_radius = static_cast<float>(scene.ball_params.radius * kUnitsPerMetre);
        const b2FixtureDef fixture = fixtureDef(&circle, scene);
        ball->CreateFixture(&fixture);
        b2MassData mass;
        mass.mass = static_cast<float>(scene.ball_params.mass);  // kg
        mass.center = b2Vec2(0.0f, 0.0f);
        mass.I = 0.0f;
        ball->SetMassData(&mass);
        return ball;
    }

    // The forces of model.md §2 on one robot for the coming step, from its
    // current velocity: each wheel's motor, the body's viscous friction, and
    // the wheels' lateral grip (the no-slip constraint, eq. 3).
    static void drive(Robot& r) {
        b2Body* b = r.body;
        const RobotParams& p = r.model.params;
        const b2Vec2 forward = b->GetWorldVector(b2Vec2(1.0f, 0.0f));
        const b2Vec2 left = b->GetWorldVector(b2Vec2(0.0f, 1.0f));
        // Lateral grip: an impulse at the centre that cancels the lateral
        // velocity. Both wheels sit on the axle through the centre, so their
        // lateral velocity is the centre's.
        const float lateral = b2Dot(left, b->GetLinearVelocity());  // unit/s
        b->ApplyLinearImpulseToCenter(-b->GetMass() * lateral * left, true);
        // Each wheel: torque K/R e - (K^2/R + beta) w at the wheel, N m, over
        // its radius: the force where it touches the floor, N. Right wheel at
        // -b/2 along the robot's left axis, left wheel at +b/2.
        const struct {
            const MotorParams& motor;
            double e;
            double side;
        } wheels[] = {{p.right, r.e.right, -1.0}, {p.left, r.e.left, 1.0}};
        for (const auto& w : wheels) {
            const b2Vec2 at =
                b->GetWorldPoint(b2Vec2(0.0f, static_cast<float>(w.side * 0.5 * p.wheel_base * kUnitsPerMetre)));
            const double speed = b2Dot(forward, b->GetLinearVelocityFromWorldPoint(at)) / kUnitsPerMetre;  // m/s
            const double wheelRate = speed / w.motor.wheel_radius;                                         // rad/s
            const double torque = w.motor.k / w.motor.resistance * w.e -
                                  (w.motor.k * w.motor.k / w.motor.resistance + w.motor.friction) * wheelRate;
            const double force = torque / w.motor.wheel_radius * kUnitsPerMetre;  // kg unit/s^2
            b->ApplyForce(static_cast<float>(force) * forward, at, true);
        }
        // The body's viscous friction along its heading and about its axis.
        const double v = b2Dot(forward, b->GetLinearVelocity()) / kUnitsPerMetre;  // m/s
        b->ApplyForceToCenter(static_cast<float>(-p.friction_linear * v * kUnitsPerMetre) * forward, true);
        b->ApplyTorque(
            static_cast<float>(-p.friction_angular * b->GetAngularVelocity() * kUnitsPerMetre * kUnitsPerMetre), true);
    }

    b2World world_;
    ContactCounter contacts_;
    std::vector<Robot> robots_;
    b2Body* ball_ = nullptr;
};

// A scene's commands as steps of dt: (step index, robot, voltages) in the
// order vssim applies them (time order, ties in file order).
struct Due {
    std::int64_t step;
    int robot;
    Voltages e;
};
std::vector<Due> schedule(const Scene& scene) {
    std::vector<Due> due;
    for (const VoltageCommand& c : scene.commands) {
        if (c.wheelSpeeds)
            throw std::runtime_error("the Box2D baseline drives voltages only, not wheel-speed commands");
        due.push_back({Simulation::stepIndexAtOrAfter(c.t, scene.simulation.dt), c.robot, c.voltages});
    }
    std::stable_sort(due.begin(), due.end(), [](const Due& a, const Due& b) { return a.step < b.step; });
    return due;
}

// Runs the scene in Box2D to step `end`, frame by frame (30 ms) as vssim's
// runs are advanced; calls `sample` after every step with the number of
// steps taken.
std::int64_t runBox2d(const Scene& scene, std::int64_t end,
                      const std::function<void(const Box2dWorld&, std::int64_t)>& sample = {},
                      int* offFloor = nullptr) {
    const double dt = scene.simulation.dt;
    const std::vector<Due> due = schedule(scene);
    Box2dWorld world(scene);
    std::size_t next = 0;
    const std::int64_t perFrame = Simulation::stepIndexAtOrAfter(kFramePeriod, dt);
    for (std::int64_t frameEnd = perFrame; frameEnd < end + perFrame; frameEnd += perFrame)
        for (std::int64_t k = frameEnd - perFrame; k < std::min(frameEnd, end); ++k) {
            for (; next < due.size() && due[next].step <= k; ++next) world.setVoltages(due[next].robot, due[next].e);
            world.step(dt);
            if (sample) sample(world, k + 1);
        }
    if (offFloor) *offFloor = world.bodiesOffFloor(scene.field);
    return world.contactsBegun();
}

// Runs the scene in vssim to step `end`, frame by frame (30 ms).
AdvanceReport runVssim(const Scene& scene, std::int64_t end) {
    Simulation sim(scene);
    AdvanceReport totals;
    const std::int64_t perFrame = Simulation::stepIndexAtOrAfter(kFramePeriod, scene.simulation.dt);
    for (std::int64_t k = perFrame; k < end + perFrame; k += perFrame) {
        const AdvanceReport r = sim.advanceTo(std::min(k, end));
        totals.stepCalls += r.stepCalls;
        totals.longSteps += r.longSteps;
        totals.contacts += r.contacts;
    }
    return totals;
}

// A first-order step response sampled every dt from rest: its final value
// and the time it takes to reach 1 - 1/e of it (interpolated), s.
struct StepResponse {
    double top = 0.0;
    double timeConstant = 0.0;
};
StepResponse stepResponse(const std::vector<double>& samples, double dt) {
    StepResponse s;
    if (samples.empty()) return s;
    s.top = samples.back();
    const double mark = (1.0 - std::exp(-1.0)) * s.top;
    double previous = 0.0;  // at rest at t = 0
    for (std::size_t k = 0; k < samples.size(); ++k) {
        if (std::abs(samples[k]) >= std::abs(mark)) {
            const double fraction = (mark - previous) / (samples[k] - previous);
            s.timeConstant = (static_cast<double>(k) + fraction) * dt;
            break;
        }
        previous = samples[k];
    }
    return s;
}

// The sanity check: one robot of the scene at full voltage from rest, alone
// on a 100 m field, driving straight (e_max on both wheels) and spinning
// (+e_max right, -e_max left) for 1.5 s (about 18 time constants).
struct Sanity {
    StepResponse speed;  // m/s
    StepResponse yaw;    // rad/s
};
Scene sanityScene(const Scene& from, const Voltages& e) {
    Scene scene;
    scene.field = makeRectangularField(100.0, 100.0);
    scene.simulation = from.simulation;
    scene.ball_params = from.ball_params;
    scene.ball.x = 40.0;  // far from the robot: nothing to touch
    scene.ball.y = 40.0;
    RobotSpec robot = from.robots.at(0);
    robot.initial = RobotState{};
    scene.robots = {robot};
    scene.commands = {{0.0, 0, e}};
    return scene;
}
Sanity sanityBox2d(const Scene& from, double dt) {
    Sanity s;
    const double e = from.robots.at(0).params.max_voltage;
    for (bool spin : {false, true}) {
        Scene scene = sanityScene(from, {e, spin ? -e : e});
        scene.simulation.dt = dt;
        std::vector<double> samples;
        runBox2d(scene, Simulation::stepIndexAtOrAfter(1.5, dt), [&](const Box2dWorld& w, std::int64_t) {
            samples.push_back(spin ? w.yawRate(0) : w.forwardSpeed(0));
        });
        (spin ? s.yaw : s.speed) = stepResponse(samples, dt);
    }
    return s;
}
Sanity sanityVssim(const Scene& from, const SimulationSettings& settings) {
    Sanity s;
    const double e = from.robots.at(0).params.max_voltage;
    for (bool spin : {false, true}) {
        Scene scene = sanityScene(from, {e, spin ? -e : e});
        scene.simulation = settings;
        Simulation sim(scene);
        std::vector<double> samples;
        for (std::int64_t k = 1; k <= Simulation::stepIndexAtOrAfter(1.5, settings.dt); ++k) {
            sim.advanceTo(k);
            samples.push_back(spin ? sim.state().robots[0].omega : sim.state().robots[0].v);
        }
        (spin ? s.yaw : s.speed) = stepResponse(samples, settings.dt);
    }
    return s;
}

// What the bodies did in the benchmark's scene, sampled at every frame
// (30 ms): the robots' mean forward speed (m/s, the mean of |v|) and the
// ball's path length (m, frame to frame). Chaos makes the runs of two
// engines part after the first contacts; these show that the two do the
// same kind of work.
struct Activity {
    double meanRobotSpeed = 0.0;
    double ballTravel = 0.0;
};
struct ActivityAccumulator {
    Activity a;
    std::int64_t samples = 0;
    Eigen::Vector2d lastBall;
    explicit ActivityAccumulator(const Scene& scene) : lastBall(scene.ball.x, scene.ball.y) {}
    void add(const std::vector<double>& speeds, const Eigen::Vector2d& ball) {
        for (double v : speeds) a.meanRobotSpeed += std::abs(v);
        samples += static_cast<std::int64_t>(speeds.size());
        a.ballTravel += (ball - lastBall).norm();
        lastBall = ball;
    }
    Activity result() const {
        Activity r = a;
        if (samples > 0) r.meanRobotSpeed /= static_cast<double>(samples);
        return r;
    }
};
Activity activityBox2d(const Scene& scene, std::int64_t end) {
    ActivityAccumulator acc(scene);
    const std::int64_t perFrame = Simulation::stepIndexAtOrAfter(kFramePeriod, scene.simulation.dt);
    runBox2d(scene, end, [&](const Box2dWorld& w, std::int64_t k) {
        if (k % perFrame != 0 && k != end) return;
        std::vector<double> speeds;
        for (int i = 0; i < w.robotCount(); ++i) speeds.push_back(w.forwardSpeed(i));
        acc.add(speeds, w.ballPosition());
    });
    return acc.result();
}
Activity activityVssim(const Scene& scene, std::int64_t end) {
    ActivityAccumulator acc(scene);
    Simulation sim(scene);
    const std::int64_t perFrame = Simulation::stepIndexAtOrAfter(kFramePeriod, scene.simulation.dt);
    for (std::int64_t k = perFrame; k < end + perFrame; k += perFrame) {
        sim.advanceTo(std::min(k, end));
        std::vector<double> speeds;
        for (const RobotState& r : sim.state().robots) speeds.push_back(r.v);
        acc.add(speeds, Eigen::Vector2d(sim.state().ball.x, sim.state().ball.y));
    }
    return acc.result();
}

}  // namespace

int box2dBaseline(const Options& options, std::ostream& out, std::ostream& log) {
    const double duration = options.quick ? 5.0 : 60.0;  // simulated s
    // Several games (seeds 7, 8, ...): one game's figure is mostly its luck
    // (how often its robots happen to meet), from 11,000x to 17,600x over
    // seeds 7 to 14. The first, seed 7, is the game measured alone before.
    const int games = options.quick ? 1 : 8;
    std::vector<Scene> scenes;
    for (int g = 0; g < games; ++g) {
        Scene game = kickoffWithRandomVoltages(options.sceneFile, static_cast<unsigned>(7 + g), duration, kFramePeriod);
        game.field = makeField(officialDimensions(options.field.value_or(FieldType::Vsss3v3)));
        if (game.robots.empty()) throw std::runtime_error("the scene has no robot");
        scenes.push_back(std::move(game));
    }
    const Scene& scene = scenes.front();
    const double dt = 0.001;  // s, every setting's step
    const std::int64_t end = Simulation::stepIndexAtOrAfter(duration, dt);

    struct Setting {
        const char* name;
        bool box2d;
        std::vector<Scene> games;               // the first is `scene`
        std::vector<double> roundMedians = {};  // s: per round, the games' medians summed
        std::vector<double> firstGameMedians = {};  // s: per round, the first game's median
        int runs = 0;
        AdvanceReport report = {};  // vssim: steps and contacts of the last timed run
        std::int64_t contacts = 0;
        Sanity sanity = {};
        Activity activity = {};
    };
    auto withIntegrator = [&](Integrator integrator, bool longSteps) {
        std::vector<Scene> all = scenes;
        for (Scene& s : all) {
            s.simulation.dt = dt;
            s.simulation.integrator = integrator;
            s.simulation.long_steps = longSteps;
        }
        return all;
    };
    std::vector<Setting> settings;
    settings.push_back({"box2d 2.4 1 ms", true, withIntegrator(Integrator::Rk4, false)});  // (the integrator unused)
    settings.push_back({"vssim rk4 1 ms", false, withIntegrator(Integrator::Rk4, false)});
    // vssim's default: exact, long steps, contacts at their time of impact.
    settings.push_back({"vssim exact long steps (default)", false, withIntegrator(Integrator::Exact, true)});

    // The sanity check first: the same robot in each engine, beside the
    // closed forms of model.md §2 (M and B are diagonal for a robot whose
    // two sides match: two first-order lags).
    const RobotModel model = makeRobotModel(scene.robots[0].params);
    const double eMax = scene.robots[0].params.max_voltage;
    log << std::fixed << std::setprecision(4) << "  sanity check: " << scene.robots[0].name
        << " alone at full voltage from rest (top value; time to 1 - 1/e of it)\n"
        << "    " << std::setw(32) << "model.md closed form"
        << "  speed " << steadyStateVelocity(model, {eMax, eMax}).x() << " m/s, " << model.M(0, 0) / model.B(0, 0) * 1e3
        << " ms; yaw rate " << steadyStateVelocity(model, {eMax, -eMax}).y() << " rad/s, "
        << model.M(1, 1) / model.B(1, 1) * 1e3 << " ms\n";
    for (Setting& s : settings) {
        const Scene& first = s.games.front();
        s.sanity = s.box2d ? sanityBox2d(first, dt) : sanityVssim(first, first.simulation);
        log << "    " << std::setw(32) << s.name << "  speed " << s.sanity.speed.top << " m/s, "
            << s.sanity.speed.timeConstant * 1e3 << " ms; yaw rate " << s.sanity.yaw.top << " rad/s, "
            << s.sanity.yaw.timeConstant * 1e3 << " ms\n";
    }
    // What the bodies did in the first game (untimed runs).
    log << "  the first game (seed 7), every 30 ms: robots' mean |speed|, ball's path\n";
    for (Setting& s : settings) {
        s.activity = s.box2d ? activityBox2d(s.games.front(), end) : activityVssim(s.games.front(), end);
        log << "    " << std::setw(32) << s.name << "  " << std::setprecision(3) << s.activity.meanRobotSpeed
            << " m/s, " << s.activity.ballTravel << " m\n";
    }

    // Interleaved rounds: each round times every setting on every game (a
    // median of several runs each, summed over the games); the figure
    // quoted is the median of the rounds' sums.
    const int rounds = options.quick ? 1 : 5;
    int offFloor = 0;
    for (int round = 0; round < rounds; ++round) {
        log << "  round " << round + 1 << " of " << rounds << ":";
        for (Setting& s : settings) {
            double total = 0.0;  // s
            s.contacts = 0;
            s.report = {};
            for (std::size_t g = 0; g < s.games.size(); ++g) {
                std::int64_t contacts = 0;
                AdvanceReport report;
                auto run = [&] {
                    if (s.box2d)
                        contacts = runBox2d(s.games[g], end, {}, &offFloor);
                    else
                        report = runVssim(s.games[g], end);
                };
                const Timing t =
                    timeMedian(run, options.quick ? 1 : 3, options.quick ? 0.0 : 0.3, options.quick ? 1 : 21);
                total += t.median;
                if (g == 0) s.firstGameMedians.push_back(t.median);
                s.runs += t.runs;
                s.contacts += s.box2d ? contacts : report.contacts;
                s.report.stepCalls += report.stepCalls;
                s.report.longSteps += report.longSteps;
            }
            s.roundMedians.push_back(total);
            log << "  " << s.name << " " << std::setprecision(0) << games * duration / total << "x";
        }
        log << "\n";
    }
    if (offFloor != 0) log << "  warning: " << offFloor << " Box2D bodies ended off the floor (through a wall)\n";

    out << "setting,dt_s,simulated_s,run_time_s,realtime_factor,runs,rounds,step_calls,long_steps,contacts,"
           "top_speed_m_s,speed_time_constant_s,top_yaw_rate_rad_s,yaw_time_constant_s,mean_robot_speed_m_s,"
           "ball_path_m,games,first_game_realtime_factor\n"
        << std::defaultfloat << std::setprecision(6);
    const double box2dTime = median(settings[0].roundMedians);
    const double simulated = games * duration;  // s, all games
    std::ostringstream summary;
    summary << std::fixed;
    for (const Setting& s : settings) {
        const double t = median(s.roundMedians);
        const double firstFactor = duration / median(s.firstGameMedians);
        const std::int64_t steps = s.box2d ? games * end : s.report.stepCalls;
        const std::int64_t longSteps = s.box2d ? 0 : s.report.longSteps;
        out << '"' << s.name << "\"," << dt << ',' << simulated << ',' << t << ',' << simulated / t << ',' << s.runs
            << ',' << rounds << ',' << steps << ',' << longSteps << ',' << s.contacts << ',' << s.sanity.speed.top
            << ',' << s.sanity.speed.timeConstant << ',' << s.sanity.yaw.top << ',' << s.sanity.yaw.timeConstant << ','
            << s.activity.meanRobotSpeed << ',' << s.activity.ballTravel << ',' << games << ',' << firstFactor << '\n';
        summary << "  " << std::setw(32) << s.name << "  " << std::setprecision(0) << std::setw(7) << simulated / t
                << "x real time  (" << std::setprecision(2) << t * 1e3 << " ms for " << std::setprecision(0)
                << simulated << " s; " << steps << " steps, " << longSteps << " long steps, " << s.contacts
                << (s.box2d ? " contacts begun" : " contacts");
        if (!s.box2d) summary << "; " << std::setprecision(1) << box2dTime / t << "x Box2D's factor";
        summary << "; the first game alone " << std::setprecision(0) << firstFactor << "x)\n";
    }
    log << "  the 3-vs-3 kick-off, random voltages every 30 ms, " << games << (games == 1 ? " game" : " games")
        << " (seeds 7 on), " << (options.field ? "on the chosen field" : "on the official 3 vs 3 field")
        << ", dt = 1 ms; medians of "
        << rounds << (rounds == 1 ? " round" : " rounds") << ":\n"
        << summary.str();
    return 0;
}

}  // namespace vssim::bench
