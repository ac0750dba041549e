// Collision response (model.md §6): the paper's exchange (eq. 12) and its
// decomposition back into (v, w), the energy-consistent impulse (§6b), and
// the positional separation, each against a closed form, an invariant or an
// independent computation written here.
#include <QtTest>

#include <limits>
#include <random>

#include "test_support.h"
#include "vssim/collision_detect.h"
#include "vssim/collision_response.h"
#include "vssim/geometry.h"

using namespace vssim;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A third parameter set, heavy and lopsided, unlike both the defaults and
// test::asymmetricParams().
RobotParams heavyParams() {
    RobotParams p;
    p.mass = 0.3;
    p.inertia = 3.1e-4;
    p.wheel_base = 0.07;
    p.right = {0.03, 10.0, 0.1, 2.2e-5, 1.1e-4};
    p.left = {0.022, 13.0, 0.08, 0.6e-5, 0.8e-4};
    return p;
}

// The bodies a contact refers to, owned here.
struct World {
    std::vector<RobotState> robots;
    std::vector<RobotModel> models;
    BallState ball;
    BallParams ballParams;
    Bodies bodies() { return Bodies{&robots, &models, &ball, &ballParams}; }
    void add(const RobotParams& p, const RobotState& s) {
        models.push_back(makeRobotModel(p));
        robots.push_back(s);
    }
};

RobotState robotState(double x, double y, double theta, double v = 0.0, double omega = 0.0) {
    RobotState r;
    r.x = x;
    r.y = y;
    r.theta = theta;
    r.v = v;
    r.omega = omega;
    return r;
}

Eigen::Vector2d heading(double theta) { return {std::cos(theta), std::sin(theta)}; }
Eigen::Vector2d perp(const Eigen::Vector2d& d) { return {-d.y(), d.x()}; }  // z x d
double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Kinetic energy of a robot written out from the wheels (model.md §2):
// body translation and yaw plus each rotor at w_k = (v +- w b/2) / r_k.
double robotEnergy(const RobotParams& p, double v, double w) {
    const double wd = (v + w * p.wheel_base / 2) / p.right.wheel_radius;
    const double we = (v - w * p.wheel_base / 2) / p.left.wheel_radius;
    return 0.5 * p.mass * v * v + 0.5 * p.inertia * w * w + 0.5 * p.right.rotor_inertia * wd * wd +
           0.5 * p.left.rotor_inertia * we * we;
}

// The same energy as a quadratic form 1/2 u^T M u: M from the energy above.
Eigen::Matrix2d massMatrix(const RobotParams& p) {
    const double cd = p.right.rotor_inertia / (p.right.wheel_radius * p.right.wheel_radius);
    const double ce = p.left.rotor_inertia / (p.left.wheel_radius * p.left.wheel_radius);
    const double b = p.wheel_base;
    Eigen::Matrix2d M;
    M << p.mass + cd + ce, (cd - ce) * b / 2, (cd - ce) * b / 2, p.inertia + (cd + ce) * b * b / 4;
    return M;
}

Eigen::Matrix2d inverse2(const Eigen::Matrix2d& M) {
    const double det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
    Eigen::Matrix2d inv;
    inv << M(1, 1) / det, -M(0, 1) / det, -M(1, 0) / det, M(0, 0) / det;
    return inv;
}

double independentEnergy(const World& w) {
    double e = 0.0;
    for (std::size_t i = 0; i < w.robots.size(); ++i)
        e += robotEnergy(w.models[i].params, w.robots[i].v, w.robots[i].omega);
    return e + 0.5 * w.ballParams.mass * (w.ball.vx * w.ball.vx + w.ball.vy * w.ball.vy);
}

// Normal velocity of a body's material point at `point`, and the body's
// generalized direction g and inverse effective mass g M^-1 g^T along n.
struct Side {
    double speed = 0.0;
    double inverseMass = 0.0;
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
};

Side side(const World& w, const BodyRef& ref, const Eigen::Vector2d& point, const Eigen::Vector2d& n) {
    Side s;
    if (ref.kind == BodyKind::Robot) {
        const RobotState& r = w.robots[ref.index];
        const Eigen::Vector2d d = point - Eigen::Vector2d(r.x, r.y);
        const Eigen::Vector2d vc = r.v * heading(r.theta) + r.omega * perp(d);
        s.speed = vc.dot(n);
        s.g = Eigen::Vector2d(n.dot(heading(r.theta)), cross(d, n));
        s.inverseMass = s.g.dot(inverse2(massMatrix(w.models[ref.index].params)) * s.g);
    } else if (ref.kind == BodyKind::Ball) {
        s.speed = n.dot(Eigen::Vector2d(w.ball.vx, w.ball.vy));
        s.inverseMass = 1.0 / w.ballParams.mass;
    }
    return s;
}

double approachSpeed(const World& w, const Contact& c) {
    return side(w, c.a, c.point, c.normal).speed - side(w, c.b, c.point, c.normal).speed;
}

// §6b written out: the velocities after an impulse lambda along n on a
// (and -lambda on b).
void applyImpulse(World& w, const BodyRef& ref, const Side& s, const Eigen::Vector2d& n, double lambda) {
    if (ref.kind == BodyKind::Robot) {
        RobotState& r = w.robots[ref.index];
        const Eigen::Vector2d du = inverse2(massMatrix(w.models[ref.index].params)) * s.g * lambda;
        r.v += du(0);
        r.omega += du(1);
    } else if (ref.kind == BodyKind::Ball) {
        w.ball.vx += lambda * n.x() / w.ballParams.mass;
        w.ball.vy += lambda * n.y() / w.ballParams.mass;
    }
}

bool sameState(const World& x, const World& y) {
    for (std::size_t i = 0; i < x.robots.size(); ++i) {
        const RobotState &a = x.robots[i], &b = y.robots[i];
        if (a.x != b.x || a.y != b.y || a.theta != b.theta || a.v != b.v || a.omega != b.omega) return false;
    }
    return x.ball.x == y.ball.x && x.ball.y == y.ball.y && x.ball.vx == y.ball.vx && x.ball.vy == y.ball.vy;
}

// Largest velocity difference, scaled: |got - want| / (1 + |want|).
double velocityError(const World& got, const World& want) {
    auto err = [](double g, double w) { return std::abs(g - w) / (1.0 + std::abs(w)); };
    double worst = 0.0;
    for (std::size_t i = 0; i < got.robots.size(); ++i)
        worst =
            std::max({worst, err(got.robots[i].v, want.robots[i].v), err(got.robots[i].omega, want.robots[i].omega)});
    return std::max({worst, err(got.ball.vx, want.ball.vx), err(got.ball.vy, want.ball.vy)});
}

// Three different robots and the ball at random places with random
// velocities, and a random contact between two of them (or one and a wall),
// with a random normal and contact point.
struct RandomCase {
    World world;
    Contact contact;
};

RandomCase randomCase(std::mt19937& rng) {
    std::uniform_real_distribution<double> pos(-0.5, 0.5), angle(-M_PI, M_PI), speed(-2.0, 2.0), yaw(-40.0, 40.0),
        ballSpeed(-3.0, 3.0), lever(-0.06, 0.06);
    std::uniform_int_distribution<int> kind(0, 4), robot(0, 2);
    RandomCase rc;
    World& w = rc.world;
    const RobotParams params[3] = {RobotParams(), test::asymmetricParams(), heavyParams()};
    for (const RobotParams& p : params) w.add(p, robotState(pos(rng), pos(rng), angle(rng), speed(rng), yaw(rng)));
    w.ball.x = pos(rng);
    w.ball.y = pos(rng);
    w.ball.vx = ballSpeed(rng);
    w.ball.vy = ballSpeed(rng);

    Contact& c = rc.contact;
    const int i = robot(rng);
    const int j = (i + 1 + robot(rng) % 2) % 3;  // another robot
    switch (kind(rng)) {
        case 0: c.a = {BodyKind::Robot, i}, c.b = {BodyKind::Robot, j}; break;
        case 1: c.a = {BodyKind::Ball, 0}, c.b = {BodyKind::Robot, i}; break;
        case 2: c.a = {BodyKind::Robot, i}, c.b = {BodyKind::Ball, 0}; break;
        case 3: c.a = {BodyKind::Robot, i}, c.b = {BodyKind::Wall, 2}; break;
        default: c.a = {BodyKind::Ball, 0}, c.b = {BodyKind::Wall, 1}; break;
    }
    const double phi = angle(rng);
    c.normal = Eigen::Vector2d(std::cos(phi), std::sin(phi));
    const BodyRef& anchor = c.a.kind == BodyKind::Robot ? c.a : c.b;
    if (anchor.kind == BodyKind::Robot) {
        const RobotState& r = w.robots[anchor.index];
        c.point = Eigen::Vector2d(r.x + lever(rng), r.y + lever(rng));
    } else {
        c.point = Eigen::Vector2d(w.ball.x, w.ball.y) - w.ballParams.radius * c.normal;
    }
    c.depth = 1e-4;
    return rc;
}

QString describe(const Contact& c) {
    auto name = [](const BodyRef& r) {
        return QString(r.kind == BodyKind::Robot  ? "robot %1"
                       : r.kind == BodyKind::Ball ? "ball"
                                                  : "wall %1")
            .arg(r.index);
    };
    return name(c.a) + " vs " + name(c.b);
}

}  // namespace

class TestCollisionResponse : public QObject {
    Q_OBJECT
private slots:
    void elasticExchangeFollowsEq12_data();
    void elasticExchangeFollowsEq12();
    void elasticExchangeAgainstWall_data();
    void elasticExchangeAgainstWall();
    void paperHeadOnRobots_data();
    void paperHeadOnRobots();
    void paperRobotKicksBallHeadOn_data();
    void paperRobotKicksBallHeadOn();
    void ballReflectsOffWall_data();
    void ballReflectsOffWall();
    void decomposeRecomposesOffLateralAxis();
    void decomposeFallbackOnLateralAxis_data();
    void decomposeFallbackOnLateralAxis();
    void kineticEnergyMatchesIndependentSum();
    void impulseModelRandomContacts_data();
    void impulseModelRandomContacts();
    void paperModelNeverCreatesEnergy();
    void separateRobotFromWall();
    void separateEqualRobots();
    void separateUnequalRobots();
    void separateRobotAndBall();
    void separateBallFromWall();
};

// ---------------------------------------------------------------- eq. 12

void TestCollisionResponse::elasticExchangeFollowsEq12_data() {
    QTest::addColumn<double>("m1");
    QTest::addColumn<double>("v1");
    QTest::addColumn<double>("m2");
    QTest::addColumn<double>("v2");
    QTest::newRow("equal masses, head on") << 0.18 << 1.3 << 0.18 << -0.7;
    QTest::newRow("equal masses, one at rest") << 0.2 << 2.0 << 0.2 << 0.0;
    QTest::newRow("equal masses, chasing") << 0.046 << 3.0 << 0.046 << 1.1;
    QTest::newRow("robot hits ball at rest") << 0.18 << 1.5 << 0.046 << 0.0;
    QTest::newRow("ball hits robot") << 0.046 << -2.5 << 0.18 << 0.4;
    QTest::newRow("very unequal") << 1000.0 << 0.01 << 0.001 << -5.0;
    QTest::newRow("both at rest") << 0.3 << 0.0 << 0.2 << 0.0;
}

void TestCollisionResponse::elasticExchangeFollowsEq12() {
    QFETCH(double, m1);
    QFETCH(double, v1);
    QFETCH(double, m2);
    QFETCH(double, v2);
    const Eigen::Vector2d got = elasticExchange(m1, v1, m2, v2);
    const double w1 = ((m1 - m2) * v1 + 2 * m2 * v2) / (m1 + m2);
    const double w2 = ((m2 - m1) * v2 + 2 * m1 * v1) / (m1 + m2);
    const double scale = 1.0 + std::abs(v1) + std::abs(v2);
    QVERIFY2(std::abs(got(0) - w1) < 1e-14 * scale, qPrintable(QString("v1' %1 vs %2").arg(got(0)).arg(w1)));
    QVERIFY2(std::abs(got(1) - w2) < 1e-14 * scale, qPrintable(QString("v2' %1 vs %2").arg(got(1)).arg(w2)));
    // Invariants: momentum and kinetic energy conserved, relative velocity reversed.
    const double p0 = m1 * v1 + m2 * v2, p1 = m1 * got(0) + m2 * got(1);
    const double e0 = 0.5 * m1 * v1 * v1 + 0.5 * m2 * v2 * v2,
                 e1 = 0.5 * m1 * got(0) * got(0) + 0.5 * m2 * got(1) * got(1);
    QVERIFY(std::abs(p1 - p0) <= 1e-13 * (std::abs(m1 * v1) + std::abs(m2 * v2)));
    QVERIFY(std::abs(e1 - e0) <= 1e-13 * e0);
    QVERIFY(std::abs((got(0) - got(1)) + (v1 - v2)) < 1e-13 * scale);
    if (m1 == m2) {  // equal masses swap their velocities
        QVERIFY(std::abs(got(0) - v2) < 1e-15 * scale);
        QVERIFY(std::abs(got(1) - v1) < 1e-15 * scale);
    }
}

void TestCollisionResponse::elasticExchangeAgainstWall_data() {
    QTest::addColumn<double>("m");
    QTest::addColumn<double>("v");
    QTest::newRow("robot into wall") << 0.18 << -1.2;
    QTest::newRow("ball into wall") << 0.046 << -4.0;
    QTest::newRow("ball moving away") << 0.046 << 0.3;
}

void TestCollisionResponse::elasticExchangeAgainstWall() {
    // A wall is a sphere of infinite mass at rest: the body's normal
    // component reverses and the wall stays at rest, whichever side it is on.
    QFETCH(double, m);
    QFETCH(double, v);
    const Eigen::Vector2d second = elasticExchange(m, v, kInf, 0.0);
    QVERIFY(std::isfinite(second(0)) && std::isfinite(second(1)));
    QCOMPARE(second(0), -v);
    QCOMPARE(second(1), 0.0);
    const Eigen::Vector2d first = elasticExchange(kInf, 0.0, m, v);
    QCOMPARE(first(0), 0.0);
    QCOMPARE(first(1), -v);
}

// ---------------------------------------------------------------- paper model, whole contacts

void TestCollisionResponse::paperHeadOnRobots_data() {
    // A at the origin heading theta; B ahead of it, facing it (heading
    // theta + pi). vA, vB are their forward speeds: positive = towards the other.
    QTest::addColumn<double>("theta");
    QTest::addColumn<double>("vA");
    QTest::addColumn<double>("vB");
    QTest::addColumn<double>("massB");
    QTest::addColumn<bool>("eq12Kept");  // false: eq. 12 would raise 1/2 u^T M u, the elastic impulse takes over
    QTest::newRow("equal, both approaching") << 0.0 << 1.0 << 0.5 << 0.18 << true;
    QTest::newRow("equal, B at rest, turned") << 0.7 << 1.2 << 0.0 << 0.18 << true;
    QTest::newRow("equal, B backing away slower") << -2.0 << 1.5 << -0.5 << 0.18 << true;
    QTest::newRow("light into heavy at rest") << 2.5 << 1.0 << 0.0 << 0.3 << true;
    QTest::newRow("heavy into light at rest") << -0.4 << 1.0 << 0.0 << 0.12 << false;
}

void TestCollisionResponse::paperHeadOnRobots() {
    QFETCH(double, theta);
    QFETCH(double, vA);
    QFETCH(double, vB);
    QFETCH(double, massB);
    QFETCH(bool, eq12Kept);
    const double s = 0.075, depth = 1e-4;
    const Eigen::Vector2d h = heading(theta);
    RobotParams pb;
    pb.mass = massB;
    World w;
    w.add(RobotParams(), robotState(0.1, -0.05, theta, vA));
    const Eigen::Vector2d cb = Eigen::Vector2d(0.1, -0.05) + (s - depth) * h;
    w.add(pb, robotState(cb.x(), cb.y(), theta + M_PI, vB));
    Contact c;
    c.a = {BodyKind::Robot, 0};
    c.b = {BodyKind::Robot, 1};
    c.normal = -h;                                                    // from B to A
    c.point = Eigen::Vector2d(0.1, -0.05) + (s / 2 - depth / 2) * h;  // on both forward axes
    c.depth = depth;

    // Velocities along h: A's is vA, B's is -vB. Eq. 12 with the robots' masses.
    const double mA = 0.18, pA = vA, pB = -vB;
    double wantA = ((mA - massB) * pA + 2 * massB * pB) / (mA + massB);
    double wantB = ((massB - mA) * pB + 2 * mA * pA) / (mA + massB);
    // The documented guard: the exchange is kept unless it raises the
    // energy 1/2 u^T M u, where M00 includes the rotors (m + J_d/r_d^2 + J_e/r_e^2).
    const double MA = massMatrix(RobotParams())(0, 0), MB = massMatrix(pb)(0, 0);
    const double before = 0.5 * MA * pA * pA + 0.5 * MB * pB * pB;
    const double after = 0.5 * MA * wantA * wantA + 0.5 * MB * wantB * wantB;
    QCOMPARE(after <= before * (1 + kPaperEnergyTolerance), eq12Kept);  // the row tests the branch it claims
    if (!eq12Kept) {
        // Then the elastic impulse: for a head-on contact g = (+-1, 0) and a
        // symmetric robot's M is diagonal, so it is eq. 12 with masses M00.
        wantA = ((MA - MB) * pA + 2 * MB * pB) / (MA + MB);
        wantB = ((MB - MA) * pB + 2 * MA * pA) / (MA + MB);
    }
    Bodies bodies = w.bodies();
    QVERIFY(respondToContact(c, bodies, CollisionModel::Paper, 1.0));
    QVERIFY2(std::abs(w.robots[0].v - wantA) < 1e-12,
             qPrintable(QString("A's speed %1, want %2").arg(w.robots[0].v).arg(wantA)));
    QVERIFY2(std::abs(w.robots[1].v - (-wantB)) < 1e-12,
             qPrintable(QString("B's speed %1, want %2").arg(w.robots[1].v).arg(-wantB)));
    if (massB == mA) {  // equal masses swap: A now moves as B did and vice versa
        QVERIFY(std::abs(w.robots[0].v - (-vB)) < 1e-12);
        QVERIFY(std::abs(w.robots[1].v - (-vA)) < 1e-12);
    }
    QVERIFY2(std::abs(w.robots[0].omega) < 1e-12 && std::abs(w.robots[1].omega) < 1e-12,
             qPrintable(QString("omega %1, %2").arg(w.robots[0].omega).arg(w.robots[1].omega)));
    QVERIFY(approachSpeed(w, c) > 0.0);  // now separating: the contact will not re-trigger
}

void TestCollisionResponse::paperRobotKicksBallHeadOn_data() {
    QTest::addColumn<double>("theta");
    QTest::addColumn<double>("v");           // robot forward speed
    QTest::addColumn<double>("ballAlong");   // ball velocity along h before
    QTest::addColumn<double>("ballAcross");  // ball velocity across h before (kept)
    QTest::newRow("ball at rest") << 0.0 << 1.0 << 0.0 << 0.0;
    QTest::newRow("ball at rest, turned") << 2.2 << 1.8 << 0.0 << 0.0;
    QTest::newRow("ball coming back") << -0.9 << 1.2 << -0.5 << 0.0;
    QTest::newRow("ball crossing") << 0.4 << 1.0 << 0.2 << 0.7;
}

void TestCollisionResponse::paperRobotKicksBallHeadOn() {
    QFETCH(double, theta);
    QFETCH(double, v);
    QFETCH(double, ballAlong);
    QFETCH(double, ballAcross);
    const double s = 0.075, depth = 1e-4;
    World w;
    w.add(RobotParams(), robotState(-0.2, 0.1, theta, v));
    const Eigen::Vector2d h = heading(theta), l = perp(h);
    const Eigen::Vector2d centre = Eigen::Vector2d(-0.2, 0.1) + (s / 2 + w.ballParams.radius - depth) * h;
    w.ball.x = centre.x();
    w.ball.y = centre.y();
    w.ball.vx = ballAlong * h.x() + ballAcross * l.x();
    w.ball.vy = ballAlong * h.y() + ballAcross * l.y();
    Contact c;  // as detection reports it: the ball is a, the robot b
    c.a = {BodyKind::Ball, 0};
    c.b = {BodyKind::Robot, 0};
    c.normal = h;
    c.point = Eigen::Vector2d(-0.2, 0.1) + s / 2 * h;  // middle of the front face
    c.depth = depth;

    // Eq. 12 with m1 = robot mass, m2 = ball mass, along h.
    const double m1 = 0.18, m2 = w.ballParams.mass;
    const double robotAfter = ((m1 - m2) * v + 2 * m2 * ballAlong) / (m1 + m2);
    const double ballAfter = ((m2 - m1) * ballAlong + 2 * m1 * v) / (m1 + m2);
    QVERIFY(std::abs(robotAfter) < std::abs(v));  // premise: the robot slows, so 1/2 u^T M u does not grow

    Bodies bodies = w.bodies();
    QVERIFY(respondToContact(c, bodies, CollisionModel::Paper, 1.0));
    const Eigen::Vector2d vb(w.ball.vx, w.ball.vy);
    QVERIFY2(std::abs(vb.dot(h) - ballAfter) < 1e-12,
             qPrintable(QString("ball %1 vs %2").arg(vb.dot(h)).arg(ballAfter)));
    QVERIFY(std::abs(vb.dot(l) - ballAcross) < 1e-12);  // the component across n is unchanged
    QVERIFY2(std::abs(w.robots[0].v - robotAfter) < 1e-12,
             qPrintable(QString("robot %1 vs %2").arg(w.robots[0].v).arg(robotAfter)));
    QVERIFY(std::abs(w.robots[0].omega) < 1e-12);
}

void TestCollisionResponse::ballReflectsOffWall_data() {
    QTest::addColumn<int>("model");
    QTest::addColumn<double>("restitution");
    QTest::addColumn<double>("normalAngle");  // the wall's inward normal
    QTest::addColumn<double>("vx");
    QTest::addColumn<double>("vy");
    for (int model : {int(CollisionModel::Paper), int(CollisionModel::Impulse)}) {
        const QByteArray m = model == int(CollisionModel::Paper) ? "paper" : "impulse";
        QTest::newRow(m + ", bottom wall") << model << 1.0 << M_PI / 2 << 1.0 << -1.5;
        QTest::newRow(m + ", right wall") << model << 1.0 << M_PI << 2.0 << 0.3;
        QTest::newRow(m + ", oblique wall") << model << 1.0 << 0.6 << -1.1 << -0.2;
    }
    // The impulse model scales the normal component by the restitution.
    QTest::newRow("impulse e=0.5, bottom") << int(CollisionModel::Impulse) << 0.5 << M_PI / 2 << 1.0 << -1.5;
    QTest::newRow("impulse e=0, oblique") << int(CollisionModel::Impulse) << 0.0 << -2.0 << 0.8 << 1.1;
}

void TestCollisionResponse::ballReflectsOffWall() {
    QFETCH(int, model);
    QFETCH(double, restitution);
    QFETCH(double, normalAngle);
    QFETCH(double, vx);
    QFETCH(double, vy);
    World w;
    w.ball.x = 0.1;
    w.ball.y = 0.2;
    w.ball.vx = vx;
    w.ball.vy = vy;
    const Eigen::Vector2d n = heading(normalAngle), t = perp(n), v0(vx, vy);
    QVERIFY(v0.dot(n) < 0.0);  // premise: moving into the wall
    Contact c;
    c.a = {BodyKind::Ball, 0};
    c.b = {BodyKind::Wall, 0};
    c.normal = n;
    c.point = Eigen::Vector2d(0.1, 0.2) - w.ballParams.radius * n;
    Bodies bodies = w.bodies();
    QVERIFY(respondToContact(c, bodies, CollisionModel(model), restitution));
    const Eigen::Vector2d v1(w.ball.vx, w.ball.vy);
    QVERIFY2(std::abs(v1.dot(n) + restitution * v0.dot(n)) < 1e-14,
             qPrintable(QString("normal %1 vs %2").arg(v1.dot(n)).arg(-restitution * v0.dot(n))));
    QVERIFY(std::abs(v1.dot(t) - v0.dot(t)) < 1e-14);  // tangential unchanged
    // Now moving away from the wall (or, at e = 0, along it): nothing more happens.
    if (restitution > 0.0) {
        const World before = w;
        QVERIFY(!respondToContact(c, bodies, CollisionModel(model), restitution));
        QVERIFY(sameState(w, before));
    }
}

// ---------------------------------------------------------------- decomposition (§6a)

void TestCollisionResponse::decomposeRecomposesOffLateralAxis() {
    // Off the lateral axis, (v', w') solves v' h + w' z x d = wanted exactly.
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> angle(-M_PI, M_PI), lever(-0.0375, 0.0375), speed(-3.0, 3.0);
    std::uniform_int_distribution<int> sign(0, 1);
    for (int k = 0; k < 5000; ++k) {
        const RobotState r = robotState(0.3, -0.1, angle(rng), speed(rng), 10 * speed(rng));
        double forward = lever(rng);
        if (k % 10 == 0)  // some just beyond the tolerance
            forward = (sign(rng) ? 1 : -1) * kLateralAxisTolerance * 1.01;
        if (std::abs(forward) < kLateralAxisTolerance) continue;
        const Eigen::Vector2d h = heading(r.theta);
        const Eigen::Vector2d d = forward * h + lever(rng) * perp(h);
        const Eigen::Vector2d wanted(speed(rng), speed(rng));
        const Eigen::Vector2d u = decomposeContactVelocity(r, d, wanted);
        const Eigen::Vector2d recomposed = u(0) * h + u(1) * perp(d);
        const double scale = 1.0 + std::abs(u(1)) * d.norm() + std::abs(u(0));
        QVERIFY2((recomposed - wanted).norm() < 1e-14 * scale,
                 qPrintable(QString("trial %1: off by %2").arg(k).arg((recomposed - wanted).norm())));
    }
}

void TestCollisionResponse::decomposeFallbackOnLateralAxis_data() {
    QTest::addColumn<double>("theta");
    QTest::addColumn<double>("forward");  // d_f, m
    QTest::addColumn<double>("lateral");  // d_l, m
    QTest::addColumn<double>("v");
    QTest::addColumn<double>("omega");
    QTest::addColumn<double>("wx");
    QTest::addColumn<double>("wy");
    QTest::newRow("exactly on the axis, left face") << 0.0 << 0.0 << 0.0375 << 0.5 << 2.0 << 1.0 << -0.4;
    QTest::newRow("exactly on the axis, right face, turned") << 1.1 << 0.0 << -0.0375 << -0.3 << -4.0 << 0.2 << 0.9;
    QTest::newRow("within tolerance ahead") << -2.3 << 5e-4 << 0.03 << 1.0 << 0.0 << -1.0 << 0.5;
    QTest::newRow("within tolerance behind") << 0.4 << -0.99e-3 << -0.02 << 0.0 << 7.0 << 0.0 << 0.0;
}

void TestCollisionResponse::decomposeFallbackOnLateralAxis() {
    // No finite yaw rate produces a lateral contact-point velocity there:
    // omega is kept, v' = v + h . (v_c' - v_c).
    QFETCH(double, theta);
    QFETCH(double, forward);
    QFETCH(double, lateral);
    QFETCH(double, v);
    QFETCH(double, omega);
    QFETCH(double, wx);
    QFETCH(double, wy);
    const RobotState r = robotState(-0.4, 0.2, theta, v, omega);
    const Eigen::Vector2d h = heading(theta);
    const Eigen::Vector2d d = forward * h + lateral * perp(h);
    const Eigen::Vector2d wanted(wx, wy);
    const Eigen::Vector2d vc = v * h + omega * perp(d);
    const Eigen::Vector2d u = decomposeContactVelocity(r, d, wanted);
    QVERIFY(std::isfinite(u(0)) && std::isfinite(u(1)));
    QCOMPARE(u(1), omega);
    const double want = v + h.dot(wanted - vc);
    QVERIFY2(std::abs(u(0) - want) < 1e-14, qPrintable(QString("v' %1 vs %2").arg(u(0)).arg(want)));
    // The forward part of the wanted velocity is met.
    QVERIFY(std::abs((u(0) * h + u(1) * perp(d)).dot(h) - wanted.dot(h)) < 1e-14);
}

// ---------------------------------------------------------------- impulse model (§6b)

void TestCollisionResponse::kineticEnergyMatchesIndependentSum() {
    World w;
    w.add(RobotParams(), robotState(0, 0, 0.3, 1.2, -7.0));
    w.add(test::asymmetricParams(), robotState(0.2, 0, -1.0, -0.8, 15.0));
    w.add(heavyParams(), robotState(-0.2, 0.1, 2.0, 0.3, 30.0));
    w.ball.vx = 2.0;
    w.ball.vy = -1.0;
    const double want = independentEnergy(w);
    QVERIFY(test::relativeError(kineticEnergy(w.bodies()), want) < 1e-13);
    // The quadratic form with the M derived here agrees with the wheel-by-wheel sum.
    double quadratic = 0.5 * w.ballParams.mass * 5.0;
    for (std::size_t i = 0; i < 3; ++i) {
        const Eigen::Vector2d u(w.robots[i].v, w.robots[i].omega);
        quadratic += 0.5 * u.dot(massMatrix(w.models[i].params) * u);
    }
    QVERIFY(test::relativeError(quadratic, want) < 1e-13);
    // Rotors count: without them the energy would be smaller.
    double bare = 0.5 * w.ballParams.mass * 5.0;
    for (std::size_t i = 0; i < 3; ++i) {
        const RobotParams& p = w.models[i].params;
        bare += 0.5 * p.mass * w.robots[i].v * w.robots[i].v + 0.5 * p.inertia * w.robots[i].omega * w.robots[i].omega;
    }
    QVERIFY(kineticEnergy(w.bodies()) > bare * (1 + 1e-3));
    // Without a ball.
    Bodies noBall = w.bodies();
    noBall.ball = nullptr;
    QVERIFY(test::relativeError(kineticEnergy(noBall), want - 0.5 * w.ballParams.mass * 5.0) < 1e-13);
}

void TestCollisionResponse::impulseModelRandomContacts_data() {
    QTest::addColumn<double>("restitution");
    QTest::newRow("e=1") << 1.0;
    QTest::newRow("e=0.7") << 0.7;
    QTest::newRow("e=0.3") << 0.3;
    QTest::newRow("e=0") << 0.0;
}

void TestCollisionResponse::impulseModelRandomContacts() {
    // For each random contact: separating bodies are left alone; approaching
    // ones get lambda = -(1 + e) v_rel / (g_A M_A^-1 g_A^T + g_B M_B^-1 g_B^T)
    // (computed here with M derived independently), after which the relative
    // normal velocity is -e v_rel and the energy changes by exactly
    // -(1 - e^2) v_rel^2 / (2 k): conserved at e = 1, strictly lost below.
    QFETCH(double, restitution);
    std::mt19937 rng(42 + static_cast<unsigned>(restitution * 10));
    int approaching = 0, separating = 0;
    for (int k = 0; k < 4000; ++k) {
        RandomCase rc = randomCase(rng);
        World& w = rc.world;
        const Contact& c = rc.contact;
        const World before = w;
        const double e0 = kineticEnergy(w.bodies());
        QVERIFY(test::relativeError(e0, independentEnergy(w)) < 1e-13);
        const Side a = side(w, c.a, c.point, c.normal), b = side(w, c.b, c.point, c.normal);
        const double vrel = a.speed - b.speed;
        Bodies bodies = w.bodies();
        const bool responded = respondToContact(c, bodies, CollisionModel::Impulse, restitution);
        const QString where = QString("trial %1 (%2), v_rel %3").arg(k).arg(describe(c)).arg(vrel);
        if (vrel >= 0.0) {
            ++separating;
            QVERIFY2(!responded, qPrintable(where));
            QVERIFY2(sameState(w, before), qPrintable(where));
            continue;
        }
        ++approaching;
        QVERIFY2(responded, qPrintable(where));
        const double inverseMass = a.inverseMass + b.inverseMass;
        const double lambda = -(1 + restitution) * vrel / inverseMass;
        World want = before;
        applyImpulse(want, c.a, a, c.normal, lambda);
        applyImpulse(want, c.b, b, c.normal, -lambda);
        QVERIFY2(velocityError(w, want) < 1e-12,
                 qPrintable(where + QString(": velocities off by %1").arg(velocityError(w, want))));
        for (std::size_t i = 0; i < w.robots.size(); ++i)  // positions untouched
            QVERIFY(w.robots[i].x == before.robots[i].x && w.robots[i].theta == before.robots[i].theta);

        const double vrelAfter = approachSpeed(w, c);
        QVERIFY2(std::abs(vrelAfter + restitution * vrel) < 1e-12 * (1 + std::abs(vrel)),
                 qPrintable(where + QString(": after %1, want %2").arg(vrelAfter).arg(-restitution * vrel)));
        const double e1 = kineticEnergy(w.bodies());
        const double loss = (1 - restitution * restitution) * vrel * vrel / (2 * inverseMass);
        QVERIFY2(std::abs((e0 - e1) - loss) <= 1e-12 * e0,
                 qPrintable(where +
                            QString(": energy %1 -> %2, loss %3").arg(e0, 0, 'g', 17).arg(e1, 0, 'g', 17).arg(loss)));
        if (restitution == 1.0)
            QVERIFY2(std::abs(e1 - e0) <= 1e-12 * e0, qPrintable(where));
        else
            QVERIFY2(e1 < e0, qPrintable(where + QString(": energy %1 -> %2").arg(e0, 0, 'g', 17).arg(e1, 0, 'g', 17)));
        // A second response does nothing: the bodies no longer approach
        // (at e = 0 they slide along: v_rel is zero up to rounding).
        if (restitution > 0.0) {
            const World resolved = w;
            QVERIFY2(!respondToContact(c, bodies, CollisionModel::Impulse, restitution), qPrintable(where));
            QVERIFY(sameState(w, resolved));
        }
    }
    QVERIFY(approaching > 1000 && separating > 1000);
}

void TestCollisionResponse::paperModelNeverCreatesEnergy() {
    // The paper's exchange ignores lever arms and M's rotor terms; whenever
    // it would raise the energy beyond kPaperEnergyTolerance the elastic
    // impulse is used instead. Random contacts of every kind: the energy
    // never grows beyond the tolerance.
    std::mt19937 rng(99);
    int approaching = 0, separating = 0, reversed = 0;
    for (int k = 0; k < 20000; ++k) {
        RandomCase rc = randomCase(rng);
        World& w = rc.world;
        const Contact& c = rc.contact;
        const World before = w;
        const double e0 = kineticEnergy(w.bodies());
        const double vrel = approachSpeed(w, c);
        Bodies bodies = w.bodies();
        const bool responded = respondToContact(c, bodies, CollisionModel::Paper, 1.0);
        const QString where = QString("trial %1 (%2), v_rel %3").arg(k).arg(describe(c)).arg(vrel);
        if (vrel >= 0.0) {
            ++separating;
            QVERIFY2(!responded && sameState(w, before), qPrintable(where));
            continue;
        }
        ++approaching;
        QVERIFY2(responded, qPrintable(where));
        const double e1 = kineticEnergy(w.bodies());
        QVERIFY2(e1 <= e0 * (1 + kPaperEnergyTolerance) + 1e-15,
                 qPrintable(where + QString(": energy %1 -> %2").arg(e0, 0, 'g', 17).arg(e1, 0, 'g', 17)));
        QVERIFY(test::relativeError(e1, independentEnergy(w)) < 1e-13);
        // Off every robot's lateral axis the contact-point velocities come
        // out exactly as asked, so whether eq. 12 is kept or the elastic
        // impulse takes over, the relative normal velocity is reversed.
        bool offAxis = true;
        for (const BodyRef* ref : {&c.a, &c.b})
            if (ref->kind == BodyKind::Robot) {
                const RobotState& r = before.robots[ref->index];
                const double df = (c.point - Eigen::Vector2d(r.x, r.y)).dot(heading(r.theta));
                offAxis = offAxis && std::abs(df) >= 1.01 * kLateralAxisTolerance;
            }
        if (offAxis) {
            ++reversed;
            const double vrelAfter = approachSpeed(w, c);
            QVERIFY2(std::abs(vrelAfter + vrel) < 1e-11 * (1 + std::abs(vrel)),
                     qPrintable(where + QString(": after %1").arg(vrelAfter)));
        }
        // Bodies not in the contact are untouched.
        for (int i = 0; i < 3; ++i) {
            const bool involved =
                (c.a.kind == BodyKind::Robot && c.a.index == i) || (c.b.kind == BodyKind::Robot && c.b.index == i);
            if (!involved) QVERIFY(w.robots[i].v == before.robots[i].v && w.robots[i].omega == before.robots[i].omega);
        }
        if (c.a.kind != BodyKind::Ball && c.b.kind != BodyKind::Ball)
            QVERIFY(w.ball.vx == before.ball.vx && w.ball.vy == before.ball.vy);
    }
    QVERIFY(approaching > 5000 && separating > 5000 && reversed > 5000);
}

// ---------------------------------------------------------------- separation

void TestCollisionResponse::separateRobotFromWall() {
    // A tilted robot 3 mm into the bottom wall moves up by exactly the depth.
    const Field field = makeRectangularField(1.5, 1.3);
    const double theta = 0.3, depth = 3e-3;
    const double lowest = std::min({std::sin(theta + M_PI / 4), std::sin(theta + 3 * M_PI / 4),
                                    std::sin(theta + 5 * M_PI / 4), std::sin(theta + 7 * M_PI / 4)});
    World w;
    const double y0 = -0.65 - depth - 0.075 / std::sqrt(2.0) * lowest;
    w.add(RobotParams(), robotState(0.1, y0, theta, -0.5, 3.0));
    const auto c = robotWallContact(w.robots[0], 0.075, 0, field.walls[0], 0);
    QVERIFY(c.has_value());
    QVERIFY(std::abs(c->depth - depth) < 1e-12);
    Bodies bodies = w.bodies();
    separateBodies(*c, bodies);
    QVERIFY(std::abs(w.robots[0].x - 0.1) < 1e-15);
    QVERIFY2(std::abs(w.robots[0].y - (y0 + depth)) < 1e-15,
             qPrintable(QString("moved %1, want %2").arg(w.robots[0].y - y0).arg(depth)));
    QCOMPARE(w.robots[0].theta, theta);
    QCOMPARE(w.robots[0].v, -0.5);  // velocities are the response's business
    QCOMPARE(w.robots[0].omega, 3.0);
    // Now resting on the wall: the lowest vertex at y = -0.65.
    double minY = 1.0;
    for (const Eigen::Vector2d& v : robotVertices(w.robots[0], 0.075)) minY = std::min(minY, v.y());
    QVERIFY(std::abs(minY + 0.65) < 1e-12);
    const auto again = robotWallContact(w.robots[0], 0.075, 0, field.walls[0], 0);
    QVERIFY(!again || again->depth < 1e-12);
}

void TestCollisionResponse::separateEqualRobots() {
    // Two equal robots, face to face 2 mm deep, turned: each takes half.
    const double theta = 0.8, depth = 2e-3, s = 0.075;
    const Eigen::Vector2d h = heading(theta);
    World w;
    w.add(RobotParams(), robotState(0.0, 0.0, theta));
    w.add(RobotParams(), robotState((s - depth) * h.x(), (s - depth) * h.y(), theta + M_PI));
    const World before = w;
    const auto c = robotRobotContact(w.robots[0], s, 0, w.robots[1], s, 1);
    QVERIFY(c.has_value());
    QVERIFY(std::abs(c->depth - depth) < 1e-12);
    Bodies bodies = w.bodies();
    separateBodies(*c, bodies);
    const Eigen::Vector2d movedA(w.robots[0].x - before.robots[0].x, w.robots[0].y - before.robots[0].y);
    const Eigen::Vector2d movedB(w.robots[1].x - before.robots[1].x, w.robots[1].y - before.robots[1].y);
    QVERIFY((movedA - (-h) * depth / 2).norm() < 1e-12);
    QVERIFY((movedB - h * depth / 2).norm() < 1e-12);
    const SquareOverlap o = squareOverlap(w.robots[0], s, w.robots[1], s);
    QVERIFY(!o.overlapping || o.depth < 1e-12);
}

void TestCollisionResponse::separateUnequalRobots() {
    // Masses 0.18 and 0.27 kg: A moves depth (1/mA)/(1/mA + 1/mB) = depth mB/(mA + mB).
    const double s = 0.075, depth = 1.5e-3;
    RobotParams heavy;
    heavy.mass = 0.27;
    World w;
    w.add(RobotParams(), robotState(0.0, 0.0, 0.0));
    w.add(heavy, robotState(0.02, -(s - depth), 0.0));  // B below A, overlapping on y
    const World before = w;
    const auto c = robotRobotContact(w.robots[0], s, 0, w.robots[1], s, 1);
    QVERIFY(c.has_value());
    QVERIFY(std::abs(c->depth - depth) < 1e-12);
    QVERIFY((c->normal - Eigen::Vector2d(0, 1)).norm() < 1e-12);
    Bodies bodies = w.bodies();
    separateBodies(*c, bodies);
    QVERIFY(std::abs((w.robots[0].y - before.robots[0].y) - depth * 0.27 / 0.45) < 1e-15);
    QVERIFY(std::abs((w.robots[1].y - before.robots[1].y) + depth * 0.18 / 0.45) < 1e-15);
    QCOMPARE(w.robots[0].x, 0.0);
    QCOMPARE(w.robots[1].x, 0.02);
}

void TestCollisionResponse::separateRobotAndBall() {
    // The ball 4 mm into a robot's front face: split by inverse mass, the
    // light ball taking m_r/(m_r + m_b) of the depth.
    const double s = 0.075, depth = 4e-3, theta = -0.6;
    World w;
    w.add(RobotParams(), robotState(0.3, 0.3, theta, 1.0, 0.0));
    const Eigen::Vector2d h = heading(theta);
    const Eigen::Vector2d centre = Eigen::Vector2d(0.3, 0.3) + (s / 2 + w.ballParams.radius - depth) * h;
    w.ball.x = centre.x();
    w.ball.y = centre.y();
    const World before = w;
    const auto c = robotBallContact(w.robots[0], s, 0, w.ball, w.ballParams.radius);
    QVERIFY(c.has_value());
    QVERIFY(std::abs(c->depth - depth) < 1e-12);
    Bodies bodies = w.bodies();
    separateBodies(*c, bodies);
    const double mr = 0.18, mb = w.ballParams.mass;
    const Eigen::Vector2d ballMoved(w.ball.x - before.ball.x, w.ball.y - before.ball.y);
    const Eigen::Vector2d robotMoved(w.robots[0].x - before.robots[0].x, w.robots[0].y - before.robots[0].y);
    QVERIFY((ballMoved - h * depth * mr / (mr + mb)).norm() < 1e-12);
    QVERIFY((robotMoved + h * depth * mb / (mr + mb)).norm() < 1e-12);
    const auto again = robotBallContact(w.robots[0], s, 0, w.ball, w.ballParams.radius);
    QVERIFY(!again || again->depth < 1e-12);
}

void TestCollisionResponse::separateBallFromWall() {
    const Field field = makeRectangularField(1.5, 1.3);
    World w;
    w.ball.x = 0.75 - w.ballParams.radius + 2e-3;  // 2 mm into the right wall
    w.ball.y = 0.1;
    const auto c = ballWallContact(w.ball, w.ballParams.radius, field.walls[1], 1);
    QVERIFY(c.has_value());
    Bodies bodies = w.bodies();
    separateBodies(*c, bodies);
    QVERIFY(std::abs(w.ball.x - (0.75 - w.ballParams.radius)) < 1e-15);
    QCOMPARE(w.ball.y, 0.1);
}

QTEST_GUILESS_MAIN(TestCollisionResponse)
#include "test_collision_response.moc"
