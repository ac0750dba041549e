// Geometry and collision detection (model.md §5): the robot's vertices, the
// closest point on a segment (paper eqs. 10-11), the point-in-robot test, the
// separating-axis test of two squares (including the cases the paper drops),
// and the contacts against walls and the ball, each against a closed form or
// an independent computation written here.
#include <QtTest>

#include <random>

#include "test_support.h"
#include "vssim/collision_detect.h"
#include "vssim/field.h"
#include "vssim/geometry.h"

using namespace vssim;

namespace {

constexpr double kSide = 0.075;      // default robot side, m
constexpr double kRadius = 0.02135;  // default ball radius, m

RobotState pose(double x, double y, double theta) {
    RobotState r;
    r.x = x;
    r.y = y;
    r.theta = theta;
    return r;
}

// Rotation by theta, written out independently of the engine.
Eigen::Vector2d rotate(double theta, const Eigen::Vector2d& p) {
    return {std::cos(theta) * p.x() - std::sin(theta) * p.y(), std::sin(theta) * p.x() + std::cos(theta) * p.y()};
}

// A point given in a robot's frame (x forward, y left), in the field frame.
Eigen::Vector2d worldPoint(const RobotState& r, double forward, double left) {
    return Eigen::Vector2d(r.x, r.y) + rotate(r.theta, Eigen::Vector2d(forward, left));
}

bool close(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double tol) { return (a - b).norm() <= tol; }

QString str(const Eigen::Vector2d& v) { return QString("(%1, %2)").arg(v.x(), 0, 'g', 17).arg(v.y(), 0, 'g', 17); }

// Independent overlap test of two squares (interiors): a vertex of one
// strictly inside the other, or two edges crossing properly. Exact ties
// (touching) have probability zero in random trials.
bool strictlyInside(const RobotState& r, double side, const Eigen::Vector2d& p) {
    const Eigen::Vector2d d = rotate(-r.theta, p - Eigen::Vector2d(r.x, r.y));
    return std::abs(d.x()) < side / 2 && std::abs(d.y()) < side / 2;
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

bool segmentsCross(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r,
                   const Eigen::Vector2d& s) {
    const double d1 = cross(q - p, r - p), d2 = cross(q - p, s - p);
    const double d3 = cross(s - r, p - r), d4 = cross(s - r, q - r);
    return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}

std::array<Eigen::Vector2d, 4> corners(const RobotState& r, double side) {
    std::array<Eigen::Vector2d, 4> c;
    for (int j = 0; j < 4; ++j) {
        const double a = r.theta + M_PI / 4 + j * M_PI / 2;
        c[j] = Eigen::Vector2d(r.x, r.y) + side / std::sqrt(2.0) * Eigen::Vector2d(std::cos(a), std::sin(a));
    }
    return c;
}

bool bruteForceOverlap(const RobotState& a, double sideA, const RobotState& b, double sideB) {
    const auto ca = corners(a, sideA), cb = corners(b, sideB);
    for (const auto& v : ca)
        if (strictlyInside(b, sideB, v)) return true;
    for (const auto& v : cb)
        if (strictlyInside(a, sideA, v)) return true;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (segmentsCross(ca[i], ca[(i + 1) % 4], cb[j], cb[(j + 1) % 4])) return true;
    return false;
}

RobotState shifted(RobotState r, const Eigen::Vector2d& by) {
    r.x += by.x();
    r.y += by.y();
    return r;
}

}  // namespace

class TestGeometry : public QObject {
    Q_OBJECT
private slots:
    void cosSinAgainstLongDouble();
    void robotVerticesMatchFormula_data();
    void robotVerticesMatchFormula();
    void closestPointOnSegment_data();
    void closestPointOnSegment();
    void closestPointOnDegenerateSegment();
    void pointInRobot_data();
    void pointInRobot();
    void robotFrameRoundTrip();
    void squaresSeparated_data();
    void squaresSeparated();
    void squaresOverlapAxisAligned_data();
    void squaresOverlapAxisAligned();
    void squareOverlapIsMinimalTranslation();
    void squareOverlapMatchesBruteForce();
    void robotsFaceToFace_data();
    void robotsFaceToFace();
    void robotsFaceToVertexAt45Degrees_data();
    void robotsFaceToVertexAt45Degrees();
    void robotsCrossedNoVertexInside_data();
    void robotsCrossedNoVertexInside();
    void robotTiltedAgainstBottomWall_data();
    void robotTiltedAgainstBottomWall();
    void robotFlatOnWallTouchesAtFaceMiddle();
    void robotClearOfWall();
    void ballTouchingWall_data();
    void ballTouchingWall();
    void ballAtEndOfWallSegment();
    void ballTouchingRobotFace_data();
    void ballTouchingRobotFace();
    void ballTouchingRobotCorner_data();
    void ballTouchingRobotCorner();
    void ballCentreInsideRobot();
};

// ---------------------------------------------------------------- vertices

// The engine's own sine and cosine against the C library's long double
// ones, in units in the last place of the exact value (an ulp of the
// value, at least an ulp of 2^-60: the reduction's error is absolute): over
// many decades of angles up to 1e6 rad, next to every quarter turn, and the
// special values.
void TestGeometry::cosSinAgainstLongDouble() {
    std::mt19937_64 rng(7);
    double worst = 0.0, worstAngle = 0.0;
    auto ulpsOff = [](double got, long double exact) {
        const double rounded = static_cast<double>(exact);
        const double ulp = std::max(std::abs(std::nextafter(rounded, INFINITY) - rounded), std::ldexp(1.0, -60));
        return static_cast<double>(std::fabs(static_cast<long double>(got) - exact)) / ulp;
    };
    auto check = [&](double angle) {
        const CosSin r = cosSin(angle);
        const double off = std::max(ulpsOff(r.s, sinl(angle)), ulpsOff(r.c, cosl(angle)));
        if (off > worst) worst = off, worstAngle = angle;
    };
    std::uniform_real_distribution<double> unit(-1.0, 1.0), decade(-15.0, 6.0);
    for (int i = 0; i < 1000000; ++i) check(unit(rng) * std::pow(10.0, decade(rng)));
    for (int k = -20000; k <= 20000; ++k) {
        const double quarter = k * (M_PI / 4);
        check(quarter);
        check(std::nextafter(quarter, INFINITY));
        check(std::nextafter(quarter, -INFINITY));
    }
    QVERIFY2(worst <= 2.5, qPrintable(QString("%1 ulps at %2").arg(worst).arg(worstAngle, 0, 'g', 17)));
    // The series alone, over its whole range and on both sides of where it
    // takes fewer terms (|d| = 0.2): within an ulp (0.73 measured).
    worst = 0.0;
    std::uniform_real_distribution<double> nearZero(-M_PI / 4, M_PI / 4), nearSwitch(0.19, 0.21);
    for (int i = 0; i < 400000; ++i) {
        const double d = i % 2 ? nearZero(rng) : (i % 4 ? 1.0 : -1.0) * nearSwitch(rng);
        double s, c;
        sinCosNearZero(d, s, c);
        const double off = std::max(ulpsOff(s, sinl(d)), ulpsOff(c, cosl(d)));
        if (off > worst) worst = off, worstAngle = d;
    }
    QVERIFY2(worst <= 1.0, qPrintable(QString("series: %1 ulps at %2").arg(worst).arg(worstAngle, 0, 'g', 17)));
    // Exact where the values are exact (the sign of a zero sine is not
    // kept), and odd and even as sine and cosine are.
    QCOMPARE(cosSin(0.0).c, 1.0);
    QCOMPARE(cosSin(0.0).s, 0.0);
    for (double a : {0.3, 2.0, 4.0, 1234.5}) {
        QCOMPARE(cosSin(-a).s, -cosSin(a).s);
        QCOMPARE(cosSin(-a).c, cosSin(a).c);
    }
    // Past the reduction's range the C library's; NaN for NaN and infinities.
    QCOMPARE(cosSin(1e7).s, std::sin(1e7));
    QVERIFY(std::abs(cosSin(1e6).s - std::sin(1e6)) < 1e-15);  // continuous at the switch
    QCOMPARE(cosSin(-3e300).c, std::cos(-3e300));
    for (double bad : {NAN, INFINITY, -INFINITY}) {
        QVERIFY(std::isnan(cosSin(bad).s));
        QVERIFY(std::isnan(cosSin(bad).c));
    }
}

void TestGeometry::robotVerticesMatchFormula_data() {
    QTest::addColumn<double>("x");
    QTest::addColumn<double>("y");
    QTest::addColumn<double>("theta");
    QTest::addColumn<double>("side");
    QTest::newRow("origin, heading 0") << 0.0 << 0.0 << 0.0 << kSide;
    QTest::newRow("offset, 30deg") << 0.31 << -0.2 << M_PI / 6 << kSide;
    QTest::newRow("negative heading") << -0.6 << 0.5 << -2.1 << kSide;
    QTest::newRow("large heading") << 0.7 << 0.6 << 17.3 << kSide;
    QTest::newRow("45deg, other side") << -0.1 << 0.05 << M_PI / 4 << 0.05;
    QTest::newRow("heading pi") << 0.2 << 0.2 << M_PI << 0.09;
}

void TestGeometry::robotVerticesMatchFormula() {
    QFETCH(double, x);
    QFETCH(double, y);
    QFETCH(double, theta);
    QFETCH(double, side);
    const auto v = robotVertices(pose(x, y, theta), side);
    for (int j = 0; j < 4; ++j) {
        const double a = theta + M_PI / 4 + M_PI / 2 * j;
        const Eigen::Vector2d want(x + side / std::sqrt(2.0) * std::cos(a), y + side / std::sqrt(2.0) * std::sin(a));
        QVERIFY2(close(v[j], want, 1e-14), qPrintable(QString("vertex %1: %2 vs %3").arg(j).arg(str(v[j]), str(want))));
        // A square: adjacent vertices one side apart, opposite ones a diagonal apart.
        QVERIFY(std::abs((v[j] - v[(j + 1) % 4]).norm() - side) < 1e-14);
        QVERIFY(std::abs((v[j] - v[(j + 2) % 4]).norm() - side * std::sqrt(2.0)) < 1e-14);
    }
}

// ---------------------------------------------------------------- segments

void TestGeometry::closestPointOnSegment_data() {
    // p = a + tau (b - a) + off * unit normal; the closed form is
    // lambda = clamp(tau, 0, 1), distance = hypot((tau - lambda) |b - a|, off).
    QTest::addColumn<double>("ax");
    QTest::addColumn<double>("ay");
    QTest::addColumn<double>("bx");
    QTest::addColumn<double>("by");
    QTest::addColumn<double>("tau");
    QTest::addColumn<double>("off");
    QTest::newRow("inside, above") << 0.0 << 0.0 << 2.0 << 0.0 << 0.25 << 1.0;
    QTest::newRow("inside, below") << 0.0 << 0.0 << 2.0 << 0.0 << 0.75 << -0.3;
    QTest::newRow("inside, on the segment") << -0.1 << 0.2 << 0.3 << -0.4 << 0.4 << 0.0;
    QTest::newRow("inside, slanted") << 0.1 << -0.2 << -0.3 << 0.5 << 0.6 << 0.07;
    QTest::newRow("before the start") << 0.1 << -0.2 << -0.3 << 0.5 << -0.4 << 0.07;
    QTest::newRow("before the start, on the line") << 0.0 << 0.0 << 1.0 << 1.0 << -0.5 << 0.0;
    QTest::newRow("past the end") << 0.1 << -0.2 << -0.3 << 0.5 << 1.3 << -0.02;
    QTest::newRow("past the end, on the line") << 0.0 << 0.0 << 0.0 << -1.0 << 2.0 << 0.0;
    QTest::newRow("just inside the start") << 0.0 << 0.0 << 1.0 << 0.0 << 1e-9 << 0.5;
    QTest::newRow("just inside the end") << 0.0 << 0.0 << 1.0 << 0.0 << 1.0 - 1e-9 << 0.5;
}

void TestGeometry::closestPointOnSegment() {
    QFETCH(double, ax);
    QFETCH(double, ay);
    QFETCH(double, bx);
    QFETCH(double, by);
    QFETCH(double, tau);
    QFETCH(double, off);
    const Eigen::Vector2d a(ax, ay), b(bx, by);
    const double len = (b - a).norm();
    const Eigen::Vector2d unit = (b - a) / len, normal(-unit.y(), unit.x());
    const Eigen::Vector2d p = a + tau * (b - a) + off * normal;
    const double lambda = std::clamp(tau, 0.0, 1.0);
    const Eigen::Vector2d point = a + lambda * (b - a);
    const double distance = std::hypot((tau - lambda) * len, off);

    const SegmentClosestPoint q = vssim::closestPointOnSegment(a, b, p);
    QVERIFY2(std::abs(q.lambda - lambda) < 1e-12, qPrintable(QString("lambda %1 vs %2").arg(q.lambda).arg(lambda)));
    QVERIFY2(close(q.point, point, 1e-12), qPrintable(str(q.point) + " vs " + str(point)));
    QVERIFY2(std::abs(q.distance - distance) < 1e-12,
             qPrintable(QString("distance %1 vs %2").arg(q.distance).arg(distance)));
    QVERIFY(q.lambda >= 0.0 && q.lambda <= 1.0);
    if (tau <= 0.0) QCOMPARE(q.lambda, 0.0);  // clamped exactly to the ends
    if (tau >= 1.0) QCOMPARE(q.lambda, 1.0);
}

void TestGeometry::closestPointOnDegenerateSegment() {
    // A zero-length segment is a point: lambda 0, the point itself, the plain distance.
    const Eigen::Vector2d a(0.3, -0.2), p(0.6, 0.2);
    const SegmentClosestPoint q = vssim::closestPointOnSegment(a, a, p);
    QVERIFY(std::isfinite(q.lambda) && std::isfinite(q.distance));
    QCOMPARE(q.lambda, 0.0);
    QVERIFY(close(q.point, a, 0.0));
    QVERIFY(std::abs(q.distance - 0.5) < 1e-15);  // a 3-4-5 triangle scaled by 0.1
    const SegmentClosestPoint same = vssim::closestPointOnSegment(a, a, a);
    QCOMPARE(same.distance, 0.0);
}

// ---------------------------------------------------------------- point in robot

void TestGeometry::pointInRobot_data() {
    // The point is given in the robot's own frame (forward, left) and placed
    // in the field with an independent rotation.
    QTest::addColumn<double>("theta");
    QTest::addColumn<double>("forward");
    QTest::addColumn<double>("left");
    QTest::addColumn<double>("margin");
    QTest::addColumn<bool>("inside");
    const double h = kSide / 2;
    for (double theta : {0.0, 0.7, -2.4}) {
        const QByteArray t = QByteArray::number(theta);
        QTest::newRow("centre " + t) << theta << 0.0 << 0.0 << 0.0 << true;
        QTest::newRow("just inside front " + t) << theta << h - 1e-9 << 0.3 * h << 0.0 << true;
        QTest::newRow("just outside front " + t) << theta << h + 1e-9 << 0.3 * h << 0.0 << false;
        QTest::newRow("just inside left " + t) << theta << -0.8 * h << h - 1e-9 << 0.0 << true;
        QTest::newRow("just outside right " + t) << theta << -0.8 * h << -h - 1e-9 << 0.0 << false;
        QTest::newRow("just inside corner " + t) << theta << -h + 1e-9 << -h + 1e-9 << 0.0 << true;
        QTest::newRow("just outside corner " + t) << theta << h + 1e-9 << h - 1e-9 << 0.0 << false;
        QTest::newRow("outside, within margin " + t) << theta << h + 2e-3 << 0.0 << 3e-3 << true;
        QTest::newRow("outside, beyond margin " + t) << theta << h + 4e-3 << 0.0 << 3e-3 << false;
        QTest::newRow("corner, within margin " + t) << theta << -h - 1e-3 << h + 1e-3 << 1.5e-3 << true;
    }
}

void TestGeometry::pointInRobot() {
    QFETCH(double, theta);
    QFETCH(double, forward);
    QFETCH(double, left);
    QFETCH(double, margin);
    QFETCH(bool, inside);
    const RobotState r = pose(0.21, -0.13, theta);
    QCOMPARE(vssim::pointInRobot(r, kSide, worldPoint(r, forward, left), margin), inside);
}

void TestGeometry::robotFrameRoundTrip() {
    std::mt19937 rng(20240601);
    std::uniform_real_distribution<double> pos(-0.7, 0.7), angle(-10.0, 10.0);
    for (int k = 0; k < 1000; ++k) {
        const RobotState r = pose(pos(rng), pos(rng), angle(rng));
        const Eigen::Vector2d p(pos(rng), pos(rng));
        const Eigen::Vector2d local = toRobotFrame(r, p);
        // Independent: rotate the offset by -theta.
        const Eigen::Vector2d want = rotate(-r.theta, p - Eigen::Vector2d(r.x, r.y));
        QVERIFY2(close(local, want, 1e-14), qPrintable(str(local) + " vs " + str(want)));
        QVERIFY(close(fromRobotFrame(r, local), p, 1e-14));
        QVERIFY(close(toRobotFrame(r, fromRobotFrame(r, p)), p, 1e-14));
        // The forward axis of the frame is the heading.
        const Eigen::Vector2d ahead = fromRobotFrame(r, Eigen::Vector2d(1.0, 0.0)) - Eigen::Vector2d(r.x, r.y);
        QVERIFY(close(ahead, Eigen::Vector2d(std::cos(r.theta), std::sin(r.theta)), 1e-14));
        const Eigen::Vector2d leftward = fromRobotFrame(r, Eigen::Vector2d(0.0, 1.0)) - Eigen::Vector2d(r.x, r.y);
        QVERIFY(close(leftward, Eigen::Vector2d(-std::sin(r.theta), std::cos(r.theta)), 1e-14));
    }
}

// ---------------------------------------------------------------- separating axes

void TestGeometry::squaresSeparated_data() {
    QTest::addColumn<double>("bx");
    QTest::addColumn<double>("by");
    QTest::addColumn<double>("btheta");
    QTest::addColumn<double>("atheta");
    // A at the origin.
    QTest::newRow("side by side, 1 mm gap") << kSide + 1e-3 << 0.0 << 0.0 << 0.0;
    QTest::newRow("diagonal, gap on y") << 0.05 << -(kSide + 1e-4) << 0.0 << 0.0;
    // B at 45deg: its reach along x is the half diagonal.
    QTest::newRow("45deg vertex 1 mm short of the face")
        << kSide / 2 + kSide / std::sqrt(2.0) + 1e-3 << 0.0 << M_PI / 4 << 0.0;
    // Both at 45deg, corner to corner along x: half diagonals add up.
    QTest::newRow("corner to corner") << kSide * std::sqrt(2.0) + 1e-6 << 0.0 << M_PI / 4 << M_PI / 4;
    // Only an axis of B separates: the projections on both of A's axes overlap.
    QTest::newRow("separated by B's axis only") << 0.0679 << 0.0679 << M_PI / 4 << 0.0;
    QTest::newRow("far away") << 0.5 << 0.3 << 1.0 << -2.0;
}

void TestGeometry::squaresSeparated() {
    QFETCH(double, bx);
    QFETCH(double, by);
    QFETCH(double, btheta);
    QFETCH(double, atheta);
    const RobotState a = pose(0.0, 0.0, atheta), b = pose(bx, by, btheta);
    QVERIFY(!bruteForceOverlap(a, kSide, b, kSide));  // the premise, checked independently
    QVERIFY(!squareOverlap(a, kSide, b, kSide).overlapping);
    QVERIFY(!squareOverlap(b, kSide, a, kSide).overlapping);
    QVERIFY(!robotRobotContact(a, kSide, 0, b, kSide, 1).has_value());
}

void TestGeometry::squaresOverlapAxisAligned_data() {
    // Axis-aligned squares: the overlap along x is (sA + sB)/2 - |dx|, along
    // y likewise; the depth is the smaller, the normal on that axis from B to A.
    QTest::addColumn<double>("sideA");
    QTest::addColumn<double>("sideB");
    QTest::addColumn<double>("dx");  // B's centre minus A's
    QTest::addColumn<double>("dy");
    QTest::addColumn<double>("theta");  // both headings (multiples of 90deg keep them aligned)
    QTest::newRow("B right, shallow on x") << kSide << kSide << 0.07 << 0.02 << 0.0;
    QTest::newRow("B left, shallow on x") << kSide << kSide << -0.071 << -0.03 << 0.0;
    QTest::newRow("B above, shallow on y") << kSide << kSide << 0.01 << 0.072 << 0.0;
    QTest::newRow("B below, shallow on y") << kSide << kSide << -0.04 << -0.0745 << 0.0;
    QTest::newRow("different sides") << 0.075 << 0.05 << 0.06 << 0.01 << 0.0;
    QTest::newRow("headings 90deg apart count as aligned") << kSide << kSide << 0.07 << 0.02 << M_PI / 2;
    QTest::newRow("heading pi") << kSide << 0.06 << -0.02 << 0.065 << M_PI;
}

void TestGeometry::squaresOverlapAxisAligned() {
    QFETCH(double, sideA);
    QFETCH(double, sideB);
    QFETCH(double, dx);
    QFETCH(double, dy);
    QFETCH(double, theta);
    const RobotState a = pose(0.1, -0.2, theta), b = pose(0.1 + dx, -0.2 + dy, 0.0);
    const double reach = (sideA + sideB) / 2;
    const double overlapX = reach - std::abs(dx), overlapY = reach - std::abs(dy);
    const double depth = std::min(overlapX, overlapY);
    const Eigen::Vector2d normal =
        overlapX < overlapY ? Eigen::Vector2d(dx > 0 ? -1.0 : 1.0, 0.0) : Eigen::Vector2d(0.0, dy > 0 ? -1.0 : 1.0);
    const SquareOverlap o = squareOverlap(a, sideA, b, sideB);
    QVERIFY(o.overlapping);
    QVERIFY2(std::abs(o.depth - depth) < 1e-12, qPrintable(QString("depth %1 vs %2").arg(o.depth).arg(depth)));
    QVERIFY2(close(o.normal, normal, 1e-12), qPrintable(str(o.normal) + " vs " + str(normal)));
    // Swapping A and B flips the normal and keeps the depth.
    const SquareOverlap swapped = squareOverlap(b, sideB, a, sideA);
    QVERIFY(swapped.overlapping);
    QVERIFY(std::abs(swapped.depth - depth) < 1e-12);
    QVERIFY(close(swapped.normal, -normal, 1e-12));
    // robotRobotContact reports the same depth and normal.
    const auto k = robotRobotContact(a, sideA, 3, b, sideB, 5);
    QVERIFY(k.has_value());
    QVERIFY(k->a.kind == BodyKind::Robot && k->a.index == 3 && k->b.kind == BodyKind::Robot && k->b.index == 5);
    QVERIFY(std::abs(k->depth - depth) < 1e-12);
    QVERIFY(close(k->normal, normal, 1e-12));
}

void TestGeometry::squareOverlapIsMinimalTranslation() {
    // For convex polygons the least translation that separates them is along
    // one of the edge normals: moving A by the depth along the normal just
    // separates the squares, moving it slightly less along any direction does not.
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> offset(-0.09, 0.09), angle(-M_PI, M_PI), side(0.04, 0.09);
    int checked = 0;
    for (int k = 0; k < 20000 && checked < 2000; ++k) {
        const double sa = side(rng), sb = side(rng);
        const RobotState a = pose(offset(rng), offset(rng), angle(rng)), b = pose(0.0, 0.0, angle(rng));
        const SquareOverlap o = squareOverlap(a, sa, b, sb);
        if (!o.overlapping || o.depth < 1e-6) continue;
        ++checked;
        QVERIFY(std::abs(o.normal.norm() - 1.0) < 1e-14);
        QVERIFY(o.depth > 0.0);
        const RobotState out = shifted(a, o.normal * (o.depth + 1e-9));
        QVERIFY2(!bruteForceOverlap(out, sa, b, sb), qPrintable(QString("trial %1: still overlapping").arg(k)));
        QVERIFY(!squareOverlap(out, sa, b, sb).overlapping);
        const RobotState notQuite = shifted(a, o.normal * (o.depth * (1 - 1e-6)));
        QVERIFY(bruteForceOverlap(notQuite, sa, b, sb));
        for (int t = 0; t < 8; ++t) {
            const double phi = angle(rng);
            const RobotState other = shifted(a, o.depth * (1 - 1e-6) * Eigen::Vector2d(std::cos(phi), std::sin(phi)));
            QVERIFY2(bruteForceOverlap(other, sa, b, sb),
                     qPrintable(QString("trial %1: a shorter translation separates them").arg(k)));
        }
    }
    QVERIFY(checked == 2000);
}

void TestGeometry::squareOverlapMatchesBruteForce() {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> offset(-0.11, 0.11), angle(-M_PI, M_PI), side(0.03, 0.1);
    int overlaps = 0, separated = 0;
    for (int k = 0; k < 20000; ++k) {
        const double sa = side(rng), sb = side(rng);
        const RobotState a = pose(offset(rng), offset(rng), angle(rng)), b = pose(offset(rng), offset(rng), angle(rng));
        const bool want = bruteForceOverlap(a, sa, b, sb);
        const SquareOverlap ab = squareOverlap(a, sa, b, sb), ba = squareOverlap(b, sb, a, sa);
        QVERIFY2(ab.overlapping == want, qPrintable(QString("trial %1").arg(k)));
        QCOMPARE(ba.overlapping, want);
        QCOMPARE(robotRobotContact(a, sa, 0, b, sb, 1).has_value(), want);
        if (want) {
            ++overlaps;
            QVERIFY(std::abs(ab.depth - ba.depth) < 1e-14);
            QVERIFY(close(ab.normal, -ba.normal, 1e-14));
        } else {
            ++separated;
        }
    }
    QVERIFY(overlaps > 1000 && separated > 1000);  // both outcomes were exercised
}

// ---------------------------------------------------------------- the paper's dropped cases

void TestGeometry::robotsFaceToFace_data() {
    QTest::addColumn<double>("theta");    // A's heading; B sits ahead of A
    QTest::addColumn<double>("bTurn");    // B's heading minus A's: 0 (same) or pi (facing)
    QTest::addColumn<double>("lateral");  // B's offset to A's left, m
    QTest::addColumn<double>("depth");    // how far the faces overlap, m
    for (double theta : {0.0, 0.3, -1.2, 2.9}) {
        const QByteArray t = QByteArray::number(theta);
        QTest::newRow("same heading, aligned " + t) << theta << 0.0 << 0.0 << 1e-4;
        QTest::newRow("facing, aligned " + t) << theta << M_PI << 0.0 << 1e-4;
        QTest::newRow("facing, 1 um " + t) << theta << M_PI << 0.0 << 1e-6;
        QTest::newRow("same heading, offset " + t) << theta << 0.0 << 0.02 << 5e-4;
        QTest::newRow("facing, offset right " + t) << theta << M_PI << -0.03 << 2e-3;
    }
}

void TestGeometry::robotsFaceToFace() {
    // Two robots flat against each other: A's front face against B's face,
    // overlapping by `depth`. The contact normal is along A's heading, from B
    // to A (i.e. -h), and the depth is the overlap of the faces.
    QFETCH(double, theta);
    QFETCH(double, bTurn);
    QFETCH(double, lateral);
    QFETCH(double, depth);
    const RobotState a = pose(-0.12, 0.31, theta);
    const Eigen::Vector2d cb = worldPoint(a, kSide - depth, lateral);
    const RobotState b = pose(cb.x(), cb.y(), theta + bTurn);
    const Eigen::Vector2d h(std::cos(theta), std::sin(theta));

    const auto k = robotRobotContact(a, kSide, 0, b, kSide, 1);
    QVERIFY(k.has_value());
    QVERIFY2(close(k->normal, -h, 1e-9), qPrintable(str(k->normal) + " vs " + str(-h)));
    QVERIFY2(std::abs(k->depth - depth) < 1e-12, qPrintable(QString("depth %1 vs %2").arg(k->depth).arg(depth)));
    // The contact point lies in the overlap: between the two faces along the
    // heading, within the shared width across it.
    const Eigen::Vector2d local = rotate(-theta, k->point - Eigen::Vector2d(a.x, a.y));
    QVERIFY2(local.x() >= kSide / 2 - depth - 1e-12 && local.x() <= kSide / 2 + 1e-12,
             qPrintable(QString("contact point %1 m ahead of A").arg(local.x())));
    QVERIFY(local.y() >= std::max(-kSide / 2, lateral - kSide / 2) - 1e-12);
    QVERIFY(local.y() <= std::min(kSide / 2, lateral + kSide / 2) + 1e-12);
    // The other way round: the normal flips, the depth stays.
    const auto back = robotRobotContact(b, kSide, 1, a, kSide, 0);
    QVERIFY(back.has_value());
    QVERIFY(close(back->normal, h, 1e-9));
    QVERIFY(std::abs(back->depth - depth) < 1e-12);
}

void TestGeometry::robotsFaceToVertexAt45Degrees_data() {
    QTest::addColumn<double>("phi");    // rotation of the whole configuration
    QTest::addColumn<double>("depth");  // how far B's vertex is into A's front face, m
    for (double phi : {0.0, 0.4, -2.5, M_PI / 2})
        for (double depth : {1e-5, 1e-3, 5e-3})
            QTest::newRow(QByteArray::number(phi) + ", " + QByteArray::number(depth)) << phi << depth;
}

void TestGeometry::robotsFaceToVertexAt45Degrees() {
    // B, turned 45deg relative to A, pushes one vertex into the middle of A's
    // front face: normal -h_A (from B to A), depth as set, contact point at
    // that vertex, half a side minus the depth ahead of A's centre.
    QFETCH(double, phi);
    QFETCH(double, depth);
    const RobotState a = pose(0.2, -0.1, phi);
    const Eigen::Vector2d cb = worldPoint(a, kSide / 2 + kSide / std::sqrt(2.0) - depth, 0.0);
    const RobotState b = pose(cb.x(), cb.y(), phi + M_PI / 4);
    const Eigen::Vector2d h(std::cos(phi), std::sin(phi));
    const Eigen::Vector2d vertex = worldPoint(a, kSide / 2 - depth, 0.0);

    const SquareOverlap o = squareOverlap(a, kSide, b, kSide);
    QVERIFY(o.overlapping);
    QVERIFY2(std::abs(o.depth - depth) < 1e-12, qPrintable(QString("depth %1 vs %2").arg(o.depth).arg(depth)));
    QVERIFY(close(o.normal, -h, 1e-12));
    const auto k = robotRobotContact(a, kSide, 0, b, kSide, 1);
    QVERIFY(k.has_value());
    QVERIFY(std::abs(k->depth - depth) < 1e-12);
    QVERIFY(close(k->normal, -h, 1e-12));
    QVERIFY2(close(k->point, vertex, 1e-12), qPrintable(str(k->point) + " vs " + str(vertex)));
}

void TestGeometry::robotsCrossedNoVertexInside_data() {
    QTest::addColumn<double>("phi");
    QTest::addColumn<double>("e");  // offset of B along A's heading, m
    for (double phi : {0.0, 0.35, -1.9})
        for (double e : {0.0, 0.004, 0.012})
            QTest::newRow(QByteArray::number(phi) + ", " + QByteArray::number(e)) << phi << e;
}

void TestGeometry::robotsCrossedNoVertexInside() {
    // Two equal squares turned 45deg to each other with (nearly) the same
    // centre form an eight-pointed star: every vertex is half a diagonal
    // (s/sqrt2 > s/2) from the other's centre along the other's diagonal...
    // so no vertex of either lies inside the other and the paper's test sees
    // nothing, yet they overlap heavily. With B offset by e < s/sqrt2 - s/2
    // along A's heading, the least penetration is along A's heading:
    // s/2 + s/sqrt2 - e (B's axes give s/2 + s/sqrt2 - e/sqrt2, larger).
    QFETCH(double, phi);
    QFETCH(double, e);
    QVERIFY(e < kSide / std::sqrt(2.0) - kSide / 2);
    const RobotState a = pose(-0.3, 0.2, phi);
    const Eigen::Vector2d cb = worldPoint(a, e, 0.0);
    const RobotState b = pose(cb.x(), cb.y(), phi + M_PI / 4);
    // The premise: the paper's vertex test, both ways, finds nothing.
    for (const Eigen::Vector2d& v : robotVertices(a, kSide)) QVERIFY(!vssim::pointInRobot(b, kSide, v));
    for (const Eigen::Vector2d& v : robotVertices(b, kSide)) QVERIFY(!vssim::pointInRobot(a, kSide, v));
    QVERIFY(bruteForceOverlap(a, kSide, b, kSide));  // yet the edges cross

    const double depth = kSide / 2 + kSide / std::sqrt(2.0) - e;
    const SquareOverlap o = squareOverlap(a, kSide, b, kSide);
    QVERIFY(o.overlapping);
    QVERIFY2(std::abs(o.depth - depth) < 1e-12, qPrintable(QString("depth %1 vs %2").arg(o.depth).arg(depth)));
    const auto k = robotRobotContact(a, kSide, 0, b, kSide, 1);
    QVERIFY(k.has_value());
    QVERIFY(std::abs(k->depth - depth) < 1e-12);
    if (e > 0.0) {  // at e = 0 all four axes tie: any of them is a valid normal
        const Eigen::Vector2d h(std::cos(phi), std::sin(phi));
        QVERIFY2(close(k->normal, -h, 1e-12), qPrintable(str(k->normal) + " vs " + str(-h)));
    }
    QVERIFY(std::abs(k->normal.norm() - 1.0) < 1e-14);
    // The contact point lies in the overlap of the two squares.
    QVERIFY(vssim::pointInRobot(a, kSide, k->point, 1e-12) && vssim::pointInRobot(b, kSide, k->point, 1e-12));
}

// ---------------------------------------------------------------- walls

void TestGeometry::robotTiltedAgainstBottomWall_data() {
    QTest::addColumn<double>("theta");
    QTest::addColumn<double>("depth");
    QTest::newRow("0.3 rad, 2 mm") << 0.3 << 2e-3;
    QTest::newRow("-0.5 rad, 0.1 mm") << -0.5 << 1e-4;
    QTest::newRow("1.2 rad, 5 mm") << 1.2 << 5e-3;
    QTest::newRow("-2.0 rad, 1 mm") << -2.0 << 1e-3;
}

void TestGeometry::robotTiltedAgainstBottomWall() {
    // A tilted robot with its lowest vertex `depth` below the bottom wall
    // (y = -0.65) of the 1.5 x 1.3 field; the next lowest is far above it
    // (the tilt is well away from a multiple of 90deg), so the contact point
    // is that vertex.
    QFETCH(double, theta);
    QFETCH(double, depth);
    const Field field = makeRectangularField(1.5, 1.3);
    const Wall& bottom = field.walls[0];
    QVERIFY(std::abs(bottom.a.y() + 0.65) < 1e-15 && std::abs(bottom.b.y() + 0.65) < 1e-15);
    // Lowest vertex: the j with the smallest sin(theta + 45deg + 90deg j).
    double lowest = 1.0;
    int jLow = 0;
    for (int j = 0; j < 4; ++j) {
        const double s = std::sin(theta + M_PI / 4 + M_PI / 2 * j);
        if (s < lowest) lowest = s, jLow = j;
    }
    const double r = kSide / std::sqrt(2.0);
    const double yc = -0.65 - depth - r * lowest;
    const RobotState robot = pose(0.12, yc, theta);
    const double a = theta + M_PI / 4 + M_PI / 2 * jLow;
    const Eigen::Vector2d vertex(0.12 + r * std::cos(a), yc + r * std::sin(a));

    const auto k = robotWallContact(robot, kSide, 2, bottom, 0);
    QVERIFY(k.has_value());
    QVERIFY(k->a.kind == BodyKind::Robot && k->a.index == 2 && k->b.kind == BodyKind::Wall && k->b.index == 0);
    QVERIFY(close(k->normal, Eigen::Vector2d(0.0, 1.0), 1e-15));
    QVERIFY2(std::abs(k->depth - depth) < 1e-12, qPrintable(QString("depth %1 vs %2").arg(k->depth).arg(depth)));
    QVERIFY2(close(k->point, vertex, 1e-12), qPrintable(str(k->point) + " vs " + str(vertex)));
    // The other walls are far: no contact there.
    for (int w = 1; w < 4; ++w) QVERIFY(!robotWallContact(robot, kSide, 2, field.walls[w], w).has_value());
    // Through detectContacts as well.
    const std::vector<RobotState> robots{robot};
    const std::vector<double> sides{kSide};
    const auto all = detectContacts(field, {&robots, &sides, nullptr, 0.0});
    QCOMPARE(int(all.size()), 1);
    QVERIFY(std::abs(all[0].depth - depth) < 1e-12);
}

void TestGeometry::robotFlatOnWallTouchesAtFaceMiddle() {
    // A robot lying flat on the right wall (x = 0.75), heading along +x,
    // pushed in by 1 mm: both front vertices are equally deep and the contact
    // point is the middle of the front face.
    const Field field = makeRectangularField(1.5, 1.3);
    const double depth = 1e-3;
    const RobotState robot = pose(0.75 - kSide / 2 + depth, 0.2, 0.0);
    const auto k = robotWallContact(robot, kSide, 0, field.walls[1], 1);
    QVERIFY(k.has_value());
    QVERIFY(close(k->normal, Eigen::Vector2d(-1.0, 0.0), 1e-15));
    QVERIFY(std::abs(k->depth - depth) < 1e-12);
    QVERIFY2(close(k->point, Eigen::Vector2d(0.75 + depth, 0.2), 1e-12), qPrintable(str(k->point)));
}

void TestGeometry::robotClearOfWall() {
    const Field field = makeRectangularField(1.5, 1.3);
    // Lowest vertex 0.1 mm above the bottom wall, tilted.
    const double theta = 0.3;
    const double lowest = std::min({std::sin(theta + M_PI / 4), std::sin(theta + 3 * M_PI / 4),
                                    std::sin(theta + 5 * M_PI / 4), std::sin(theta + 7 * M_PI / 4)});
    const RobotState robot = pose(0.0, -0.65 + 1e-4 - kSide / std::sqrt(2.0) * lowest, theta);
    for (int w = 0; w < 4; ++w) QVERIFY(!robotWallContact(robot, kSide, 0, field.walls[w], w).has_value());
}

void TestGeometry::ballTouchingWall_data() {
    QTest::addColumn<int>("wall");
    QTest::addColumn<double>("along");  // position along the wall (x for bottom/top, y for left/right)
    QTest::addColumn<double>("gap");    // distance from the centre to the wall minus r_b (negative: overlap)
    QTest::newRow("bottom, 1 mm in") << 0 << 0.2 << -1e-3;
    QTest::newRow("right, 0.01 mm in") << 1 << -0.3 << -1e-5;
    QTest::newRow("top, 5 mm in") << 2 << 0.7 << -5e-3;
    QTest::newRow("left, 1 um in") << 3 << 0.0 << -1e-6;
    QTest::newRow("bottom, 1 um clear") << 0 << 0.2 << 1e-6;
    QTest::newRow("left, 1 cm clear") << 3 << 0.1 << 1e-2;
    QTest::newRow("bottom, centre behind the wall") << 0 << -0.4 << -kRadius - 0.01;
}

void TestGeometry::ballTouchingWall() {
    QFETCH(int, wall);
    QFETCH(double, along);
    QFETCH(double, gap);
    const Field field = makeRectangularField(1.5, 1.3);
    // Wall foot point and inward normal, from the field's dimensions.
    const Eigen::Vector2d foot[4] = {{along, -0.65}, {0.75, along}, {along, 0.65}, {-0.75, along}};
    const Eigen::Vector2d inward[4] = {{0, 1}, {-1, 0}, {0, -1}, {1, 0}};
    BallState ball;
    const Eigen::Vector2d c = foot[wall] + (kRadius + gap) * inward[wall];
    ball.x = c.x();
    ball.y = c.y();
    const auto k = ballWallContact(ball, kRadius, field.walls[wall], wall);
    QCOMPARE(k.has_value(), gap < 0.0);
    if (!k) return;
    QVERIFY(k->a.kind == BodyKind::Ball && k->b.kind == BodyKind::Wall && k->b.index == wall);
    QVERIFY2(close(k->normal, inward[wall], 1e-12), qPrintable(str(k->normal)));
    QVERIFY2(std::abs(k->depth + gap) < 1e-12, qPrintable(QString("depth %1 vs %2").arg(k->depth).arg(-gap)));
    QVERIFY2(close(k->point, foot[wall], 1e-12), qPrintable(str(k->point) + " vs " + str(foot[wall])));
}

void TestGeometry::ballAtEndOfWallSegment() {
    // A free-standing wall (a goal post, say) from (0, 0) to (0.3, 0), normal
    // +y. A ball just past its end touches the end point: the normal is from
    // the end to the centre, not the wall's normal.
    const Wall wall{Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.3, 0.0), Eigen::Vector2d(0.0, 1.0)};
    BallState ball;
    ball.x = 0.3 + 0.012;
    ball.y = 0.009;  // 0.015 m from the end, a 3-4-5 triangle
    const auto k = ballWallContact(ball, kRadius, wall, 7);
    QVERIFY(k.has_value());
    QCOMPARE(k->b.index, 7);
    QVERIFY(std::abs(k->depth - (kRadius - 0.015)) < 1e-12);
    QVERIFY(close(k->normal, Eigen::Vector2d(0.8, 0.6), 1e-12));
    QVERIFY(close(k->point, wall.b, 1e-15));
    ball.x = 0.3 + 0.8 * (kRadius + 1e-5);
    ball.y = 0.6 * (kRadius + 1e-5);
    QVERIFY(!ballWallContact(ball, kRadius, wall, 7).has_value());
}

// ---------------------------------------------------------------- robot and ball

void TestGeometry::ballTouchingRobotFace_data() {
    QTest::addColumn<double>("theta");
    QTest::addColumn<int>("face");       // 0 front, 1 left, 2 back, 3 right
    QTest::addColumn<double>("across");  // position of the touch along the face, m (|.| < s/2)
    QTest::addColumn<double>("depth");
    QTest::newRow("front, centred") << 0.0 << 0 << 0.0 << 1e-3;
    QTest::newRow("front, off centre, turned") << 0.8 << 0 << 0.02 << 2e-4;
    QTest::newRow("left") << -1.3 << 1 << -0.03 << 4e-3;
    QTest::newRow("back") << 2.2 << 2 << 0.01 << 1e-6;
    QTest::newRow("right, near a corner") << 3.0 << 3 << 0.037 << 5e-4;
    QTest::newRow("front, clear by 1 um") << 0.4 << 0 << 0.0 << -1e-6;
}

void TestGeometry::ballTouchingRobotFace() {
    QFETCH(double, theta);
    QFETCH(int, face);
    QFETCH(double, across);
    QFETCH(double, depth);
    const RobotState robot = pose(0.05, -0.2, theta);
    // Outward normal of the face and its point, in the robot's frame.
    const double faceAngle = M_PI / 2 * face;
    const Eigen::Vector2d outward(std::cos(faceAngle), std::sin(faceAngle));
    const Eigen::Vector2d tangent(-outward.y(), outward.x());
    const Eigen::Vector2d onFace = kSide / 2 * outward + across * tangent;
    const Eigen::Vector2d centre = onFace + (kRadius - depth) * outward;
    BallState ball;
    const Eigen::Vector2d c = worldPoint(robot, centre.x(), centre.y());
    ball.x = c.x();
    ball.y = c.y();
    const auto k = robotBallContact(robot, kSide, 4, ball, kRadius);
    QCOMPARE(k.has_value(), depth > 0.0);
    if (!k) return;
    QVERIFY(k->a.kind == BodyKind::Ball && k->b.kind == BodyKind::Robot && k->b.index == 4);
    const Eigen::Vector2d normal = rotate(theta, outward);  // from the robot (b) to the ball (a)
    const Eigen::Vector2d point = worldPoint(robot, onFace.x(), onFace.y());
    QVERIFY2(close(k->normal, normal, 1e-9), qPrintable(str(k->normal) + " vs " + str(normal)));
    QVERIFY2(std::abs(k->depth - depth) < 1e-12, qPrintable(QString("depth %1 vs %2").arg(k->depth).arg(depth)));
    QVERIFY2(close(k->point, point, 1e-12), qPrintable(str(k->point) + " vs " + str(point)));
}

void TestGeometry::ballTouchingRobotCorner_data() {
    QTest::addColumn<double>("theta");
    QTest::addColumn<int>("vertex");
    QTest::addColumn<double>("spread");  // direction of the ball from the vertex, relative to the diagonal, rad
    QTest::addColumn<double>("depth");
    QTest::newRow("vertex 0, on the diagonal") << 0.0 << 0 << 0.0 << 1e-3;
    QTest::newRow("vertex 1, 30deg off, turned") << 0.6 << 1 << M_PI / 6 << 2e-3;
    QTest::newRow("vertex 2, -40deg off") << -2.0 << 2 << -0.7 << 1e-4;
    QTest::newRow("vertex 3, 10deg off") << 1.9 << 3 << 0.17 << 5e-3;
    QTest::newRow("vertex 0, clear by 1 um") << 0.2 << 0 << 0.3 << -1e-6;
}

void TestGeometry::ballTouchingRobotCorner() {
    // The ball in the exterior quadrant of a vertex (within 45deg of the
    // diagonal): the closest point of the square is the vertex itself.
    QFETCH(double, theta);
    QFETCH(int, vertex);
    QFETCH(double, spread);
    QFETCH(double, depth);
    const RobotState robot = pose(-0.4, 0.3, theta);
    const double diagonal = theta + M_PI / 4 + M_PI / 2 * vertex;
    const Eigen::Vector2d corner = Eigen::Vector2d(robot.x, robot.y) +
                                   kSide / std::sqrt(2.0) * Eigen::Vector2d(std::cos(diagonal), std::sin(diagonal));
    const Eigen::Vector2d dir(std::cos(diagonal + spread), std::sin(diagonal + spread));
    const Eigen::Vector2d c = corner + (kRadius - depth) * dir;
    BallState ball;
    ball.x = c.x();
    ball.y = c.y();
    const auto k = robotBallContact(robot, kSide, 0, ball, kRadius);
    QCOMPARE(k.has_value(), depth > 0.0);
    if (!k) return;
    QVERIFY2(close(k->point, corner, 1e-12), qPrintable(str(k->point) + " vs " + str(corner)));
    QVERIFY2(std::abs(k->depth - depth) < 1e-12, qPrintable(QString("depth %1 vs %2").arg(k->depth).arg(depth)));
    QVERIFY2(close(k->normal, dir, 1e-9), qPrintable(str(k->normal) + " vs " + str(dir)));
}

void TestGeometry::ballCentreInsideRobot() {
    // A ball whose centre has got inside the square leaves through the
    // nearest face: depth r_b plus how far the centre is inside that face.
    const RobotState robot = pose(0.1, 0.1, 0.9);
    const double inside = 0.004, left = 0.012;
    const Eigen::Vector2d c = worldPoint(robot, kSide / 2 - inside, left);
    BallState ball;
    ball.x = c.x();
    ball.y = c.y();
    const auto k = robotBallContact(robot, kSide, 0, ball, kRadius);
    QVERIFY(k.has_value());
    QVERIFY(close(k->normal, Eigen::Vector2d(std::cos(0.9), std::sin(0.9)), 1e-12));
    QVERIFY(std::abs(k->depth - (kRadius + inside)) < 1e-12);
    QVERIFY(close(k->point, worldPoint(robot, kSide / 2, left), 1e-12));
}

QTEST_GUILESS_MAIN(TestGeometry)
#include "test_geometry.moc"
