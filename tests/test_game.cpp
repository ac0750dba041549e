// The game library (game/): goal detection, the referee's rules with their
// timers at the edges, placements for every call, the built-in team and the
// Match that puts them together.
#include <QtTest>
#include <cmath>

#include "test_support.h"
#include "vssim/game/match.h"
#include "vssim/game/pitch.h"
#include "vssim/game/placement.h"
#include "vssim/game/referee.h"
#include "vssim/game/sparring_team.h"
#include "vssim/geometry.h"

using namespace vssim;

Q_DECLARE_METATYPE(vssim::Team)

namespace {

constexpr double kR = 0.02135;  // ball radius, m
constexpr double kHx = 0.75;    // half length of the 3 vs 3 field, m

// The official 3 vs 3 field with three robots a side in a kick-off layout
// (each team in the half it defends), referee on, teams as given.
Scene gameScene(TeamControl yellow = TeamControl::Idle, TeamControl blue = TeamControl::Idle,
                FieldType type = FieldType::Vsss3v3, int perTeam = 3, Team leftTeam = Team::Yellow) {
    Scene scene;
    scene.field = makeField(officialDimensions(type));
    scene.simulation.collision_model = CollisionModel::Impulse;
    scene.simulation.restitution = 0.5;
    for (int t = 0; t < 2; ++t)
        for (int i = 0; i < perTeam; ++i) {
            const Team team = t == 0 ? Team::Yellow : Team::Blue;
            const double s = team == leftTeam ? -1.0 : 1.0;
            RobotSpec r = test::robotAt("", s * (0.25 + 0.12 * i), 0.15 * (i - 1), s < 0.0 ? 0.0 : M_PI);
            r.team = team;
            r.name = std::string(t == 0 ? "yellow" : "blue") + std::to_string(i);
            scene.robots.push_back(r);
        }
    scene.game.rules.referee = true;
    scene.game.rules.left_team = leftTeam;
    scene.game.yellow = yellow;
    scene.game.blue = blue;
    return scene;
}

// A world to hand to refereeTick: bodies where the test puts them.
struct Table {
    Scene scene = gameScene();
    WorldModel model = makeWorldModel(scene);
    WorldState state = initialWorldState(scene);
    std::vector<Team> teams = robotTeams(scene);
    GameRules rules = scene.game.rules;
    GameState game = initialGameState(scene.game.rules, scene.robots.size());

    Table() {
        game.phase = GamePhase::GameOn;  // past the opening kick-off
        park();
    }
    // Every robot far from the goal areas, the ball rolling in the open.
    void park() {
        for (std::size_t i = 0; i < state.robots.size(); ++i) {
            state.robots[i] = RobotState{(i < 3 ? -0.3 : 0.3), -0.4 + 0.3 * static_cast<double>(i % 3), 0.0, 0.0, 0.0};
        }
        state.ball = BallState{0.1, 0.1, 0.5, 0.0};
    }
    // n ticks of the rules' tick, the ball moving by its velocity times the
    // tick before each; the first call made, if any. (The referee judges the
    // ball's speed by its displacement from the previous tick.)
    std::optional<RefereeCall> ticks(int n) {
        for (int k = 0; k < n; ++k) {
            state.ball.x += state.ball.vx * rules.tick;
            state.ball.y += state.ball.vy * rules.tick;
            if (auto c = refereeTick(rules, model, state, teams, rules.tick, game)) return c;
        }
        return std::nullopt;
    }
    // Puts the ball somewhere and lets the referee see it there once (that
    // tick, the ball arrived: it counts as moving).
    void putBall(const BallState& ball) {
        state.ball = BallState{ball.x, ball.y, 0.0, 0.0};
        QVERIFY(!refereeTick(rules, model, state, teams, rules.tick, game));
        state.ball = ball;
    }
};

bool inside(const WorldModel& model, const Placement& p) {
    for (std::size_t i = 0; i < p.robots.size(); ++i)
        if (!robotInsideField(model.field, model.sides[i], p.robots[i].x, p.robots[i].y, p.robots[i].theta))
            return false;
    return discInsideField(model.field, model.ball.radius, p.ball.x, p.ball.y);
}

std::vector<std::string> namesOf(const Scene& scene) {
    std::vector<std::string> names;
    for (const RobotSpec& r : scene.robots) names.push_back(r.name);
    return names;
}

}  // namespace

class TestGame : public QObject {
    Q_OBJECT
private slots:
    void goalNeedsTheWholeBallPastTheLine_data();
    void goalNeedsTheWholeBallPastTheLine();
    void goalAreasAndMarks();
    void stuckBallTimerEdges_data();
    void stuckBallTimerEdges();
    void stuckBallSpeedEdge();
    void ballStuckInGoalAreaIsAPenalty();
    void twoDefenders_data();
    void twoDefenders();
    void twoAttackersGiveAGoalKick();
    void goalkeeperIsLongestInTheArea();
    void stopThenGameOnAfterTheTransition();
    void clockStopsWhileStoppedAndHalvesEnd();
    void automaticPlacementIsLegal_data();
    void automaticPlacementIsLegal();
    void illegalPlacementsAreNamed();
    void firaClientsKickOffPlacementIsLegalInFirasimsLayout();
    void goalInAMatchCountsOnceAndKicksOff();
    void goalsFollowTheLeftTeam();
    void ballOffAPostIsNoGoal();
    void remoteVoltagesHeldWhileStopped();
    void teamPlacementDuringStop();
    void aPersonOverridesAnyTeam();
    void matchWithoutGameIsThePlainSimulation();
    void matchIsDeterministicAndCutFree();
    void builtinTeamScoresAgainstIdle_data();
    void builtinTeamScoresAgainstIdle();
    void seedsVaryTheGameReproducibly();
    void voltagesForReachTheAskedVelocity();
};

// ---------------------------------------------------------------- goals

void TestGame::goalNeedsTheWholeBallPastTheLine_data() {
    QTest::addColumn<double>("x");
    QTest::addColumn<double>("y");
    QTest::addColumn<int>("side");
    QTest::newRow("wholly in the right goal") << kHx + kR + 1e-6 << 0.0 << 1;
    QTest::newRow("a micrometre short of wholly in") << kHx + kR - 1e-6 << 0.0 << 0;
    QTest::newRow("centre on the goal line") << kHx << 0.05 << 0;
    QTest::newRow("wholly in the left goal") << -kHx - kR - 1e-6 << -0.1 << -1;
    QTest::newRow("just inside a post") << kHx + 0.05 << 0.2 - kR - 1e-4 << 1;
    QTest::newRow("in line with the goal but beside the mouth") << kHx + 0.05 << 0.2 + 1e-3 << 0;
    QTest::newRow("middle of the field") << 0.0 << 0.0 << 0;
}

void TestGame::goalNeedsTheWholeBallPastTheLine() {
    QFETCH(double, x);
    QFETCH(double, y);
    QFETCH(int, side);
    const Field field = makeField(officialDimensions(FieldType::Vsss3v3));
    QCOMPARE(goalScoredIn(field, BallState{x, y, 0.0, 0.0}, kR), side);
    // A box has no goals: nothing is ever a goal.
    QCOMPARE(goalScoredIn(makeRectangularField(1.5, 1.3), BallState{x, y, 0.0, 0.0}, kR), 0);
}

void TestGame::goalAreasAndMarks() {
    const Field field = makeField(officialDimensions(FieldType::Vsss3v3));
    // 0.15 deep x 0.70 wide in front of each goal, and the goal behind it.
    QVERIFY(inGoalArea(field, -1, {-kHx + 0.15, 0.35}));
    QVERIFY(!inGoalArea(field, -1, {-kHx + 0.15 + 1e-6, 0.0}));
    QVERIFY(!inGoalArea(field, -1, {-kHx + 0.05, 0.35 + 1e-6}));
    QVERIFY(inGoalArea(field, 1, {kHx + 0.09, 0.1}));  // inside the goal
    QVERIFY(!inGoalArea(field, 1, {-kHx + 0.05, 0.0}));
    QCOMPARE(penaltyMark(field, 1), Eigen::Vector2d(0.375, 0.0));
    QCOMPARE(freeBallMark(field, 1), Eigen::Vector2d(0.375, 0.25));
    QCOMPARE(freeBallMark(field, 2), Eigen::Vector2d(-0.375, 0.25));
    QCOMPARE(freeBallMark(field, 3), Eigen::Vector2d(-0.375, -0.25));
    QCOMPARE(freeBallMark(field, 4), Eigen::Vector2d(0.375, -0.25));
    QCOMPARE(quadrantOf(0.1, 0.1), 1);
    QCOMPARE(quadrantOf(-0.1, 0.1), 2);
    QCOMPARE(quadrantOf(-0.1, -0.1), 3);
    QCOMPARE(quadrantOf(0.1, -0.1), 4);
    // On an axis, as VSSReferee says: x = 0 is left, y = 0 is down.
    QCOMPARE(quadrantOf(0.0, 0.0), 3);
    QCOMPARE(quadrantOf(0.0, 0.1), 2);
    QCOMPARE(quadrantOf(0.0, -0.1), 3);
    QCOMPARE(quadrantOf(0.1, 0.0), 4);
    QCOMPARE(quadrantOf(-0.1, 0.0), 3);
    // 5 vs 5: marks from the goal lines (vsss-game.md).
    const Field big = makeField(officialDimensions(FieldType::Vsss5v5));
    QCOMPARE(penaltyMark(big, -1), Eigen::Vector2d(-(1.1 - 0.375), 0.0));
    QCOMPARE(freeBallMark(big, 1), Eigen::Vector2d(1.1 - 0.375, 0.40));
}

// ---------------------------------------------------------------- the rules' timers

void TestGame::stuckBallTimerEdges_data() {
    QTest::addColumn<int>("quadrant");
    QTest::addColumn<double>("x");
    QTest::addColumn<double>("y");
    QTest::newRow("q1") << 1 << 0.3 << 0.2;
    QTest::newRow("q2") << 2 << -0.3 << 0.2;
    QTest::newRow("q3") << 3 << -0.3 << -0.2;
    QTest::newRow("q4") << 4 << 0.3 << -0.2;
}

void TestGame::stuckBallTimerEdges() {
    QFETCH(int, quadrant);
    QFETCH(double, x);
    QFETCH(double, y);
    Table t;
    t.putBall(BallState{x, y, 0.0, 0.0});
    // 5 s at 0.01 s a tick: 499 ticks (4.99 s) is just under, the 500th just over.
    QVERIFY(!t.ticks(499));
    QCOMPARE(t.game.phase, GamePhase::GameOn);
    const auto call = t.ticks(1);
    QVERIFY(call);
    QCOMPARE(call->call, Call::FreeBall);
    QCOMPARE(call->quadrant, quadrant);
    QCOMPARE(t.game.phase, GamePhase::Stop);
    QCOMPARE(t.game.calls.size(), std::size_t(2));  // the opening kick-off and this
}

void TestGame::stuckBallSpeedEdge() {
    Table t;
    // Rolling just under 0.10 m/s counts as stuck...
    t.putBall(BallState{-0.3, 0.2, 0.0999, 0.0});
    QVERIFY(!t.ticks(499));
    QVERIFY(t.ticks(1));
    // ...just over does not, and moving again restarts the timer.
    Table u;
    u.putBall(BallState{-0.3, 0.2, 0.1001, 0.0});
    QVERIFY(!u.ticks(1000));
    u.state.ball.vx = 0.0;
    QVERIFY(!u.ticks(400));
    // A nudge (2 mm in one tick) leaves the mean over the last half second
    // under 0.10 m/s: still stuck, the timer runs on...
    Table n = u;
    n.state.ball.x += 0.002;
    QVERIFY(!n.ticks(99));
    QVERIFY(n.ticks(1));
    // ...a kick (10 cm) counts as moving for the half second it stays in
    // the window, and then the timer starts again.
    u.state.ball.x += 0.1;
    QVERIFY(!u.ticks(549));
    QVERIFY(u.ticks(1));
    // A ball rattling in a jam: a large velocity, going nowhere. Stuck.
    Table w;
    w.putBall(BallState{0.3, -0.2, 0.0, 0.0});
    for (int k = 0; k < 499; ++k) {
        w.state.ball.vx = k % 2 == 0 ? 0.8 : -0.8;  // what the contacts give it each tick
        QVERIFY(!refereeTick(w.rules, w.model, w.state, w.teams, w.rules.tick, w.game));
    }
    QVERIFY(refereeTick(w.rules, w.model, w.state, w.teams, w.rules.tick, w.game));
}

void TestGame::ballStuckInGoalAreaIsAPenalty() {
    Table t;
    t.putBall(BallState{-kHx + 0.08, 0.1, 0.0, 0.0});  // in yellow's goal area
    const auto call = t.ticks(500);
    QVERIFY(call);
    QCOMPARE(call->call, Call::PenaltyKick);
    QCOMPARE(call->team, Team::Blue);
    QCOMPARE(int(std::lround(call->clock * 100)), 501);  // the tick that saw it arrive, then 5 s
}

void TestGame::twoDefenders_data() {
    QTest::addColumn<int>("defenders");
    QTest::addColumn<bool>("ballInArea");
    QTest::newRow("two, ball in the area") << 2 << true;
    QTest::newRow("three, ball in the area") << 3 << true;
    QTest::newRow("one, ball in the area") << 1 << true;
    QTest::newRow("two, ball outside") << 2 << false;
}

void TestGame::twoDefenders() {
    QFETCH(int, defenders);
    QFETCH(bool, ballInArea);
    Table t;
    for (int i = 0; i < defenders; ++i) t.state.robots[i] = RobotState{-kHx + 0.06, -0.25 + 0.2 * i, 0.0, 0.0, 0.0};
    // The ball in the area or just outside it (at rest: a stuck ball takes
    // 5 s, longer than this test runs).
    t.state.ball = BallState{ballInArea ? -kHx + 0.12 : -kHx + 0.2, 0.3, 0.0, 0.0};
    const bool foul = defenders >= 2 && ballInArea;
    QVERIFY(!t.ticks(299));                     // 2.99 s
    const auto call = t.ticks(foul ? 1 : 150);  // (4.49 s in all: short of a stuck ball's 5 s)
    QCOMPARE(bool(call), foul);
    if (!foul) return;
    QCOMPARE(call->call, Call::PenaltyKick);
    QCOMPARE(call->team, Team::Blue);
    QCOMPARE(QString::fromStdString(call->reason), QString("two defenders"));
}

void TestGame::twoAttackersGiveAGoalKick() {
    Table t;
    // Two blue robots in yellow's goal area (blue attacks x < 0) with the ball.
    t.state.robots[3] = RobotState{-kHx + 0.06, -0.2, 0.0, 0.0, 0.0};
    t.state.robots[4] = RobotState{-kHx + 0.06, 0.2, 0.0, 0.0, 0.0};
    t.state.ball = BallState{-kHx + 0.12, 0.0, 0.0, 0.0};  // at rest: stuck only after 5 s
    QVERIFY(!t.ticks(299));
    const auto call = t.ticks(1);
    QVERIFY(call);
    QCOMPARE(call->call, Call::GoalKick);
    QCOMPARE(call->team, Team::Yellow);
    // One attacker leaves for a tick: the timer starts again.
    Table u;
    u.state.robots[3] = t.state.robots[3];
    u.state.robots[4] = t.state.robots[4];
    u.state.ball = t.state.ball;
    QVERIFY(!u.ticks(200));
    u.state.robots[4].x = 0.0;
    QVERIFY(!u.ticks(1));
    u.state.robots[4].x = -kHx + 0.06;
    QVERIFY(!u.ticks(299));
    QVERIFY(u.ticks(1));
}

void TestGame::goalkeeperIsLongestInTheArea() {
    Table t;
    // Nobody in an area yet: the lowest index of each team.
    QCOMPARE(goalkeeperOf(t.game, t.teams, Team::Yellow), 0);
    QCOMPARE(goalkeeperOf(t.game, t.teams, Team::Blue), 3);
    t.state.robots[2] = RobotState{-kHx + 0.05, 0.0, 0.0, 0.0, 0.0};  // yellow2 in its own area
    t.state.robots[4] = RobotState{-kHx + 0.05, 0.2, 0.0, 0.0, 0.0};  // blue1 in the *other* area
    QVERIFY(!t.ticks(10));
    QCOMPARE(goalkeeperOf(t.game, t.teams, Team::Yellow), 2);
    QCOMPARE(goalkeeperOf(t.game, t.teams, Team::Blue), 3);
    QCOMPARE(goalkeeperOf(t.game, t.teams, Team::Blue), 3);
}

void TestGame::stopThenGameOnAfterTheTransition() {
    Table t;
    makeCall(t.rules, t.game, Call::FreeBall, Team::Yellow, 2, 0.0, "test");
    QCOMPARE(t.game.phase, GamePhase::Stop);
    QVERIFY(!t.ticks(399));  // 3.99 s of the 4 s
    QCOMPARE(t.game.phase, GamePhase::Stop);
    QVERIFY(!t.ticks(1));
    QCOMPARE(t.game.phase, GamePhase::GameOn);
}

void TestGame::clockStopsWhileStoppedAndHalvesEnd() {
    Table t;
    t.rules.half_duration = 2.0;
    t.rules.halves = 2;
    t.rules.stuck_ball_time = 1e9;  // not under test here
    t.state.ball.vx = 0.0;
    QVERIFY(!t.ticks(150));
    QCOMPARE(int(std::lround(t.game.clock * 100)), 150);
    makeCall(t.rules, t.game, Call::FreeBall, Team::Yellow, 1, 0.0, "test");
    QVERIFY(!t.ticks(400));  // the stop: the clock stands still
    QCOMPARE(int(std::lround(t.game.clock * 100)), 150);
    QCOMPARE(t.game.phase, GamePhase::GameOn);
    QVERIFY(!t.ticks(49));
    const auto second = t.ticks(1);
    QVERIFY(second);
    QCOMPARE(second->call, Call::KickOff);
    QCOMPARE(second->team, Team::Blue);  // the other team kicks off the second half
    QCOMPARE(t.game.half, 2);
    QCOMPARE(t.game.clock, 0.0);
    QVERIFY(!t.ticks(400 + 199));
    QCOMPARE(t.game.phase, GamePhase::GameOn);
    QVERIFY(!t.ticks(1));
    QCOMPARE(t.game.phase, GamePhase::Finished);
    QVERIFY(!t.ticks(100));  // nothing after full time
    QCOMPARE(t.game.phase, GamePhase::Finished);
}

// ---------------------------------------------------------------- placements

void TestGame::automaticPlacementIsLegal_data() {
    QTest::addColumn<int>("type");
    QTest::addColumn<int>("perTeam");
    QTest::addColumn<Team>("leftTeam");
    for (int type : {int(FieldType::Vsss3v3), int(FieldType::Vsss5v5)})
        for (int perTeam : {1, 3, 5})
            for (Team left : {Team::Yellow, Team::Blue}) {
                const QByteArray name = (type == int(FieldType::Vsss3v3) ? "3v3 field, " : "5v5 field, ") +
                                        QByteArray::number(perTeam) + " a side, " + teamLabel(left) + " on the left";
                QTest::newRow(name.constData()) << type << perTeam << left;
            }
}

void TestGame::automaticPlacementIsLegal() {
    QFETCH(int, type);
    QFETCH(int, perTeam);
    QFETCH(Team, leftTeam);
    const Scene scene = gameScene(TeamControl::Idle, TeamControl::Idle, FieldType(type), perTeam, leftTeam);
    const GameRules& rules = scene.game.rules;
    const WorldModel model = makeWorldModel(scene);
    const WorldState state = initialWorldState(scene);
    const std::vector<Team> teams = robotTeams(scene);
    const GameState game = initialGameState(scene.game.rules, teams.size());
    struct Case {
        Call call;
        Team team;
        int quadrant;
    };
    const Case cases[] = {
        {Call::KickOff, Team::Yellow, 0},     {Call::KickOff, Team::Blue, 0},     {Call::FreeBall, Team::Yellow, 1},
        {Call::FreeBall, Team::Yellow, 2},    {Call::FreeBall, Team::Yellow, 3},  {Call::FreeBall, Team::Yellow, 4},
        {Call::PenaltyKick, Team::Yellow, 0}, {Call::PenaltyKick, Team::Blue, 0}, {Call::GoalKick, Team::Yellow, 0},
        {Call::GoalKick, Team::Blue, 0},
    };
    for (const Case& c : cases) {
        RefereeCall call;
        call.call = c.call;
        call.team = c.team;
        call.quadrant = c.quadrant;
        const Placement p = automaticPlacement(model, state, teams, game, scene.game.rules, call);
        const QByteArray what =
            QByteArray(callName(c.call)) + " " + teamLabel(c.team) + " q" + QByteArray::number(c.quadrant);
        QVERIFY2(inside(model, p), what.constData());
        for (Team team : {Team::Yellow, Team::Blue}) {
            const std::string why = checkTeamPlacement(model, teams, namesOf(scene), scene.game.rules, call, team, p);
            QVERIFY2(why.empty(), (what + ": " + QByteArray::fromStdString(why)).constData());
        }
        for (const RobotState& r : p.robots) QVERIFY(r.v == 0.0 && r.omega == 0.0);
        // The ball on its mark.
        const Eigen::Vector2d ball(p.ball.x, p.ball.y);
        if (c.call == Call::KickOff) QCOMPARE(ball, Eigen::Vector2d(0.0, 0.0));
        if (c.call == Call::FreeBall) QCOMPARE(ball, freeBallMark(model.field, c.quadrant));
        if (c.call == Call::PenaltyKick)
            QCOMPARE(ball, penaltyMark(model.field, static_cast<int>(defendedSide(rules, otherTeam(c.team)))));
        if (c.call == Call::GoalKick)
            QVERIFY(inGoalArea(model.field, static_cast<int>(defendedSide(rules, c.team)), ball));
        // The side, independently of defendedSide: the left team's penalty
        // and goal kick are at x < 0 exactly when the call says so.
        if (c.call == Call::PenaltyKick) QCOMPARE(ball.x() < 0.0, c.team != leftTeam);
        if (c.call == Call::GoalKick) QCOMPARE(ball.x() < 0.0, c.team == leftTeam);
        // At a kick-off every robot is wholly in the half its team defends.
        if (c.call == Call::KickOff)
            for (std::size_t i = 0; i < teams.size(); ++i)
                QVERIFY2((p.robots[i].x < 0.0) == (teams[i] == leftTeam), what.constData());
        // Free ball: one robot of each team at free_ball_distance along x, on its own side.
        if (c.call == Call::FreeBall && perTeam > 1) {
            for (Team team : {Team::Yellow, Team::Blue}) {
                const Eigen::Vector2d spot = ball + Eigen::Vector2d(defendedSide(rules, team) * 0.20, 0.0);
                bool found = false;
                for (std::size_t i = 0; i < teams.size(); ++i)
                    found |= teams[i] == team && (Eigen::Vector2d(p.robots[i].x, p.robots[i].y) - spot).norm() < 1e-12;
                QVERIFY2(found, what.constData());
            }
        }
    }
}

void TestGame::illegalPlacementsAreNamed() {
    const Scene scene = gameScene();
    const WorldModel model = makeWorldModel(scene);
    const WorldState state = initialWorldState(scene);
    const std::vector<Team> teams = robotTeams(scene);
    const GameState game = initialGameState(scene.game.rules, teams.size());
    const std::vector<std::string> names = namesOf(scene);
    RefereeCall kickoff;
    kickoff.call = Call::KickOff;
    kickoff.team = Team::Blue;
    Placement p = automaticPlacement(model, state, teams, game, scene.game.rules, kickoff);
    auto check = [&](const RefereeCall& call, Team team) {
        return QString::fromStdString(checkTeamPlacement(model, teams, names, scene.game.rules, call, team, p));
    };
    QCOMPARE(check(kickoff, Team::Yellow), QString());
    // In the other half at a kick-off.
    p.robots[1].x = 0.3;
    QVERIFY2(check(kickoff, Team::Yellow).contains("yellow1 (robot 1) is not wholly in its own half"),
             qPrintable(check(kickoff, Team::Yellow)));
    // In the centre circle, not kicking off.
    p.robots[1] = RobotState{-0.12, 0.05, 0.0, 0.0, 0.0};
    QVERIFY2(check(kickoff, Team::Yellow).contains("centre circle"), qPrintable(check(kickoff, Team::Yellow)));
    // On another robot.
    p.robots[1] = p.robots[0];
    p.robots[1].x += 0.03;
    QVERIFY2(check(kickoff, Team::Yellow).contains("overlaps"), qPrintable(check(kickoff, Team::Yellow)));
    // Off the floor: behind the back wall of the goal.
    p.robots[1] = RobotState{-kHx - 0.2, 0.0, 0.0, 0.0, 0.0};
    QVERIFY2(check(kickoff, Team::Yellow).contains("not wholly on the floor"),
             qPrintable(check(kickoff, Team::Yellow)));
    // Too near a free ball.
    RefereeCall freeBall;
    freeBall.call = Call::FreeBall;
    freeBall.quadrant = 2;
    p = automaticPlacement(model, state, teams, game, scene.game.rules, freeBall);
    QCOMPARE(check(freeBall, Team::Yellow), QString());
    p.robots[2] = RobotState{p.ball.x - 0.15, p.ball.y, 0.0, 0.0, 0.0};
    QVERIFY2(check(freeBall, Team::Yellow).contains("free-ball distance"), qPrintable(check(freeBall, Team::Yellow)));
}

void TestGame::firaClientsKickOffPlacementIsLegalInFirasimsLayout() {
    // The league's sample client (FIRAClient) plays yellow on the right and
    // places its robots at (0.2, 0), (0.2, 0.2), (0.2, -0.2), heading 0, at
    // every kick-off. With blue on the left (FIRASim's layout) that is
    // yellow's own half, for either team's kick-off; with yellow on the left
    // it is not, and the referee says why.
    for (Team left : {Team::Blue, Team::Yellow}) {
        const Scene scene = gameScene(TeamControl::Idle, TeamControl::Idle, FieldType::Vsss3v3, 3, left);
        const WorldModel model = makeWorldModel(scene);
        const std::vector<Team> teams = robotTeams(scene);
        const GameState game = initialGameState(scene.game.rules, teams.size());
        for (Team kicker : {Team::Yellow, Team::Blue}) {
            RefereeCall kickoff;
            kickoff.call = Call::KickOff;
            kickoff.team = kicker;
            Placement p = automaticPlacement(model, initialWorldState(scene), teams, game, scene.game.rules, kickoff);
            p.robots[0] = RobotState{0.2, 0.0, 0.0, 0.0, 0.0};
            p.robots[1] = RobotState{0.2, 0.2, 0.0, 0.0, 0.0};
            p.robots[2] = RobotState{0.2, -0.2, 0.0, 0.0, 0.0};
            const std::string why =
                checkTeamPlacement(model, teams, namesOf(scene), scene.game.rules, kickoff, Team::Yellow, p);
            if (left == Team::Blue)
                QVERIFY2(why.empty(), why.c_str());
            else
                QVERIFY2(why.find("not wholly in its own half") != std::string::npos, why.c_str());
        }
    }
}

// ---------------------------------------------------------------- the match

void TestGame::goalInAMatchCountsOnceAndKicksOff() {
    // Idle teams; once the game is on, the ball is rolled hard into the right
    // goal, where it bounces off the back wall and comes out again.
    Scene scene = gameScene();
    scene.simulation.restitution = 1.0;
    scene.game.rules.stop_duration = 0.05;
    Match match(scene);
    match.advanceTo(100);
    QCOMPARE(match.game().phase, GamePhase::GameOn);
    match.placeBall(BallState{0.5, 0.12, 3.0, 0.0});  // beside blue's goalkeeper on the line
    match.advanceTo(match.simulation().state().step + 150);
    QCOMPARE(match.game().goals[0], 1);  // yellow attacks the right goal
    QCOMPARE(match.game().goals[1], 0);
    QCOMPARE(match.game().last.call, Call::KickOff);
    QCOMPARE(match.game().last.team, Team::Blue);
    QCOMPARE(QString::fromStdString(match.game().last.reason), QString("goal by yellow"));
    // The kick-off placement: the ball at the centre, everybody legal.
    const WorldState& s = match.simulation().state();
    QCOMPARE(s.ball.x, 0.0);
    QCOMPARE(s.ball.y, 0.0);
    Placement now{s.robots, s.ball};
    for (Team team : {Team::Yellow, Team::Blue})
        QCOMPARE(checkTeamPlacement(match.simulation().model(), match.teams(), namesOf(scene), scene.game.rules,
                                    match.game().last, team, now),
                 std::string());
}

void TestGame::goalsFollowTheLeftTeam() {
    // Blue on the left (FIRASim's layout): the goal at x > 0 is yellow's, so
    // a ball rolled into it is a goal by blue, and yellow kicks off.
    Scene scene = gameScene(TeamControl::Idle, TeamControl::Idle, FieldType::Vsss3v3, 3, Team::Blue);
    scene.simulation.restitution = 1.0;
    scene.game.rules.stop_duration = 0.05;
    Match match(scene);
    match.advanceTo(100);
    QCOMPARE(match.game().phase, GamePhase::GameOn);
    match.placeBall(BallState{0.5, 0.12, 3.0, 0.0});
    match.advanceTo(match.simulation().state().step + 150);
    QCOMPARE(match.game().goals[teamIndex(Team::Blue)], 1);
    QCOMPARE(match.game().goals[teamIndex(Team::Yellow)], 0);
    QCOMPARE(match.game().last.team, Team::Yellow);
    QCOMPARE(QString::fromStdString(match.game().last.reason), QString("goal by blue"));
    // The kick-off placement puts blue in the left half, yellow in the right.
    const WorldState& s = match.simulation().state();
    for (std::size_t i = 0; i < s.robots.size(); ++i)
        QCOMPARE(s.robots[i].x < 0.0, match.teams()[i] == Team::Blue);
    // And into the goal at x < 0, blue's: a goal by yellow.
    match.advanceTo(match.simulation().state().step + 100);
    QCOMPARE(match.game().phase, GamePhase::GameOn);
    match.placeBall(BallState{-0.5, -0.12, -3.0, 0.0});
    match.advanceTo(match.simulation().state().step + 150);
    QCOMPARE(match.game().goals[teamIndex(Team::Yellow)], 1);
    QCOMPARE(QString::fromStdString(match.game().last.reason), QString("goal by yellow"));
}

void TestGame::ballOffAPostIsNoGoal() {
    Scene scene = gameScene();
    scene.simulation.restitution = 1.0;
    Match match(scene);
    match.advanceTo(4000);  // past the opening stop (4 s)
    QCOMPARE(match.game().phase, GamePhase::GameOn);
    // Straight at the top post's corner from the field: it bounces back.
    match.placeBall(BallState{0.5, 0.2, 2.0, 0.0});
    match.advanceTo(match.simulation().state().step + 400);
    QCOMPARE(match.game().goals[0] + match.game().goals[1], 0);
    QVERIFY(match.simulation().state().ball.vx < 0.0);
}

void TestGame::remoteVoltagesHeldWhileStopped() {
    Match match(gameScene(TeamControl::Remote, TeamControl::Idle));
    QCOMPARE(match.game().phase, GamePhase::Stop);
    match.setVoltages(0, {5.0, 5.0});
    match.setVoltages(3, {5.0, 5.0});  // blue is idle: ignored
    QCOMPARE(match.simulation().state().voltages[0].right, 0.0);
    match.advanceTo(4000);  // the opening stop ends (4 s): the remembered voltages apply
    QCOMPARE(match.game().phase, GamePhase::GameOn);
    QCOMPARE(match.simulation().state().voltages[0].right, 5.0);
    QCOMPARE(match.simulation().state().voltages[3].right, 0.0);
    match.halt();
    QCOMPARE(match.simulation().state().voltages[0].right, 0.0);
    match.resume();
    QCOMPARE(match.simulation().state().voltages[0].right, 5.0);
    // A call by hand stops everybody and places the ball.
    QVERIFY(match.call(Call::FreeBall, Team::Yellow, 3));
    QCOMPARE(match.game().phase, GamePhase::Stop);
    QCOMPARE(match.simulation().state().voltages[0].right, 0.0);
    QCOMPARE(Eigen::Vector2d(match.simulation().state().ball.x, match.simulation().state().ball.y),
             freeBallMark(match.simulation().model().field, 3));
    QVERIFY(!match.call(Call::FreeBall, Team::Yellow, 7));  // no such quadrant
}

void TestGame::aPersonOverridesAnyTeam() {
    Match match(gameScene(TeamControl::Builtin, TeamControl::Remote));
    const Voltages hand{3.0, -2.0};
    match.overrideVoltages(1, hand);  // a built-in robot, during the opening stop: 0 V
    QCOMPARE(match.simulation().state().voltages[1].right, 0.0);
    match.advanceTo(4000);  // game on: the person's, tick after tick, not the team's
    QCOMPARE(match.game().phase, GamePhase::GameOn);
    for (int k = 0; k < 5; ++k) {
        match.advanceTo(match.simulation().state().step + match.tickSteps());
        QCOMPARE(match.simulation().state().voltages[1].right, hand.right);
        QCOMPARE(match.simulation().state().voltages[1].left, hand.left);
    }
    // A remote robot: TCP voltages are kept, not applied, while a person has it.
    match.overrideVoltages(4, hand);
    match.setVoltages(4, {5.0, 5.0});
    QCOMPARE(match.simulation().state().voltages[4].right, hand.right);
    match.overrideVoltages(4, std::nullopt);  // back: its last TCP voltages at once
    QCOMPARE(match.simulation().state().voltages[4].right, 5.0);
    // The built-in robot back: 0 V until its team's next tick, then the team's.
    match.overrideVoltages(1, std::nullopt);
    QCOMPARE(match.simulation().state().voltages[1].right, 0.0);
    match.advanceTo((match.simulation().state().step / match.tickSteps() + 1) * match.tickSteps());
    QVERIFY(match.simulation().state().voltages[1].right != hand.right);
    // Halted: the person's robot too.
    match.overrideVoltages(2, hand);
    match.halt();
    QCOMPARE(match.simulation().state().voltages[2].right, 0.0);
    match.resume();
    QCOMPARE(match.simulation().state().voltages[2].right, hand.right);
}

void TestGame::teamPlacementDuringStop() {
    Match match(gameScene(TeamControl::Remote, TeamControl::Remote));
    // Opening kick-off for yellow: move yellow1 to another legal spot.
    const RobotState spot{-0.4, -0.35, 0.3, 0.0, 0.0};
    QCOMPARE(match.placeTeam(Team::Yellow, {{1, spot}}), std::string());
    QCOMPARE(match.simulation().state().robots[1].x, spot.x);
    QCOMPARE(match.simulation().state().robots[1].theta, spot.theta);
    // Illegal: into the other half; the robot stays where it was.
    const std::string why = match.placeTeam(Team::Yellow, {{1, RobotState{0.4, 0.0, 0.0, 0.0, 0.0}}});
    QVERIFY2(!why.empty(), why.c_str());
    QCOMPARE(match.simulation().state().robots[1].x, spot.x);
    // Another team's robot, an unknown robot.
    QVERIFY(!match.placeTeam(Team::Yellow, {{4, spot}}).empty());
    QVERIFY(!match.placeTeam(Team::Yellow, {{17, spot}}).empty());
    // Not while the game is on.
    match.advanceTo(4000);
    QCOMPARE(match.game().phase, GamePhase::GameOn);
    QVERIFY(QString::fromStdString(match.placeTeam(Team::Yellow, {{1, spot}})).contains("stopped"));
}

void TestGame::matchWithoutGameIsThePlainSimulation() {
    Scene scene = gameScene(TeamControl::Remote, TeamControl::Remote);
    scene.game.rules.referee = false;
    scene.simulation.integrator = Integrator::Exact;
    scene.commands.push_back({0.0, 0, {6.0, 5.0}});
    scene.commands.push_back({0.0, 4, {-3.0, 4.0}});
    scene.ball.vx = 1.0;
    Match match(scene);
    QVERIFY(!match.ticking());
    Simulation plain(scene);
    for (std::int64_t target : {7, 1000, 1333, 3000}) {
        match.advanceTo(target);
        plain.advanceTo(target);
        QCOMPARE(hashState(match.simulation().state()), hashState(plain.state()));
    }
    QCOMPARE(match.game().phase, GamePhase::GameOn);
    QCOMPARE(match.game().goals[0] + match.game().goals[1], 0);
}

void TestGame::matchIsDeterministicAndCutFree() {
    Scene scene = gameScene(TeamControl::Builtin, TeamControl::Builtin);
    scene.simulation.integrator = Integrator::Exact;
    Match a(scene), b(scene);
    // a in steps of one tick, b in uneven multiples of ticks.
    const std::int64_t tick = a.tickSteps();
    const std::int64_t end = 20000;  // 20 s
    for (std::int64_t s = tick; s <= end; s += tick) a.advanceTo(s);
    for (std::int64_t s = 0; s < end;) {
        s = std::min(end, s + tick * (1 + (s / tick) % 37));
        b.advanceTo(s);
    }
    QCOMPARE(hashState(a.simulation().state()), hashState(b.simulation().state()));
    QCOMPARE(a.game().calls.size(), b.game().calls.size());
    QCOMPARE(a.game().goals, b.game().goals);
    // And something happened: the robots left their places.
    QVERIFY(a.simulation().state().robots[2].x != scene.robots[2].initial.x);
}

void TestGame::builtinTeamScoresAgainstIdle_data() {
    QTest::addColumn<Team>("leftTeam");
    QTest::newRow("yellow on the left") << Team::Yellow;
    QTest::newRow("blue on the left") << Team::Blue;
}

void TestGame::builtinTeamScoresAgainstIdle() {
    // Against an idle team every goal of the idle team is an own goal: the
    // built-in team attacks the goal its side says and scores only there.
    QFETCH(Team, leftTeam);
    Scene scene = gameScene(TeamControl::Builtin, TeamControl::Idle, FieldType::Vsss3v3, 3, leftTeam);
    scene.game.rules.halves = 1;
    scene.game.rules.half_duration = 60.0;
    Match match(scene);
    while (match.game().phase != GamePhase::Finished && match.simulation().state().time < 200.0)
        match.advanceTo(match.simulation().state().step + 1000);
    QCOMPARE(match.game().phase, GamePhase::Finished);
    QVERIFY2(match.game().goals[0] >= 1, qPrintable(QString::number(match.game().goals[0])));
    QCOMPARE(match.game().goals[1], 0);
}

void TestGame::seedsVaryTheGameReproducibly() {
    const Scene scene = gameScene(TeamControl::Builtin, TeamControl::Builtin);
    auto play = [&scene](std::uint64_t seed) {
        Match match(scene, seed);
        match.advanceTo(15000);
        return std::make_pair(hashState(match.simulation().state()), match.game().calls.size());
    };
    QCOMPARE(play(7), play(7));
    QVERIFY(play(7).first != play(8).first);
    QVERIFY(play(7).first != play(0).first);
    // The jittered kick-off: every robot within the jitter of its spot, legal.
    Match plain(scene, 0), jittered(scene, 9);
    const WorldState& a = plain.simulation().state();
    const WorldState& b = jittered.simulation().state();
    bool moved = false;
    for (std::size_t i = 0; i < a.robots.size(); ++i) {
        QVERIFY(std::abs(a.robots[i].x - b.robots[i].x) <= Match::kPlacementJitter);
        QVERIFY(std::abs(a.robots[i].y - b.robots[i].y) <= Match::kPlacementJitter);
        QVERIFY(std::abs(a.robots[i].theta - b.robots[i].theta) <= Match::kHeadingJitter);
        moved |= a.robots[i].x != b.robots[i].x;
    }
    QVERIFY(moved);
    Placement now{b.robots, b.ball};
    for (Team team : {Team::Yellow, Team::Blue})
        QCOMPARE(checkTeamPlacement(jittered.simulation().model(), jittered.teams(), namesOf(scene), scene.game.rules,
                                    jittered.game().last, team, now),
                 std::string());
}

void TestGame::voltagesForReachTheAskedVelocity() {
    // Held long enough, the voltages for (v, w) give (v, w): the steady state
    // of the motor model (model.md eq. 7) with the correction at zero error.
    const RobotModel robot = makeRobotModel(test::asymmetricParams());
    for (const auto& [v, w] : {std::pair{0.5, 0.0}, std::pair{0.3, 2.0}, std::pair{-0.4, -1.0}}) {
        RobotState at{0.0, 0.0, 0.0, v, w};
        const Voltages e = voltagesFor(robot, at, v, w);
        const Eigen::Vector2d u = steadyStateVelocity(robot, e);
        QVERIFY(std::abs(u(0) - v) < 1e-12 && std::abs(u(1) - w) < 1e-12);
    }
    // Beyond what the battery gives: clamped.
    const Voltages e = voltagesFor(robot, RobotState{}, 50.0, 0.0);
    QCOMPARE(std::max(std::abs(e.right), std::abs(e.left)), robot.params.max_voltage);
}

QTEST_APPLESS_MAIN(TestGame)
#include "test_game.moc"
