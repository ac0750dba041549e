// vssim match as a user runs it (help, bad input, the text and JSON reports,
// seeds), and the seed's jitter of the kick-off in the library.
#include <QtTest>

#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QRegularExpression>
#include <QTemporaryDir>
#include <cmath>

#include "match_setup.h"
#include "run_vssim.h"

using namespace vssim;

namespace {

using test::Result;
using test::runVssim;

QString sceneFile(const char* name) { return QStringLiteral(VSSIM_SOURCE_DIR "/resources/scenes/%1").arg(name); }

// A short match: two halves of 20 s of game time (about 50 s simulated).
QStringList shortMatch(const QStringList& more = {}) { return QStringList{"match", "--half-duration", "20"} + more; }

QJsonObject jsonOf(const Result& r) {
    QJsonParseError error{};
    const QJsonDocument doc = QJsonDocument::fromJson(r.out, &error);
    if (error.error != QJsonParseError::NoError) qWarning() << error.errorString() << r.out;
    return doc.object();
}

}  // namespace

class TestMatchCommand : public QObject {
    Q_OBJECT
private slots:
    void helpDescribesEveryOption();
    void badInput_data();
    void badInput();
    void textReport();
    void leftTeamSwapsTheSides();
    void jsonReport();
    void sameSeedSameMatch();
    void otherSeedOtherMatch();
    void outFile();
    void sceneByName();
    void idleTeamsScoreNothing();
    void seedJittersThePlacements();
};

void TestMatchCommand::helpDescribesEveryOption() {
    const Result main = runVssim({"--help"});
    QCOMPARE(main.exitCode, 0);
    QVERIFY(main.out.contains("vssim match"));
    const Result help = runVssim({"match", "--help"});
    QCOMPARE(help.exitCode, 0);
    QVERIFY(help.out.startsWith("Usage: vssim match [SCENE] [options]"));
    for (const char* option : {"--halves", "--half-duration", "--seed", "--yellow", "--blue", "--left-team", "--json", "--out"})
        QVERIFY2(help.out.contains(option), option);
    QVERIFY(help.out.contains("splitmix64"));
    QVERIFY(help.err.isEmpty());
}

void TestMatchCommand::badInput_data() {
    QTest::addColumn<QStringList>("args");
    QTest::addColumn<QString>("message");
    QTest::newRow("unknown control") << QStringList{"match", "--yellow", "clever"}
                                     << "--yellow: expected builtin or idle, got \"clever\"";
    QTest::newRow("remote control") << QStringList{"match", "--blue", "remote"} << "--blue: remote teams play over TCP";
    QTest::newRow("negative halves") << QStringList{"match", "--halves", "-1"} << "--halves: expected a whole number";
    QTest::newRow("no halves") << QStringList{"match", "--halves", "0"} << "--halves: expected a whole number";
    QTest::newRow("half a half") << QStringList{"match", "--halves", "1.5"} << "--halves: expected a whole number";
    QTest::newRow("nan half") << QStringList{"match", "--half-duration", "nan"}
                              << "--half-duration: expected a number of seconds, got \"nan\"";
    QTest::newRow("infinite half") << QStringList{"match", "--half-duration", "inf"}
                                   << "--half-duration: expected a number of seconds";
    QTest::newRow("negative half") << QStringList{"match", "--half-duration", "-30"}
                                   << "--half-duration: must be > 0 s";
    QTest::newRow("zero half") << QStringList{"match", "--half-duration", "0"} << "--half-duration: must be > 0 s";
    QTest::newRow("negative seed") << QStringList{"match", "--seed", "-1"} << "--seed: expected a whole number";
    QTest::newRow("text seed") << QStringList{"match", "--seed", "lucky"} << "--seed: expected a whole number";
    QTest::newRow("huge seed") << QStringList{"match", "--seed", "9007199254740992"}
                               << "--seed: expected a whole number from 0 to 9007199254740991";
    QTest::newRow("too long") << QStringList{"match", "--halves", "1000", "--half-duration", "1e7"} << "steps";
    QTest::newRow("two scenes") << QStringList{"match", "kickoff_3v3", "kickoff_3v3"} << "expected at most one scene";
    QTest::newRow("missing scene") << QStringList{"match", "/nonexistent/scene.json"} << "no such file";
    QTest::newRow("field without goals") << QStringList{"match", sceneFile("robot_hits_ball.json")}
                                         << "the field has no goals";
    QTest::newRow("unknown option") << QStringList{"match", "--duration", "3"} << "Unknown option 'duration'";
    QTest::newRow("empty out") << QStringList{"match", "--out", ""} << "--out: expected a file name";
    QTest::newRow("bad left team") << QStringList{"match", "--left-team", "left"}
                                   << "--left-team: expected yellow or blue, got \"left\"";
}

void TestMatchCommand::badInput() {
    QFETCH(QStringList, args);
    QFETCH(QString, message);
    const Result r = runVssim(args);
    QCOMPARE(r.exitCode, 2);
    QVERIFY2(r.err.startsWith("vssim match: "), r.err.constData());
    QVERIFY2(QString::fromUtf8(r.err).contains(message), r.err.constData());
    QVERIFY(r.out.isEmpty());
}

void TestMatchCommand::textReport() {
    const Result r = runVssim(shortMatch({"--seed", "1"}));
    QCOMPARE(r.exitCode, 0);
    const QStringList lines = QString::fromUtf8(r.out).split('\n');
    QVERIFY2(lines.size() > 8, r.out.constData());
    QVERIFY(lines[0].startsWith("scene: the official 3 vs 3 field"));
    QCOMPARE(lines[1],
             QStringLiteral("match: 2 halves of 20 s, seed 1, yellow builtin (defends x < 0) vs blue builtin"));
    const QRegularExpressionMatch score =
        QRegularExpression("^final score: yellow (\\d+) - (\\d+) blue$").match(lines[2]);
    QVERIFY2(score.hasMatch(), qPrintable(lines[2]));
    QVERIFY(QRegularExpression("^\\d+ calls?:$").match(lines[4]).hasMatch());
    QVERIFY(lines[5].contains("time [s]") && lines[5].contains("quadrant") && lines[5].contains("reason"));
    // The first call is yellow's kick-off at 0; the second half starts with blue's.
    const QRegularExpression row("^ *([0-9.]+) +(\\d) +([0-9.]+)  (\\S+) +(\\S+) +(\\S+)  (.+)$");
    const QRegularExpressionMatch first = row.match(lines[6]);
    QVERIFY2(first.hasMatch(), qPrintable(lines[6]));
    QCOMPARE(first.captured(1), QStringLiteral("0.000"));
    QCOMPARE(first.captured(4), QStringLiteral("kickoff"));
    QCOMPARE(first.captured(5), QStringLiteral("yellow"));
    QCOMPARE(first.captured(6), QStringLiteral("-"));
    QCOMPARE(first.captured(7), QStringLiteral("first half"));
    int goals[2] = {0, 0}, secondHalf = 0;
    for (int i = 6; i < lines.size() && !lines[i].isEmpty(); ++i) {
        const QRegularExpressionMatch m = row.match(lines[i]);
        QVERIFY2(m.hasMatch(), qPrintable(lines[i]));
        if (m.captured(7) == "goal by yellow") ++goals[0];
        if (m.captured(7) == "goal by blue") ++goals[1];
        if (m.captured(7) == "half 2") {
            ++secondHalf;
            QCOMPARE(m.captured(2), QStringLiteral("2"));
            QCOMPARE(m.captured(5), QStringLiteral("blue"));
        }
    }
    QCOMPARE(secondHalf, 1);
    QCOMPARE(goals[0], score.captured(1).toInt());
    QCOMPARE(goals[1], score.captured(2).toInt());
    QVERIFY(QRegularExpression("^full time at [0-9.]+ s of simulated time \\(\\d+ steps of 0.001 s\\)$")
                .match(lines[lines.size() - 3])
                .hasMatch());
    QVERIFY(QRegularExpression("^match hash [0-9a-f]{16}, final state hash [0-9a-f]{16}$")
                .match(lines[lines.size() - 2])
                .hasMatch());
    QVERIFY2(r.err.contains("x real time"), r.err.constData());
}

void TestMatchCommand::leftTeamSwapsTheSides() {
    // Blue on the left: the report says so, and the built-in blue team,
    // alone against an idle yellow one, scores into the goal at x > 0
    // (goals by blue only: an own goal would be yellow's).
    const Result r = runVssim({"match", "--halves", "1", "--half-duration", "40", "--yellow", "idle", "--left-team",
                               "blue", "--json"});
    QCOMPARE(r.exitCode, 0);
    const QJsonObject o = QJsonDocument::fromJson(r.out).object();
    QCOMPARE(o["left_team"].toString(), QString("blue"));
    QVERIFY2(o["goals"].toObject()["blue"].toInt() >= 1, r.out.constData());
    QCOMPARE(o["goals"].toObject()["yellow"].toInt(), 0);
    const Result text = runVssim({"match", "--halves", "1", "--half-duration", "1", "--left-team", "blue"});
    QCOMPARE(text.exitCode, 0);
    QVERIFY2(text.out.contains("yellow builtin (defends x > 0) vs blue builtin"), text.out.constData());
}

void TestMatchCommand::jsonReport() {
    const Result r = runVssim(shortMatch({"--seed", "2", "--json"}));
    QCOMPARE(r.exitCode, 0);
    const QJsonObject o = jsonOf(r);
    QVERIFY2(!o.isEmpty(), r.out.constData());
    QVERIFY(o["scene"].isNull());
    QCOMPARE(o["seed"].toInteger(), 2);
    QCOMPARE(o["halves"].toInt(), 2);
    QCOMPARE(o["half_duration"].toDouble(), 20.0);
    QCOMPARE(o["yellow"].toString(), QStringLiteral("builtin"));
    QCOMPARE(o["blue"].toString(), QStringLiteral("builtin"));
    QCOMPARE(o["dt"].toDouble(), 0.001);
    QVERIFY(QRegularExpression("^[0-9a-f]{16}$").match(o["state_hash"].toString()).hasMatch());
    QVERIFY(QRegularExpression("^[0-9a-f]{16}$").match(o["match_hash"].toString()).hasMatch());
    const QJsonArray calls = o["calls"].toArray();
    QVERIFY(calls.size() >= 2);
    const QJsonObject first = calls[0].toObject();
    QCOMPARE(first["call"].toString(), QStringLiteral("kickoff"));
    QCOMPARE(first["team"].toString(), QStringLiteral("yellow"));
    QCOMPARE(first["time"].toDouble(), 0.0);
    QCOMPARE(first["half"].toInt(), 1);
    QVERIFY(first["quadrant"].isNull());
    int goals[2] = {0, 0};
    double lastTime = -1.0;
    for (const QJsonValue& v : calls) {
        const QJsonObject c = v.toObject();
        for (const char* key : {"time", "half", "clock", "call", "team", "quadrant", "reason"})
            QVERIFY2(c.contains(key), key);
        QVERIFY(c["time"].toDouble() >= lastTime);
        lastTime = c["time"].toDouble();
        QVERIFY(c["clock"].toDouble() >= 0.0 && c["clock"].toDouble() <= 20.0);
        if (c["call"] == "free_ball") {
            QVERIFY(c["team"].isNull());
            QVERIFY(c["quadrant"].toInt() >= 1 && c["quadrant"].toInt() <= 4);
        } else {
            QVERIFY(c["team"] == "yellow" || c["team"] == "blue");
        }
        if (c["reason"] == "goal by yellow") ++goals[0];
        if (c["reason"] == "goal by blue") ++goals[1];
    }
    QCOMPARE(o["goals"].toObject()["yellow"].toInt(), goals[0]);
    QCOMPARE(o["goals"].toObject()["blue"].toInt(), goals[1]);
    // Two halves of 20 s of game time, and 4 s of stop per call.
    const double simulated = o["simulated_time"].toDouble();
    QVERIFY(simulated >= 40.0 + 4.0 * calls.size() - 0.02);
    QCOMPARE(o["steps"].toInteger(), std::llround(simulated / 0.001));
}

void TestMatchCommand::sameSeedSameMatch() {
    const Result a = runVssim(shortMatch({"--seed", "7", "--json"}));
    const Result b = runVssim(shortMatch({"--seed", "7", "--json"}));
    QCOMPARE(a.exitCode, 0);
    QCOMPARE(b.exitCode, 0);
    QCOMPARE(jsonOf(a)["match_hash"].toString(), jsonOf(b)["match_hash"].toString());
    QCOMPARE(jsonOf(a)["state_hash"].toString(), jsonOf(b)["state_hash"].toString());
    QCOMPARE(a.out, b.out);  // the whole report: it depends on the scene and the options only
}

void TestMatchCommand::otherSeedOtherMatch() {
    // The seed jitters the placement after every call, so the matches part
    // for good: the final states differ too, not only the match hashes.
    for (const char* key : {"match_hash", "state_hash"}) {
        const QString h7 = jsonOf(runVssim(shortMatch({"--seed", "7", "--json"})))[key].toString();
        const QString h8 = jsonOf(runVssim(shortMatch({"--seed", "8", "--json"})))[key].toString();
        const QString h0 = jsonOf(runVssim(shortMatch({"--json"})))[key].toString();
        QVERIFY(!h7.isEmpty() && !h8.isEmpty() && !h0.isEmpty());
        QVERIFY2(h7 != h8, key);
        QVERIFY2(h7 != h0, key);
    }
}

void TestMatchCommand::outFile() {
    QTemporaryDir dir;
    const QString path = dir.filePath("match.json");
    const Result r = runVssim(shortMatch({"--seed", "3", "--json", "--out", path}));
    QCOMPARE(r.exitCode, 0);
    QVERIFY(r.out.isEmpty());
    QFile f(path);
    QVERIFY(f.open(QIODevice::ReadOnly));
    const Result same = runVssim(shortMatch({"--seed", "3", "--json"}));
    QCOMPARE(f.readAll(), same.out);
}

void TestMatchCommand::sceneByName() {
    const Result r = runVssim({"match", "kickoff_3v3", "--halves", "1", "--half-duration", "10", "--json"});
    QCOMPARE(r.exitCode, 0);
    const QJsonObject o = jsonOf(r);
    QCOMPARE(o["scene"].toString(), QStringLiteral("kickoff_3v3"));
    QCOMPARE(o["halves"].toInt(), 1);
    QCOMPARE(o["calls"].toArray()[0].toObject()["reason"].toString(), QStringLiteral("first half"));
}

void TestMatchCommand::idleTeamsScoreNothing() {
    const Result r =
        runVssim({"match", "--yellow", "idle", "--blue", "idle", "--halves", "1", "--half-duration", "12", "--json"});
    QCOMPARE(r.exitCode, 0);
    const QJsonObject o = jsonOf(r);
    QCOMPARE(o["goals"].toObject()["yellow"].toInt(), 0);
    QCOMPARE(o["goals"].toObject()["blue"].toInt(), 0);
    QCOMPARE(o["yellow"].toString(), QStringLiteral("idle"));
    // Nobody touches the ball at the centre: a free ball after 5 s and after 10 s.
    const QJsonArray calls = o["calls"].toArray();
    QCOMPARE(calls.size(), 3);
    QCOMPARE(calls[1].toObject()["call"].toString(), QStringLiteral("free_ball"));
    QCOMPARE(calls[1].toObject()["reason"].toString(), QStringLiteral("ball stuck"));
}

void TestMatchCommand::seedJittersThePlacements() {
    // vssim match passes its seed to the Match, which jitters the referee's
    // placements (match.h); the default scene's kick-off takes it.
    const Scene scene = defaultMatchScene(TeamControl::Builtin, TeamControl::Builtin);
    const Match plain(scene), a(scene, 42), b(scene, 42), c(scene, 43);
    const auto& p = plain.simulation().state().robots;
    const auto& ra = a.simulation().state().robots;
    const auto& rb = b.simulation().state().robots;
    const auto& rc = c.simulation().state().robots;
    QCOMPARE(p.size(), std::size_t(6));
    int moved = 0, differ = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        QCOMPARE(ra[i].x, rb[i].x);
        QCOMPARE(ra[i].y, rb[i].y);
        QCOMPARE(ra[i].theta, rb[i].theta);
        QVERIFY(std::abs(ra[i].x - p[i].x) <= Match::kPlacementJitter);
        QVERIFY(std::abs(ra[i].y - p[i].y) <= Match::kPlacementJitter);
        QVERIFY(std::abs(ra[i].theta - p[i].theta) <= Match::kHeadingJitter);
        moved += ra[i].x != p[i].x;
        differ += ra[i].x != rc[i].x;
    }
    QCOMPARE(moved, 6);
    QCOMPARE(differ, 6);
    QCOMPARE(a.game().phase, GamePhase::Stop);
}

QTEST_GUILESS_MAIN(TestMatchCommand)
#include "test_match_command.moc"
