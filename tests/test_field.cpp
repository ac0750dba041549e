// The official VSSS fields (shared vsss-game.md, "Fields"; model.md §4): the
// chain of walls that makeField builds, the checks on its dimensions, what
// lies on the floor, and the bodies against every wall, post and hidden
// corner of the goals under both collision models (model.md §5, §6): no
// energy created, no body ever off the floor, and the long steps and the
// free-body test as safe there as in the box.
#include <QtTest>

#include <random>

#include "test_support.h"
#include "vssim/collision_detect.h"
#include "vssim/collision_response.h"
#include "vssim/field.h"
#include "vssim/free_bodies.h"
#include "vssim/geometry.h"
#include "vssim/world.h"

using namespace vssim;

namespace {

constexpr double kSide = 0.075;      // default robot side, m
constexpr double kRadius = 0.02135;  // default ball radius, m

Field official(FieldType type) { return makeField(officialDimensions(type)); }

QString str(const Eigen::Vector2d& v) { return QString("(%1, %2)").arg(v.x(), 0, 'g', 17).arg(v.y(), 0, 'g', 17); }

RobotState pose(double x, double y, double theta, double v = 0.0) {
    RobotState r;
    r.x = x, r.y = y, r.theta = theta, r.v = v;
    return r;
}

// Whether p lies on the closed polygon's floor, by the winding number of the
// corners (independent of the engine's crossing test).
bool insidePolygon(const std::vector<Eigen::Vector2d>& corners, const Eigen::Vector2d& p) {
    double turn = 0.0;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        const Eigen::Vector2d a = corners[i] - p, b = corners[(i + 1) % corners.size()] - p;
        turn += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    }
    return std::abs(turn) > M_PI;
}

// How far a robot reaches off the floor, m: the largest distance of a vertex
// off the floor to the walls, or of a post inside the square to its nearest
// face.
double robotOffFloor(const Field& field, const RobotState& r, double side) {
    double worst = 0.0;
    for (const Eigen::Vector2d& v : robotVertices(r, side))
        if (!onFloor(field, v)) worst = std::max(worst, nearestWall(field, v).distance);
    for (const Eigen::Vector2d& post : field.posts) {
        const Eigen::Vector2d local = toRobotFrame(r, post);
        worst = std::max(worst, std::min(0.5 * side - std::abs(local.x()), 0.5 * side - std::abs(local.y())));
    }
    return worst;
}

// How far the ball reaches past the walls, m.
double ballOffFloor(const Field& field, const BallState& b, double radius) {
    const Eigen::Vector2d c(b.x, b.y);
    const double d = nearestWall(field, c).distance;
    return onFloor(field, c) ? std::max(0.0, radius - d) : radius + d;
}

Scene sceneOn(FieldType type, CollisionModel model) {
    Scene scene;
    scene.field = official(type);
    scene.simulation.collision_model = model;
    scene.ball.x = 0.0, scene.ball.y = 0.0;
    return scene;
}

const char* modelName(CollisionModel m) { return m == CollisionModel::Paper ? "paper" : "impulse"; }

}  // namespace

class TestField : public QObject {
    Q_OBJECT
private slots:
    void officialDimensionsAreTheRules();
    void officialFieldsAreClosedChains();
    void boxIsTheSeedsFourWalls();
    void checkFieldDimensionsNamesTheProblem();
    void onFloorMatchesAPolygonTest();
    void bodiesInsideTheFieldNearGoalsAndCorners();
    void wallsPastAtAPostFollowTheCentre();
    void ballBouncesOffEveryWall();
    void robotBouncesOffEveryWall();
    void bodiesAgainstThePosts();
    void hiddenCornersAtTheBackOfTheGoal();
    void cornerTriangleJunctions();
    void ballRollsIntoTheGoalAndStopsAtTheBackWall();
    void robotDrivesIntoTheGoal();
    void impulseModelCreatesNoEnergyAgainstTheWalls();
    void noBodyEverEndsOffTheFloor();
    void longStepsAgreeWithStepsNearTheGoals();
    void freeBodiesNearPostsReallyAreFree();
};

void TestField::officialDimensionsAreTheRules() {
    // vsss-game.md, "Fields".
    const FieldDimensions a = officialDimensions(FieldType::Vsss3v3);
    QCOMPARE(a.length, 1.50);
    QCOMPARE(a.width, 1.30);
    QCOMPARE(a.goal_width, 0.40);
    QCOMPARE(a.goal_depth, 0.10);
    QCOMPARE(a.corner_leg, 0.07);
    QCOMPARE(a.centre_radius, 0.20);
    QCOMPARE(a.goal_area_depth, 0.15);
    QCOMPARE(a.goal_area_width, 0.70);
    const FieldDimensions b = officialDimensions(FieldType::Vsss5v5);
    QCOMPARE(b.length, 2.20);
    QCOMPARE(b.width, 1.80);
    QCOMPARE(b.goal_width, 0.40);
    QCOMPARE(b.goal_depth, 0.15);
    QCOMPARE(b.centre_radius, 0.25);
    QCOMPARE(b.goal_area_width, 0.50);
    QCOMPARE(b.free_ball_y, 0.40);
    const FieldDimensions box = officialDimensions(FieldType::Box);
    QCOMPARE(box.length, 1.50);
    QCOMPARE(box.width, 1.30);
    QCOMPARE(box.goal_width, 0.0);
    QCOMPARE(box.corner_leg, 0.0);
    for (FieldType t : {FieldType::Box, FieldType::Vsss3v3, FieldType::Vsss5v5})
        QVERIFY(checkFieldDimensions(officialDimensions(t)).key == nullptr);
}

void TestField::officialFieldsAreClosedChains() {
    for (FieldType type : {FieldType::Vsss3v3, FieldType::Vsss5v5}) {
        const FieldDimensions d = officialDimensions(type);
        const Field f = makeField(d);
        const double hx = d.length / 2, hy = d.width / 2, g = d.goal_width / 2;
        QCOMPARE(f.walls.size(), std::size_t(16));
        QVERIFY(hasGoals(f));
        std::vector<Eigen::Vector2d> corners;
        double area = 0.0;
        for (std::size_t i = 0; i < f.walls.size(); ++i) {
            const Wall& w = f.walls[i];
            const Wall& next = f.walls[(i + 1) % f.walls.size()];
            QVERIFY2(
                w.b == next.a,
                qPrintable(QString("wall %1 ends at %2, the next starts at %3").arg(i).arg(str(w.b)).arg(str(next.a))));
            QVERIFY(std::abs(w.normal.norm() - 1.0) < 1e-15);
            QVERIFY(std::abs(w.normal.dot(w.b - w.a)) < 1e-15);
            corners.push_back(w.a);
            area += w.a.x() * w.b.y() - w.a.y() * w.b.x();
            // The normal points to the floor: a point just in front of the
            // middle is on the floor, one just behind is not.
            const Eigen::Vector2d mid = 0.5 * (w.a + w.b);
            QVERIFY2(onFloor(f, mid + 1e-6 * w.normal), qPrintable(QString("wall %1").arg(i)));
            QVERIFY2(!onFloor(f, mid - 1e-6 * w.normal), qPrintable(QString("wall %1").arg(i)));
        }
        // Counter-clockwise, and the area is the rectangle plus two goals
        // minus four corner triangles.
        const double want = d.length * d.width + 2 * d.goal_width * d.goal_depth - 2 * d.corner_leg * d.corner_leg;
        QVERIFY2(std::abs(0.5 * area - want) < 1e-12, qPrintable(QString("area %1 vs %2").arg(0.5 * area).arg(want)));
        // The posts: the four ends of the goal mouths, and nothing else.
        QCOMPARE(f.posts.size(), std::size_t(4));
        for (const Eigen::Vector2d& p :
             {Eigen::Vector2d(hx, -g), Eigen::Vector2d(hx, g), Eigen::Vector2d(-hx, g), Eigen::Vector2d(-hx, -g)})
            QVERIFY2(std::find(f.posts.begin(), f.posts.end(), p) != f.posts.end(), qPrintable(str(p)));
        int starts = 0;
        for (std::size_t i = 0; i < f.walls.size(); ++i)
            if (f.startsAtPost[i]) {
                ++starts;
                QVERIFY(std::find(f.posts.begin(), f.posts.end(), f.walls[i].a) != f.posts.end());
            }
        QCOMPARE(starts, 4);
        // The goals: open mouths, depth and width as the rules say.
        for (double s : {1.0, -1.0}) {
            QVERIFY(onFloor(f, {s * (hx + d.goal_depth - 1e-6), g - 1e-6}));
            QVERIFY(onFloor(f, {s * (hx + d.goal_depth - 1e-6), -g + 1e-6}));
            QVERIFY(!onFloor(f, {s * (hx + d.goal_depth + 1e-6), 0.0}));
            QVERIFY(!onFloor(f, {s * (hx + 1e-6), g + 1e-6}));
            QVERIFY(onFloor(f, {s * (hx - 1e-6), s * (hy - d.corner_leg - 1e-4)}));  // just short of a triangle's foot
            QVERIFY(!onFloor(f, {s * (hx - 0.02), s * (hy - 0.02)}));                // in a corner triangle
        }
        QCOMPARE(f.lower, Eigen::Vector2d(-hx - d.goal_depth, -hy));
        QCOMPARE(f.upper, Eigen::Vector2d(hx + d.goal_depth, hy));
        QVERIFY(!insidePolygon(corners, {hx + d.goal_depth + 0.01, 0.0}));
    }
}

void TestField::boxIsTheSeedsFourWalls() {
    const Field f = makeRectangularField(1.5, 1.3);
    QCOMPARE(f.walls.size(), std::size_t(4));
    QVERIFY(f.posts.empty());
    QVERIFY(!hasGoals(f));
    const Eigen::Vector2d normals[4] = {{0, 1}, {-1, 0}, {0, -1}, {1, 0}};  // bottom, right, top, left
    for (int i = 0; i < 4; ++i) QVERIFY(f.walls[i].normal == normals[i]);
    QVERIFY(f.walls[0].a == Eigen::Vector2d(-0.75, -0.65));
}

void TestField::checkFieldDimensionsNamesTheProblem() {
    const FieldDimensions ok = officialDimensions(FieldType::Vsss3v3);
    struct Case {
        const char* what;
        FieldDimensions d;
        const char* key;
    };
    std::vector<Case> cases;
    auto with = [&](const char* what, auto change, const char* key) {
        FieldDimensions d = ok;
        change(d);
        cases.push_back({what, d, key});
    };
    with(
        "goal as wide as the wall between the corners", [](FieldDimensions& d) { d.goal_width = 1.30 - 0.14; },
        "goal_width");
    with(
        "goal wider than the field", [](FieldDimensions& d) { d.goal_width = 2.0; }, "goal_width");
    with(
        "negative length", [](FieldDimensions& d) { d.length = -1.5; }, "length");
    with(
        "zero width", [](FieldDimensions& d) { d.width = 0.0; }, "width");
    with(
        "NaN length", [](FieldDimensions& d) { d.length = std::nan(""); }, "length");
    with(
        "infinite width", [](FieldDimensions& d) { d.width = INFINITY; }, "width");
    with(
        "negative goal depth", [](FieldDimensions& d) { d.goal_depth = -0.1; }, "goal_depth");
    with(
        "NaN goal width", [](FieldDimensions& d) { d.goal_width = std::nan(""); }, "goal_width");
    with(
        "NaN corner leg", [](FieldDimensions& d) { d.corner_leg = std::nan(""); }, "corner_leg");
    with(
        "corner legs meeting", [](FieldDimensions& d) { d.corner_leg = 0.65; }, "corner_leg");
    with(
        "goals without depth", [](FieldDimensions& d) { d.goal_depth = 0.0; }, "goal_depth");
    with(
        "centre circle too big", [](FieldDimensions& d) { d.centre_radius = 0.7; }, "centre_radius");
    for (const Case& c : cases) {
        const FieldProblem p = checkFieldDimensions(c.d);
        QVERIFY2(p.key != nullptr, c.what);
        QVERIFY2(QString(p.key) == c.key, qPrintable(QString("%1: %2, not %3").arg(c.what, p.key, c.key)));
        QVERIFY2(std::strlen(p.reason) > 0, c.what);
    }
    // A goal just narrower than the wall between the corners is fine.
    FieldDimensions wide = ok;
    wide.goal_width = 1.30 - 0.14 - 1e-3;
    QVERIFY(checkFieldDimensions(wide).key == nullptr);
}

void TestField::onFloorMatchesAPolygonTest() {
    // Random points over the bounding box and beyond, against the winding
    // number; points within 1e-9 m of a wall are skipped (on a wall counts
    // as on the floor, which the winding number cannot say reliably).
    std::mt19937 rng(3);
    for (FieldType type : {FieldType::Box, FieldType::Vsss3v3, FieldType::Vsss5v5}) {
        const Field f = official(type);
        std::vector<Eigen::Vector2d> corners;
        for (const Wall& w : f.walls) corners.push_back(w.a);
        std::uniform_real_distribution<double> x(f.lower.x() - 0.05, f.upper.x() + 0.05),
            y(f.lower.y() - 0.05, f.upper.y() + 0.05);
        int on = 0;
        for (int k = 0; k < 20000; ++k) {
            const Eigen::Vector2d p(x(rng), y(rng));
            if (nearestWall(f, p).distance < 1e-9) continue;
            const bool want = insidePolygon(corners, p);
            QVERIFY2(onFloor(f, p) == want, qPrintable(str(p)));
            on += want;
        }
        QVERIFY(on > 10000);
        // The cheap test never clears a disc that touches a wall.
        for (int k = 0; k < 20000; ++k) {
            const Eigen::Vector2d p(x(rng), y(rng));
            const double r = 0.06 * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
            if (clearOfWalls(f, p, r)) QVERIFY2(onFloor(f, p) && nearestWall(f, p).distance > r, qPrintable(str(p)));
        }
    }
}

void TestField::bodiesInsideTheFieldNearGoalsAndCorners() {
    const Field f = official(FieldType::Vsss3v3);
    const double hx = 0.75, hy = 0.65, g = 0.20, depth = 0.10, c = 0.07, h = kSide / 2;
    // Robots.
    QVERIFY(robotInsideField(f, kSide, 0.0, 0.0, 0.3));
    QVERIFY(robotInsideField(f, kSide, hx + 0.05, 0.0, 0.0));         // in the goal, square
    QVERIFY(robotInsideField(f, kSide, -hx - 0.05, 0.1, M_PI));       // in the other goal
    QVERIFY(!robotInsideField(f, kSide, hx + 0.05, 0.0, M_PI / 4));   // 45°: 5.3 cm each way, 5 cm to the back wall
    QVERIFY(robotInsideField(f, kSide, hx + depth - h, g - h, 0.0));  // jammed square in a back corner, touching
    QVERIFY(!robotInsideField(f, kSide, hx + depth - h + 1e-6, 0.0, 0.0));
    QVERIFY(!robotInsideField(f, kSide, hx + 0.05, -g - 0.03, 0.0));  // behind a post, in the wall
    QVERIFY(!robotInsideField(f, kSide, hx, -g, 0.0));                // straddling a post
    QVERIFY(!robotInsideField(f, kSide, hx + 0.01, -g + 0.03, 0.0));  // a post in its face, nothing else out
    QVERIFY(robotInsideField(f, kSide, hx - h, -g - 0.01, 0.0));      // face on the goal line, post on the face
    QVERIFY(robotInsideField(f, kSide, hx + h, -g + h, 0.0));         // inside the goal, touching post and side wall
    QVERIFY(!robotInsideField(f, kSide, hx - 0.05, hy - 0.05, 0.0));  // a vertex in a corner triangle
    QVERIFY(robotInsideField(f, kSide, hx - 0.10, hy - 0.10, M_PI / 4));  // face flat on the triangle, clear
    // Face flat on the middle of the top right corner triangle's hypotenuse.
    const Eigen::Vector2d mid(hx - c / 2, hy - c / 2), out = Eigen::Vector2d(1, 1).normalized();
    const Eigen::Vector2d flat = mid - h * out;
    QVERIFY(robotInsideField(f, kSide, flat.x() - 1e-9, flat.y() - 1e-9, M_PI / 4));
    QVERIFY(!robotInsideField(f, kSide, flat.x() + 1e-6, flat.y() + 1e-6, M_PI / 4));
    QVERIFY(!robotInsideField(f, kSide, std::nan(""), 0.0, 0.0));
    // Discs.
    QVERIFY(discInsideField(f, kRadius, hx + 0.05, 0.0));
    QVERIFY(discInsideField(f, kRadius, hx + depth - kRadius, 0.0));  // touching the back wall
    QVERIFY(!discInsideField(f, kRadius, hx + depth - kRadius + 1e-6, 0.0));
    QVERIFY(
        discInsideField(f, kRadius, hx - kRadius * std::sqrt(0.5), -g + kRadius * std::sqrt(0.5)));  // touching a post
    QVERIFY(!discInsideField(f, kRadius, hx - 0.005, -g + 0.005));                                   // on a post
    QVERIFY(!discInsideField(f, kRadius, hx + 0.05, -g - 0.05));                                     // behind a post
    QVERIFY(!discInsideField(f, kRadius, hx - 0.03, hy - 0.03));  // in a corner triangle
    const Eigen::Vector2d disc = mid - kRadius * out;             // touching the hypotenuse
    QVERIFY(discInsideField(f, kRadius, disc.x() - 1e-9, disc.y() - 1e-9));
    QVERIFY(!discInsideField(f, kRadius, disc.x() + 1e-6, disc.y() + 1e-6));
}

void TestField::wallsPastAtAPostFollowTheCentre() {
    // A point inside the solid corner behind the post (0.75, -0.2), past both
    // the goal line's wall (2) and the goal's side wall (3): a body whose
    // centre is in the field came through the goal line, one in the goal
    // through the side wall, whichever is nearer.
    const Field f = official(FieldType::Vsss3v3);
    QCOMPARE(f.walls[2].b, Eigen::Vector2d(0.75, -0.2));
    QCOMPARE(f.walls[3].a, Eigen::Vector2d(0.75, -0.2));
    const Eigen::Vector2d p(0.752, -0.201);  // nearer the side wall
    QCOMPARE(wallsPast(f, p, {0.72, -0.23})[0], 2);
    QCOMPARE(wallsPast(f, p, {0.78, -0.17})[0], 3);
    QCOMPARE(wallsPast(f, p, p)[0], 3);  // nothing to tell: the nearest
    QCOMPARE(wallsPast(f, p, p)[1], -1);
    // A floor-facing corner (the back of the goal): past both walls.
    const std::array<int, 3> back = wallsPast(f, {0.851, -0.201}, {0.8, -0.15});
    QCOMPARE(back[0], 3);
    QCOMPARE(back[1], 4);
    // On the floor: nothing, even beyond the lines of walls far away.
    QCOMPARE(wallsPast(f, {0.8, 0.0}, {0.8, 0.0})[0], -1);
    QCOMPARE(wallsPast(f, {0.7, -0.3}, {0.7, -0.3})[0], -1);
}

void TestField::ballBouncesOffEveryWall() {
    // The ball sent at 1 m/s straight at the middle of every wall of both
    // official fields (from in front of it: inside the goal for the goals'
    // walls) comes back along the wall's normal, touching that wall only, and
    // never leaves the floor.
    for (FieldType type : {FieldType::Vsss3v3, FieldType::Vsss5v5})
        for (CollisionModel model : {CollisionModel::Paper, CollisionModel::Impulse}) {
            const Field f = official(type);
            for (int w = 0; w < static_cast<int>(f.walls.size()); ++w) {
                const Wall& wall = f.walls[w];
                const Eigen::Vector2d mid = 0.5 * (wall.a + wall.b);
                const Eigen::Vector2d start = mid + (kRadius + 0.02) * wall.normal;
                Scene scene = sceneOn(type, model);
                scene.ball.x = start.x(), scene.ball.y = start.y();
                scene.ball.vx = -wall.normal.x(), scene.ball.vy = -wall.normal.y();
                Simulation sim(scene);
                bool touched = false;
                for (int k = 0; k < 60; ++k) {
                    const BallState b = sim.state().ball;
                    std::vector<Contact> contacts;
                    const std::vector<RobotState> none;
                    const std::vector<double> sides;
                    BodiesView view{&none, &sides, &b, kRadius};
                    appendWallContacts(f, view, contacts);
                    for (const Contact& c : contacts) {
                        QVERIFY2(c.b.index == w, qPrintable(QString("%1: wall %2 touched aiming at %3")
                                                                .arg(modelName(model))
                                                                .arg(c.b.index)
                                                                .arg(w)));
                        touched = true;
                    }
                    touched = sim.step().contacts > 0 || touched;
                    QVERIFY(ballOffFloor(f, sim.state().ball, kRadius) < 1e-12);
                }
                const BallState& b = sim.state().ball;
                const Eigen::Vector2d v(b.vx, b.vy);
                QVERIFY2(touched, qPrintable(QString("wall %1").arg(w)));
                QVERIFY2(
                    v.dot(wall.normal) > 0.9 && std::abs(v.x() * wall.normal.y() - v.y() * wall.normal.x()) < 1e-9,
                    qPrintable(QString("%1, wall %2: the ball leaves at %3").arg(modelName(model)).arg(w).arg(str(v))));
            }
        }
}

void TestField::robotBouncesOffEveryWall() {
    // A robot coasting at 0.5 m/s face first into the middle of every wall
    // (the goals' walls from inside the goal, where it fits; the corner
    // triangles face on, the 7.5 cm face on their 9.9 cm hypotenuse) touches
    // that wall only, turns back, and never leaves the floor.
    for (FieldType type : {FieldType::Vsss3v3, FieldType::Vsss5v5})
        for (CollisionModel model : {CollisionModel::Paper, CollisionModel::Impulse}) {
            const Field f = official(type);
            for (int w = 0; w < static_cast<int>(f.walls.size()); ++w) {
                const Wall& wall = f.walls[w];
                const Eigen::Vector2d mid = 0.5 * (wall.a + wall.b);
                const Eigen::Vector2d start = mid + (kSide / 2 + 0.005) * wall.normal;
                Scene scene = sceneOn(type, model);
                const double heading = std::atan2(-wall.normal.y(), -wall.normal.x());
                scene.robots.push_back(test::robotAt("r", start.x(), start.y(), heading, 0.5));
                Simulation sim(scene);
                QVERIFY(robotInsideField(f, kSide, start.x(), start.y(), heading));
                bool touched = false;
                for (int k = 0; k < 80; ++k) {
                    std::vector<Contact> contacts;
                    const std::vector<RobotState> robots = sim.state().robots;
                    const std::vector<double> sides{kSide};
                    BodiesView view{&robots, &sides, nullptr, kRadius};
                    appendWallContacts(f, view, contacts);
                    for (const Contact& c : contacts) {
                        QVERIFY2(c.b.index == w, qPrintable(QString("%1: wall %2 touched aiming at %3")
                                                                .arg(modelName(model))
                                                                .arg(c.b.index)
                                                                .arg(w)));
                        QVERIFY(c.normal.dot(wall.normal) > 1.0 - 1e-12);
                        touched = true;
                    }
                    touched = sim.step().contacts > 0 || touched;
                    QVERIFY2(robotOffFloor(f, sim.state().robots[0], kSide) < 1e-12,
                             qPrintable(QString("wall %1, step %2").arg(w).arg(k)));
                }
                QVERIFY2(touched, qPrintable(QString("%1, wall %2: never touched").arg(modelName(model)).arg(w)));
                // Straight back along the wall's normal: no other wall touched.
                const RobotState& r = sim.state().robots[0];
                const Eigen::Vector2d moved = Eigen::Vector2d(r.x, r.y) - start;
                QVERIFY2(r.v < 0.0 && std::abs(r.theta - heading) < 1e-9 &&
                             std::abs(moved.x() * wall.normal.y() - moved.y() * wall.normal.x()) < 1e-9,
                         qPrintable(QString("%1, wall %2: v %3, turned %4, moved %5")
                                        .arg(modelName(model))
                                        .arg(w)
                                        .arg(r.v)
                                        .arg(r.theta - heading)
                                        .arg(str(moved))));
            }
        }
}

void TestField::bodiesAgainstThePosts() {
    const Field f = official(FieldType::Vsss3v3);
    const double hx = 0.75, g = 0.20, h = kSide / 2;
    // A robot face first against a post (the post in the middle of its
    // face): pushed straight back out along its heading.
    {
        const RobotState r = pose(hx - h + 0.002, -g, 0.0);
        std::vector<RobotState> robots{r};
        const std::vector<double> sides{kSide};
        std::vector<Contact> contacts;
        appendWallContacts(f, BodiesView{&robots, &sides, nullptr, kRadius}, contacts);
        QVERIFY(!contacts.empty());
        for (const Contact& c : contacts) {
            QVERIFY2(c.normal.isApprox(Eigen::Vector2d(-1, 0), 1e-12), qPrintable(str(c.normal)));
            QVERIFY(std::abs(c.depth - 0.002) < 1e-12);
        }
    }
    // A robot sliding up the goal line into the mouth: everything pushes it
    // back along -x, nothing pulls it into the goal or along y.
    // (1e-5 m into the wall, its front past the post by more than that.)
    for (double y : {-g - h + 0.0005, -g - h + 0.001, -g - 0.01, -g + 0.01}) {
        const RobotState r = pose(hx - h + 1e-5, y, M_PI / 2);
        std::vector<RobotState> robots{r};
        const std::vector<double> sides{kSide};
        std::vector<Contact> contacts;
        appendWallContacts(f, BodiesView{&robots, &sides, nullptr, kRadius}, contacts);
        QVERIFY2(!contacts.empty(), qPrintable(QString("y %1").arg(y)));
        for (const Contact& c : contacts)
            QVERIFY2(c.normal.isApprox(Eigen::Vector2d(-1, 0), 1e-12),
                     qPrintable(QString("y %1: normal %2 (wall %3)").arg(y).arg(str(c.normal)).arg(c.b.index)));
    }
    // A robot inside the goal pressing its side on the side wall next to the
    // post: pushed back along +y, into the goal, not out through the post.
    for (double x : {hx + h - 0.002, hx + h - 0.01, hx + h + 0.01}) {
        const RobotState r = pose(x, -g + h - 0.001, 0.0);
        std::vector<RobotState> robots{r};
        const std::vector<double> sides{kSide};
        std::vector<Contact> contacts;
        appendWallContacts(f, BodiesView{&robots, &sides, nullptr, kRadius}, contacts);
        QVERIFY(!contacts.empty());
        bool upward = false;
        for (const Contact& c : contacts) {
            QVERIFY2(c.normal.y() > -1e-12, qPrintable(QString("x %1: normal %2").arg(x).arg(str(c.normal))));
            upward = upward || c.normal.isApprox(Eigen::Vector2d(0, 1), 1e-12);
        }
        QVERIFY(upward);
    }
    // A vertex meeting a post from in front of the mouth, 1 mm into the solid
    // corner behind it, at several headings around the diagonal (found by
    // vssim stress: the vertex test against one wall and a push of the post
    // along a face disagreed and left the robot in the corner): one step
    // clears it, under both models.
    for (CollisionModel model : {CollisionModel::Paper, CollisionModel::Impulse})
        for (double tilt : {0.0, 0.2, -0.2, 0.6, -0.6}) {
            const Eigen::Vector2d post(hx, -g), into = Eigen::Vector2d(1, -1).normalized();
            const double towards = std::atan2(into.y(), into.x()) + tilt;  // the vertex's direction from the centre
            const Eigen::Vector2d vertex = post + 0.001 * into;
            const Eigen::Vector2d centre =
                vertex - (kSide / std::sqrt(2.0)) * Eigen::Vector2d(std::cos(towards), std::sin(towards));
            Scene scene = sceneOn(FieldType::Vsss3v3, model);
            // Vertex 0 lies at theta + 45° (model.md §5).
            scene.robots.push_back(test::robotAt("r", centre.x(), centre.y(), towards - M_PI / 4));
            Simulation sim(scene);
            QVERIFY(robotOffFloor(f, sim.state().robots[0], kSide) > 0.0005);
            sim.step();
            QVERIFY2(robotOffFloor(f, sim.state().robots[0], kSide) < 1e-12,
                     qPrintable(QString("%1, tilt %2: %3 m into the post's corner after a step")
                                    .arg(modelName(model))
                                    .arg(tilt)
                                    .arg(robotOffFloor(f, sim.state().robots[0], kSide))));
        }
    // The ball on a post touches it once, along the line from the post.
    {
        const Eigen::Vector2d post(hx, -g), dir = Eigen::Vector2d(-1, 1).normalized();
        BallState b;
        b.x = post.x() + (kRadius - 0.001) * dir.x(), b.y = post.y() + (kRadius - 0.001) * dir.y();
        const std::vector<RobotState> none;
        const std::vector<double> sides;
        std::vector<Contact> contacts;
        appendWallContacts(f, BodiesView{&none, &sides, &b, kRadius}, contacts);
        QCOMPARE(contacts.size(), std::size_t(1));
        QVERIFY(contacts[0].normal.isApprox(dir, 1e-12));
        QVERIFY(std::abs(contacts[0].depth - 0.001) < 1e-12);
    }
    // The ball wedged between a post and a robot pushing it: the robot
    // drives on for a second at full voltage, under both models; the ball
    // stays on the floor and out of the robot, and nothing becomes NaN.
    for (CollisionModel model : {CollisionModel::Paper, CollisionModel::Impulse})
        for (double angle : {0.0, 0.4, -0.4, 0.8}) {
            Scene scene = sceneOn(FieldType::Vsss3v3, model);
            const Eigen::Vector2d post(hx, -g), dir(-std::cos(angle), std::sin(angle));
            const Eigen::Vector2d ball = post + (kRadius + 1e-4) * dir, robot = ball + (kRadius + h + 0.003) * dir;
            scene.ball.x = ball.x(), scene.ball.y = ball.y();
            scene.robots.push_back(test::robotAt("r", robot.x(), robot.y(), std::atan2(-dir.y(), -dir.x()), 0.3));
            scene.commands.push_back({0.0, 0, {7.4, 7.4}});
            Simulation sim(scene);
            for (int k = 0; k < 1000; ++k) {
                sim.step();
                const WorldState& s = sim.state();
                QVERIFY(std::isfinite(s.ball.x) && std::isfinite(s.robots[0].x));
                QVERIFY2(ballOffFloor(f, s.ball, kRadius) < 1e-4,
                         qPrintable(QString("%1, angle %2, step %3: ball %4 m past the walls")
                                        .arg(modelName(model))
                                        .arg(angle)
                                        .arg(k)
                                        .arg(ballOffFloor(f, s.ball, kRadius))));
                QVERIFY(robotOffFloor(f, s.robots[0], kSide) < 1e-4);
                QVERIFY(onFloor(f, {s.ball.x, s.ball.y}));
            }
        }
}

void TestField::hiddenCornersAtTheBackOfTheGoal() {
    // The ball and a robot thrown diagonally into each back corner of each
    // goal: both walls push them out, they come back out of the corner, and
    // they never leave the floor.
    const Field f = official(FieldType::Vsss3v3);
    const double hx = 0.75, g = 0.20, depth = 0.10;
    for (CollisionModel model : {CollisionModel::Paper, CollisionModel::Impulse})
        for (double sx : {1.0, -1.0})
            for (double sy : {1.0, -1.0}) {
                const Eigen::Vector2d corner(sx * (hx + depth), sy * g);
                const Eigen::Vector2d in = Eigen::Vector2d(sx, sy).normalized();  // into the corner
                Scene scene = sceneOn(FieldType::Vsss3v3, model);
                const Eigen::Vector2d ball = corner - 0.045 * Eigen::Vector2d(sx, sy);
                scene.ball.x = ball.x(), scene.ball.y = ball.y(), scene.ball.vx = in.x(), scene.ball.vy = in.y();
                Simulation sim(scene);
                for (int k = 0; k < 100; ++k) {
                    sim.step();
                    QVERIFY(ballOffFloor(f, sim.state().ball, kRadius) < 1e-12);
                }
                const Eigen::Vector2d v(sim.state().ball.vx, sim.state().ball.vy);
                QVERIFY2(v.dot(in) < -0.9,
                         qPrintable(QString("%1: ball leaves the corner at %2").arg(modelName(model)).arg(str(v))));
                // A robot, vertex first into the corner, pushed on by its motors.
                Scene robotScene = sceneOn(FieldType::Vsss3v3, model);
                const Eigen::Vector2d robot = corner - 0.06 * Eigen::Vector2d(sx, sy);
                robotScene.robots.push_back(
                    test::robotAt("r", robot.x(), robot.y(), std::atan2(in.y(), in.x()) + 0.1, 0.5));
                robotScene.commands.push_back({0.0, 0, {5.0, 5.0}});
                Simulation robotSim(robotScene);
                QVERIFY(robotInsideField(f, kSide, robot.x(), robot.y(), std::atan2(in.y(), in.x()) + 0.1));
                for (int k = 0; k < 1000; ++k) {
                    robotSim.step();
                    QVERIFY2(robotOffFloor(f, robotSim.state().robots[0], kSide) < 1e-9,
                             qPrintable(QString("%1, corner %2: %3 m off the floor at step %4")
                                            .arg(modelName(model))
                                            .arg(str(corner))
                                            .arg(robotOffFloor(f, robotSim.state().robots[0], kSide))
                                            .arg(k)));
                }
                const RobotState& r = robotSim.state().robots[0];
                QVERIFY(std::abs(r.x) > hx);  // still in the goal, jammed in its corner
            }
}

void TestField::cornerTriangleJunctions() {
    // Where a corner triangle meets a wall the chain turns away from the
    // floor by 45°: a ball touching both touches each once, along its
    // normal; one pushed past both is pushed back by both (as in the box's
    // corners); balls and robots driven into each junction stay on the floor.
    const Field f = official(FieldType::Vsss3v3);
    const double hx = 0.75, hy = 0.65, c = 0.07;
    const Eigen::Vector2d junction(hx - c, -hy);  // bottom wall (0) meets the triangle (1)
    const Eigen::Vector2d n0 = f.walls[0].normal, n1 = f.walls[1].normal;
    QCOMPARE(f.walls[0].b, junction);
    const Eigen::Vector2d bisector = (n0 + n1).normalized();
    const double along = (kRadius - 0.001) / bisector.dot(n0);  // 1 mm into both
    const std::vector<RobotState> none;
    const std::vector<double> sides;
    for (double extra : {0.0, 0.03}) {  // 0.03: the centre beyond both lines, off the floor
        BallState b;
        const Eigen::Vector2d centre = junction + (along - extra) * bisector;
        b.x = centre.x(), b.y = centre.y();
        std::vector<Contact> contacts;
        appendWallContacts(f, BodiesView{&none, &sides, &b, kRadius}, contacts);
        QCOMPARE(contacts.size(), std::size_t(2));
        QCOMPARE(contacts[0].b.index, 0);
        QCOMPARE(contacts[1].b.index, 1);
        QVERIFY(contacts[0].normal.isApprox(n0, 1e-12) && contacts[1].normal.isApprox(n1, 1e-12));
    }
    int junctions = 0;
    for (CollisionModel model : {CollisionModel::Paper, CollisionModel::Impulse})
        for (int w = 0; w < 16; ++w) {
            // A foot of a triangle: c from a corner of the rectangle, along a side.
            const Eigen::Vector2d a = f.walls[w].a;
            const bool triangleEnd =
                std::abs(std::abs(std::abs(a.x()) - hx) + std::abs(std::abs(a.y()) - hy) - c) < 1e-12;
            if (!triangleEnd) continue;
            ++junctions;
            const Eigen::Vector2d p = f.walls[w].a;
            const Eigen::Vector2d in = (f.walls[w].normal + f.walls[(w + 15) % 16].normal).normalized();
            Scene scene = sceneOn(FieldType::Vsss3v3, model);
            const Eigen::Vector2d ball = p + 0.05 * in;
            scene.ball.x = ball.x(), scene.ball.y = ball.y(), scene.ball.vx = -3 * in.x(), scene.ball.vy = -3 * in.y();
            const Eigen::Vector2d robot = p + 0.15 * in;
            scene.robots.push_back(test::robotAt("r", robot.x(), robot.y(), std::atan2(-in.y(), -in.x()) + 0.3, 0.5));
            scene.commands.push_back({0.0, 0, {6.0, 5.0}});
            Simulation sim(scene);
            for (int k = 0; k < 1500; ++k) {
                sim.step();
                QVERIFY2(ballOffFloor(f, sim.state().ball, kRadius) < 1e-12 &&
                             robotOffFloor(f, sim.state().robots[0], kSide) < 1e-9,
                         qPrintable(QString("%1, junction %2, step %3").arg(modelName(model)).arg(str(p)).arg(k)));
            }
        }
    QCOMPARE(junctions, 2 * 8);
}

void TestField::ballRollsIntoTheGoalAndStopsAtTheBackWall() {
    // Rolled from the centre spot into the right goal: it crosses the goal
    // line, and the back wall stops it. Inelastic (impulse, e = 0): it stays
    // against the back wall; elastic (paper): it comes back out of the goal.
    const Field f = official(FieldType::Vsss3v3);
    const double back = 0.75 + 0.10 - kRadius;
    for (CollisionModel model : {CollisionModel::Paper, CollisionModel::Impulse}) {
        Scene scene = sceneOn(FieldType::Vsss3v3, model);
        scene.simulation.restitution = 0.0;
        scene.ball.vx = 2.0, scene.ball.vy = 0.3;
        Simulation sim(scene);
        double farthest = 0.0;
        bool cameBack = false;
        for (int k = 0; k < 3000; ++k) {
            sim.step();
            const BallState& b = sim.state().ball;
            farthest = std::max(farthest, b.x);
            cameBack = cameBack || (farthest > 0.8 && b.x < 0.75 && b.vx < 0.0);
            QVERIFY(ballOffFloor(f, b, kRadius) < 1e-12);
        }
        const BallState& b = sim.state().ball;
        QVERIFY2(std::abs(farthest - back) < 1e-9,
                 qPrintable(QString("reached x = %1, back wall at %2").arg(farthest).arg(back)));
        if (model == CollisionModel::Impulse) {
            QVERIFY2(std::abs(b.x - back) < 1e-9 && std::abs(b.vx) < 1e-12,
                     qPrintable(QString("ball at x %1, vx %2").arg(b.x).arg(b.vx)));
            QVERIFY(std::abs(b.y) <= 0.2 - kRadius + 1e-9);  // in the goal (it rolls on into a back corner)
        } else {
            QVERIFY(cameBack);  // bounced back out
        }
    }
}

void TestField::robotDrivesIntoTheGoal() {
    // A 7.5 cm robot fits in the 10 cm deep, 40 cm wide goal: driven straight
    // in, it crosses the goal line without touching a post and is stopped by
    // the back wall, inside the goal.
    const Field f = official(FieldType::Vsss3v3);
    for (CollisionModel model : {CollisionModel::Paper, CollisionModel::Impulse})
        for (double y : {0.0, 0.1, -0.15}) {
            Scene scene = sceneOn(FieldType::Vsss3v3, model);
            scene.ball.x = -0.3;
            scene.robots.push_back(test::robotAt("r", 0.45, y, 0.0));
            scene.commands.push_back({0.0, 0, {3.0, 3.0}});
            scene.commands.push_back({1.5, 0, {0.0, 0.0}});
            Simulation sim(scene);
            for (int k = 0; k < 2500; ++k) {
                sim.step();
                QVERIFY2(robotOffFloor(f, sim.state().robots[0], kSide) < 1e-12,
                         qPrintable(QString("y %1, step %2").arg(y).arg(k)));
            }
            const RobotState& r = sim.state().robots[0];
            QVERIFY2(r.x > 0.75 + kSide / 2 && r.x <= 0.85 - kSide / 2 + 1e-12,
                     qPrintable(QString("%1, y %2: robot at x %3").arg(modelName(model)).arg(y).arg(r.x)));
            QVERIFY(robotInsideField(f, kSide, r.x, r.y, r.theta));
            QVERIFY2(
                std::abs(r.y - y) < 0.01,
                qPrintable(
                    QString("%1, y %2: robot at %3, heading %4").arg(modelName(model)).arg(y).arg(r.y).arg(r.theta)));
        }
}

void TestField::impulseModelCreatesNoEnergyAgainstTheWalls() {
    // Random robots and balls overlapping random walls and posts of the
    // official field, with random velocities: each contact's response leaves
    // the kinetic energy no higher (e = 1: equal to rounding; e < 1: lower).
    const Field f = official(FieldType::Vsss3v3);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0), angle(-M_PI, M_PI), speed(-2.0, 2.0), yaw(-30.0, 30.0);
    const RobotModel robotModel = makeRobotModel(RobotParams{});
    const std::vector<RobotModel> models{robotModel};
    const BallParams ballParams;
    int responses = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        // Near a random point of a random wall, or a post.
        const Wall& wall = f.walls[rng() % f.walls.size()];
        const Eigen::Vector2d near =
            trial % 4 == 0 ? f.posts[rng() % f.posts.size()] : Eigen::Vector2d(wall.a + unit(rng) * (wall.b - wall.a));
        const Eigen::Vector2d offset(0.04 * (2 * unit(rng) - 1), 0.04 * (2 * unit(rng) - 1));
        std::vector<RobotState> robots{pose(near.x() + offset.x(), near.y() + offset.y(), angle(rng), speed(rng))};
        robots[0].omega = yaw(rng);
        BallState ball;
        ball.x = near.x() - offset.y(), ball.y = near.y() + offset.x(), ball.vx = speed(rng), ball.vy = speed(rng);
        const std::vector<double> sides{kSide};
        std::vector<Contact> contacts;
        appendWallContacts(f, BodiesView{&robots, &sides, &ball, kRadius}, contacts);
        const double e = trial % 3 == 0 ? 1.0 : unit(rng);
        Bodies bodies{&robots, &models, &ball, &ballParams};
        for (const Contact& c : contacts) {
            QVERIFY(std::abs(c.normal.norm() - 1.0) < 1e-12 && c.depth >= 0.0);
            const double before = kineticEnergy(bodies);
            if (respondToContact(c, bodies, CollisionModel::Impulse, e)) ++responses;
            const double after = kineticEnergy(bodies);
            QVERIFY2(after <= before * (1.0 + 1e-12) + 1e-15,
                     qPrintable(QString("trial %1, wall %2, e %3: %4 J -> %5 J")
                                    .arg(trial)
                                    .arg(c.b.index)
                                    .arg(e)
                                    .arg(before)
                                    .arg(after)));
            if (e == 1.0) QVERIFY(std::abs(after - before) <= 1e-12 * before + 1e-15);
        }
    }
    QVERIFY(responses > 1000);
}

void TestField::noBodyEverEndsOffTheFloor() {
    // Many robots (as many as fit, 20) and the ball on the official 3 vs 3
    // field with random voltages, under both models and all integrators:
    // after every step, no vertex off the floor, no post inside a robot and
    // the ball within its radius of the floor, beyond the separation
    // tolerance of jams (world.cpp: 1e-4 m).
    for (std::uint32_t seed = 1; seed <= 6; ++seed) {
        std::mt19937 rng(seed);
        Scene scene = sceneOn(seed % 2 ? FieldType::Vsss3v3 : FieldType::Vsss5v5,
                              seed % 3 == 0 ? CollisionModel::Impulse : CollisionModel::Paper);
        scene.simulation.integrator = seed % 2 ? Integrator::Rk4 : Integrator::Exact;
        scene.simulation.restitution = 0.5;
        const Field& f = scene.field;
        std::uniform_real_distribution<double> x(f.lower.x(), f.upper.x()), y(f.lower.y(), f.upper.y()),
            angle(-M_PI, M_PI), volt(-7.4, 7.4), speed(-1.5, 1.5);
        while (scene.robots.size() < 20) {
            const double px = x(rng), py = y(rng), th = angle(rng);
            if (!robotInsideField(f, kSide, px, py, th)) continue;
            RobotSpec r = test::robotAt("r", px, py, th, speed(rng));
            r.name = "r" + std::to_string(scene.robots.size());
            scene.robots.push_back(r);
        }
        scene.ball.x = 0.8 * (seed % 2 ? 0.75 : 1.1), scene.ball.y = 0.0, scene.ball.vx = 3.0;
        for (int k = 0; k < 40; ++k)
            for (int i = 0; i < 20; ++i) scene.commands.push_back({0.05 * k, i, {volt(rng), volt(rng)}});
        Simulation sim(scene);
        double worst = 0.0;
        for (int k = 0; k < 2000; ++k) {
            sim.step();
            const WorldState& s = sim.state();
            for (const RobotState& r : s.robots) {
                QVERIFY(std::isfinite(r.x) && std::isfinite(r.y) && std::isfinite(r.theta));
                QVERIFY(onFloor(f, {r.x, r.y}));
                worst = std::max(worst, robotOffFloor(f, r, kSide));
            }
            QVERIFY(onFloor(f, {s.ball.x, s.ball.y}));
            worst = std::max(worst, ballOffFloor(f, s.ball, kRadius));
        }
        QVERIFY2(worst < 1e-4, qPrintable(QString("seed %1: %2 m off the floor").arg(seed).arg(worst)));
    }
}

void TestField::longStepsAgreeWithStepsNearTheGoals() {
    // As test_skipping's longStepsAgreeWithFixedSteps, on the official field
    // with the robots and the ball around a goal and in it: advanceTo with
    // long steps agrees with step() to rounding at every sample (with the
    // contacts on the grid as step() has them; at their time of impact they
    // come earlier: tests/test_time_of_impact.cpp).
    for (std::uint32_t seed = 1; seed <= 8; ++seed) {
        std::mt19937 rng(seed);
        Scene scene = sceneOn(FieldType::Vsss3v3, seed % 2 ? CollisionModel::Paper : CollisionModel::Impulse);
        scene.simulation.integrator = Integrator::Exact;
        scene.simulation.time_of_impact = false;
        const Field& f = scene.field;
        std::uniform_real_distribution<double> x(0.45, 0.85), y(-0.45, 0.45), angle(-M_PI, M_PI), volt(-7.4, 7.4),
            speed(-1.0, 1.0);
        while (scene.robots.size() < 4) {
            const double px = x(rng), py = y(rng), th = angle(rng);
            if (!robotInsideField(f, kSide, px, py, th)) continue;
            RobotSpec r = test::robotAt("r", px, py, th, speed(rng));
            r.name = "r" + std::to_string(scene.robots.size());
            scene.robots.push_back(r);
        }
        scene.ball.x = 0.5, scene.ball.y = 0.1 * (seed % 3), scene.ball.vx = 1.5, scene.ball.vy = speed(rng);
        for (int k = 0; k < 34; ++k)
            for (int i = 0; i < 4; ++i) scene.commands.push_back({0.03 * k, i, {volt(rng), volt(rng)}});
        Simulation longSteps(scene), reference(scene);
        std::int64_t contacts = 0, taken = 0;
        for (std::int64_t sample = 1; sample <= 20; ++sample) {
            taken += longSteps.advanceTo(sample * 50).longSteps;
            while (reference.state().step < sample * 50) contacts += reference.step().contacts;
            const WorldState &a = longSteps.state(), &b = reference.state();
            double diff = std::max(std::abs(a.ball.x - b.ball.x), std::abs(a.ball.y - b.ball.y));
            for (std::size_t i = 0; i < a.robots.size(); ++i)
                diff = std::max({diff, std::abs(a.robots[i].x - b.robots[i].x), std::abs(a.robots[i].y - b.robots[i].y),
                                 0.05 * std::abs(a.robots[i].theta - b.robots[i].theta)});
            QVERIFY2(diff < 1e-9, qPrintable(QString("seed %1, t=%2: %3 m apart").arg(seed).arg(b.time).arg(diff)));
        }
        QVERIFY(contacts > 0);
        QVERIFY(taken > 0);
    }
}

void TestField::freeBodiesNearPostsReallyAreFree() {
    // A body that findFreeBodies declares free for a horizon, around the
    // posts and in the goals, does not touch any wall over that horizon when
    // stepped finely (alone, RK4 at 0.1 ms, its voltages held): the test is
    // conservative near the chain's corners too.
    const Field f = official(FieldType::Vsss3v3);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> x(0.55, 0.85), y(-0.4, 0.4), angle(-M_PI, M_PI), volt(-7.4, 7.4),
        speed(-1.5, 1.5), yaw(-15.0, 15.0), horizon(0.005, 0.1);
    int freeRobots = 0, freeBalls = 0;
    for (int trial = 0; trial < 600; ++trial) {
        Scene scene = sceneOn(FieldType::Vsss3v3, CollisionModel::Paper);
        scene.simulation.integrator = Integrator::Exact;
        double px, py, th;
        do px = x(rng), py = y(rng), th = angle(rng);
        while (!robotInsideField(f, kSide, px, py, th));
        RobotSpec r = test::robotAt("r", px, py, th, speed(rng));
        r.initial.omega = yaw(rng);
        scene.robots.push_back(r);
        do scene.ball.x = x(rng), scene.ball.y = y(rng);
        while (!discInsideField(f, kRadius, scene.ball.x, scene.ball.y) ||
               std::hypot(scene.ball.x - px, scene.ball.y - py) < 0.08);
        scene.ball.vx = 2 * speed(rng), scene.ball.vy = 2 * speed(rng);
        scene.commands.push_back({0.0, 0, {volt(rng), volt(rng)}});
        const double h = horizon(rng);
        Simulation sim(scene);
        sim.step();  // applies the voltages
        FreeBodies free;
        findFreeBodies(sim.model(), sim.state(), h, free);
        freeRobots += free.robots[0] != 0;
        freeBalls += free.ball;
        // Each body alone (the other far away at the centre, at rest), finely.
        for (int body = 0; body < 2; ++body) {
            if (body == 0 ? !free.robots[0] : !free.ball) continue;
            Scene alone = scene;
            alone.simulation.integrator = Integrator::Rk4;
            alone.simulation.dt = 1e-4;
            alone.commands.clear();
            alone.commands.push_back({0.0, 0, sim.state().voltages[0]});
            alone.robots[0].initial = sim.state().robots[0];
            alone.ball = sim.state().ball;
            if (body == 0)
                alone.ball = BallState{};
            else
                alone.robots[0].initial = pose(0.0, 0.0, 0.0), alone.commands.clear();
            Simulation fine(alone);
            const std::vector<double> sides{kSide};
            for (int k = 0; k * 1e-4 <= h; ++k) {
                std::vector<Contact> contacts;
                const std::vector<RobotState> robots = fine.state().robots;
                const BallState ball = fine.state().ball;
                appendWallContacts(f, BodiesView{&robots, &sides, &ball, kRadius}, contacts);
                QVERIFY2(contacts.empty(),
                         qPrintable(QString("trial %1: the %2 declared free for %3 s touches wall %4 at %5 s")
                                        .arg(trial)
                                        .arg(body == 0 ? "robot" : "ball")
                                        .arg(h)
                                        .arg(contacts.empty() ? -1 : contacts[0].b.index)
                                        .arg(k * 1e-4)));
                fine.step();
            }
        }
    }
    qInfo("%d robots and %d balls declared free in 600 trials", freeRobots, freeBalls);
    QVERIFY(freeRobots > 100 && freeBalls > 100);
}

QTEST_APPLESS_MAIN(TestField)
#include "test_field.moc"
