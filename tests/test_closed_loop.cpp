// The closed loop, end to end, as a team would run it: `vssim serve` in its
// own process, an example client (examples/) that sees only camera images
// and sends only voltages, and this test as an observer reading the ground
// truth (STATE) to check that the client's robot really reaches the ball.
// Also `vssim serve`'s command line: errors, --help, the address it prints.
#include <QJsonDocument>
#include <QProcess>
#include <QTemporaryDir>
#include <QtTest>
#include <cmath>

#include "net/protocol_client.h"
#include "run_vssim.h"

using namespace vssim;

namespace {

// A `vssim serve` process; port() is the one it printed.
struct ServeProcess {
    QProcess process;
    quint16 port = 0;
    QString firstLine;
    explicit ServeProcess(const QStringList& args) {
        process.start(VSSIM_BINARY, QStringList{"serve"} + args + QStringList{"--port", "0", "--quit-after", "120"});
        if (process.waitForStarted(5000) && process.waitForReadyRead(10000)) {
            firstLine = QString::fromUtf8(process.readLine()).trimmed();
            port = static_cast<quint16>(firstLine.section(':', -1).toUInt());
        }
    }
    ~ServeProcess() {
        process.terminate();
        if (!process.waitForFinished(5000)) process.kill();
    }
};

}  // namespace

class TestClosedLoop : public QObject {
    Q_OBJECT
private slots:
    void clientDrivesToTheBallFromImagesOnly_data() {
        QTest::addColumn<QString>("program");
        QTest::addColumn<QStringList>("clientArgs");
        QTest::addColumn<bool>("lockstep");
        QTest::addColumn<double>("ballX");  // m: where the ball is put first, off the robot's axis
        QTest::addColumn<double>("ballY");
        // The realistic camera (the scene's "camera": {"preset": "realistic"}):
        // a pinhole lens 2 m up with distortion, uneven light, a colour cast,
        // noise, motion blur, and images 50 to 60 ms late, 1% dropped.
        QTest::addColumn<bool>("realistic");
        // Where the client's robot starts (x, y in m, theta in rad); empty: the scene's place.
        QTest::addColumn<QVector<double>>("robotPose");
        const QString python = QStringLiteral(VSSIM_SOURCE_DIR "/examples/python/vssim_client.py");
        for (const bool realistic : {false, true}) {
            const char* camera = realistic ? ", realistic camera" : "";
            QTest::addRow("python, lockstep, png%s", camera)
                << QString("/usr/bin/python3") << QStringList{python, "--lockstep"} << true << -0.2 << 0.45 << realistic
                << QVector<double>{};
            QTest::addRow("C++, lockstep, jpeg%s", camera)
                << QString(VSSIM_EXAMPLE_CLIENT) << QStringList{"--lockstep", "--encoding", "jpeg"} << true << 0.4 << -0.5
                << realistic << QVector<double>{};
            QTest::addRow("C++, blue 0, real time, raw%s", camera)
                << QString(VSSIM_EXAMPLE_CLIENT) << QStringList{"--team", "blue", "--robot", "0", "--encoding", "raw"}
                << false << 0.55 << 0.5 << realistic << QVector<double>{};
        }
        // Just short of blue's upper goal post, facing 60 degrees: the robot's
        // front-right corner inside the goal mouth, the post 8.5 mm in front of
        // its front face. Driving on presses that face onto the post, and
        // turning left, towards the ball, swings it into the post: the robot is
        // caught at (0.715, 0.178), where the real-time case with the realistic
        // camera once ended under ctest -j2. The go-to-point law alone pushes
        // on there until --max-time; the clients' Unstick backs it off.
        const QVector<double> caught{0.71, 0.17, 60.0 * 3.14159265358979323846 / 180.0};
        QTest::addRow("C++, blue 0, lockstep, raw, caught on a goal post")
            << QString(VSSIM_EXAMPLE_CLIENT)
            << QStringList{"--team", "blue", "--robot", "0", "--lockstep", "--encoding", "raw", "--max-time", "5"}
            << true << 0.55 << 0.5 << false << caught;
        QTest::addRow("python, blue 0, lockstep, raw, caught on a goal post")
            << QString("/usr/bin/python3")
            << QStringList{python, "--team", "blue", "--robot", "0", "--lockstep", "--encoding", "raw", "--max-time", "5"}
            << true << 0.55 << 0.5 << false << caught;
        // A ball near a corner, where the lens bends most and the top face's
        // parallax is largest (2.9 cm at 0.75 m from the centre).
        QTest::addRow("python, blue 1, lockstep, raw, realistic camera, ball in a corner")
            << QString("/usr/bin/python3") << QStringList{python, "--team", "blue", "--robot", "1", "--lockstep", "--encoding", "raw"}
            << true << 0.62 << -0.5 << true << QVector<double>{};
    }

    void clientDrivesToTheBallFromImagesOnly() {
        QFETCH(QString, program);
        QFETCH(QStringList, clientArgs);
        QFETCH(bool, lockstep);
        QFETCH(double, ballX);
        QFETCH(double, ballY);
        QFETCH(bool, realistic);
        QFETCH(QVector<double>, robotPose);
        // The kick-off's field without a game (the built-in scene is a match of
        // the built-in team against itself): every robot left to clients. With
        // the realistic camera, the same scene with its "camera" key.
        QString scene = "kickoff_3v3";
        QTemporaryDir dir;
        if (realistic) {
            QFile builtIn(VSSIM_SOURCE_DIR "/resources/scenes/kickoff_3v3.json");
            QVERIFY(builtIn.open(QIODevice::ReadOnly));
            QJsonObject root = QJsonDocument::fromJson(builtIn.readAll()).object();
            root["camera"] = QJsonObject{{"preset", "realistic"}};
            scene = dir.filePath("kickoff_3v3_realistic.json");
            QFile file(scene);
            QVERIFY(file.open(QIODevice::WriteOnly) && file.write(QJsonDocument(root).toJson()) > 0);
        }
        const QStringList bare{scene, "--referee", "off", "--yellow", "tcp", "--blue", "tcp"};
        ServeProcess serve(lockstep ? bare + QStringList{"--lockstep"} : bare);
        QVERIFY2(serve.port != 0, qPrintable("vssim serve printed: " + serve.firstLine));

        ProtocolClient observer;
        QVERIFY(observer.connectTo(serve.port));
        // The observer's STATE is the ground truth: without the scene camera's
        // delay, drops and noise (a HELLO's own camera, docs/protocol.md), so
        // that it also sees the last instants before the client stops stepping.
        const QJsonObject exact{{"latency", 0},        {"jitter", 0},        {"drop", 0},
                                {"position_noise", 0}, {"heading_noise", 0}, {"vanish", 0}};
        const auto welcome = observer.hello(QJsonObject{
            {"protocol", 1}, {"role", "observer"}, {"images", "none"}, {"state", true}, {"camera", exact}});
        QVERIFY(welcome);
        // The camera the clients are told about (docs/protocol.md, WELCOME):
        // the ideal one is orthographic (older servers: no "projection").
        const QJsonObject camera = (*welcome)["camera"].toObject();
        if (realistic)
            QVERIFY2(camera["projection"].toString() == "pinhole" && camera["matrix"].isArray() &&
                         camera["distortion"].isArray() && camera["settings"].isObject(),
                     "WELCOME's camera is not the realistic one: does vssim serve render the scene's `camera` "
                     "and describe its lens in WELCOME?");
        else
            QVERIFY(camera["projection"].toString("orthographic") == "orthographic");
        observer.sendJson(protocol::MessageType::Control,
                          QJsonObject{{"command", "place_ball"}, {"x", ballX}, {"y", ballY}});
        const auto placed = observer.nextOf(protocol::MessageType::Reply);
        QVERIFY(placed && jsonPayload(placed->message)["ok"].toBool());
        // Which robot the client drives: its team and identity id. (vssim
        // serve applies no scene commands by default: only the client moves it.)
        const QString team = clientArgs.contains("blue") ? "blue" : "yellow";
        const int id = clientArgs.contains("--robot") ? clientArgs[clientArgs.indexOf("--robot") + 1].toInt() : 0;
        int robot = -1;
        double side = 0;
        for (const QJsonValue& r : (*welcome)["robots"].toArray()) {
            if (r["team"].toString() == team && r["id"].toInt() == id) {
                robot = r["index"].toInt();
                side = r["side"].toDouble();
            }
        }
        QVERIFY(robot >= 0);
        if (robotPose.size() == 3) {
            observer.sendJson(protocol::MessageType::Control,
                              QJsonObject{{"command", "place_robot"},
                                          {"robot", robot},
                                          {"x", robotPose[0]},
                                          {"y", robotPose[1]},
                                          {"theta", robotPose[2]}});
            // A refusal (outside_field, ...) is an ERROR, not a REPLY.
            const auto reply = std::uint8_t(protocol::MessageType::Reply);
            const auto error = std::uint8_t(protocol::MessageType::Error);
            int answerType = -1;
            QJsonObject robotPlaced;
            while (answerType < 0) {
                const auto m = observer.next();
                if (!m) break;
                if (m->message.type == reply || m->message.type == error) {
                    answerType = m->message.type;
                    robotPlaced = jsonPayload(m->message);
                }
            }
            QVERIFY2(answerType >= 0, "no answer to place_robot");
            QVERIFY2(answerType == reply && robotPlaced["ok"].toBool(),
                     qPrintable("place_robot: " + QJsonDocument(robotPlaced).toJson(QJsonDocument::Compact)));
        }
        const double reach = 0.5 * side + (*welcome)["ball"].toObject()["radius"].toDouble();

        QProcess client;
        client.setProcessChannelMode(QProcess::MergedChannels);
        QStringList args = clientArgs + QStringList{"--port", QString::number(serve.port)};
        if (!args.contains("--max-time")) args << "--max-time" << "20";
        client.start(program, args);
        QVERIFY2(client.waitForStarted(10000), qPrintable(program + ": " + client.errorString()));

        // Follow the ground truth until the client exits.
        double closest = 1e9, last = 1e9, startDistance = -1, lastTime = 0;
        QElapsedTimer wall;
        wall.start();
        // (After it exits, the states already sent are still read: 300 ms more.)
        qint64 drainUntil = -1;
        while (wall.elapsed() < 90000 && (drainUntil < 0 || wall.elapsed() < drainUntil)) {
            if (drainUntil < 0 && client.state() == QProcess::NotRunning) drainUntil = wall.elapsed() + 300;
            while (auto m = observer.next(20)) {
                if (m->message.type != std::uint8_t(protocol::MessageType::State)) continue;
                const QJsonObject state = jsonPayload(m->message);
                const QJsonObject r = state["robots"].toArray()[robot].toObject();
                const QJsonObject ball = state["ball"].toObject();
                last = std::hypot(r["x"].toDouble() - ball["x"].toDouble(), r["y"].toDouble() - ball["y"].toDouble());
                if (startDistance < 0) startDistance = last;
                closest = std::min(closest, last);
                lastTime = state["time"].toDouble();
            }
            client.waitForFinished(10);
        }
        const QString output = QString::fromUtf8(client.readAll());
        QVERIFY2(client.state() == QProcess::NotRunning, "the client did not finish within 90 s");
        QVERIFY2(client.exitStatus() == QProcess::NormalExit && client.exitCode() == 0, qPrintable(output));
        QVERIFY2(output.contains("reached the ball"), qPrintable(output));
        QVERIFY2(output.contains(realistic ? "pinhole camera" : "orthographic camera"), qPrintable(output));
        // The ground truth agrees: it started well away and ended touching
        // distance (within the client's 1.5 cm tolerance and its image
        // error, 5 mm). With the realistic camera the client also moves
        // each body forward by its velocity times the images' 55 to 60 ms
        // delay (Predictor), while the robot slows down onto the ball
        // (about 0.3 m/s there): the prediction runs ahead of the robot by
        // up to about a centimetre, so the client stops that much short.
        // (Measured: 0.071 to 0.073 m alone, 0.072 to 0.078 m beside two
        // busy cores, 0.080 m once under ctest -j2, against a contact
        // distance of 0.059 m: the 2 cm allowed before left 0.9 mm.)
        QVERIFY2(startDistance > reach + 0.1, qPrintable(QString::number(startDistance)));
        const double allowed = realistic ? 0.03 : 0.02;  // m beyond contact
        QVERIFY2(closest < reach + allowed,
                 qPrintable(QString("closest %1 m, reach %2 m; client said: %3").arg(closest).arg(reach).arg(output)));
        QVERIFY(lastTime > 0.1);
        qInfo("%s: from %.3f m to %.3f m (contact at %.3f m) by t = %.2f s; client: %s", QTest::currentDataTag(),
              startDistance, closest, reach, lastTime, qPrintable(output.trimmed().section('\n', -1)));
    }

    void serveCommandLine() {
        using test::runVssim;
        const test::Result help = runVssim({"serve", "--help"});
        QCOMPARE(help.exitCode, 0);
        QVERIFY(help.out.contains("--lockstep") && help.out.contains("docs/protocol.md"));
        QVERIFY(help.out.contains("--firasim") && help.out.contains("--vssref") && help.out.contains("docs/firasim.md"));
        QVERIFY(help.out.contains("--camera ideal|realistic"));
        const struct {
            QStringList args;
            const char* says;
        } bad[] = {
            {{"serve"}, "a scene is required"},
            {{"serve", "no_such_scene"}, "no scene file or built-in scene"},
            {{"serve", "kickoff_3v3", "--port", "70000"}, "--port"},
            {{"serve", "kickoff_3v3", "--port", "x"}, "--port"},
            {{"serve", "kickoff_3v3", "--listen", "localhost:1"}, "--listen"},
            {{"serve", "kickoff_3v3", "--speed", "0"}, "--speed"},
            {{"serve", "kickoff_3v3", "--speed", "nan"}, "--speed"},
            {{"serve", "kickoff_3v3", "--speed", "2", "--lockstep"}, "exclude"},
            {{"serve", "kickoff_3v3", "--hello-timeout", "-1"}, "--hello-timeout"},
            {{"serve", "kickoff_3v3", "--bogus"}, "bogus"},
            {{"serve", "a", "b"}, "one scene only"},
            // FIRASim's interface and VSSReferee's protocol.
            {{"serve", "kickoff_3v3", "--vision-port", "10002"}, "--vision-port needs --firasim"},
            {{"serve", "kickoff_3v3", "--firasim", "--vision-port", "0"}, "--vision-port: expected 1 to 65535"},
            {{"serve", "kickoff_3v3", "--firasim", "--firasim-port", "65536"}, "--firasim-port: expected 0 to 65535"},
            {{"serve", "kickoff_3v3", "--firasim", "--vision-address", "vision"}, "--vision-address"},
            {{"serve", "kickoff_3v3", "--firasim", "--vision-rate", "5000"}, "--vision-rate"},
            {{"serve", "kickoff_3v3", "--firasim", "--vision-rate", "nan"}, "--vision-rate"},
            {{"serve", "kickoff_3v3", "--firasim", "--multicast-ttl", "300"}, "--multicast-ttl"},
            {{"serve", "kickoff_3v3", "--multicast-ttl", "1"}, "--multicast-ttl needs --firasim or --vssref"},
            {{"serve", "kickoff_3v3", "--firasim-sync", "--speed", "2"}, "exclude"},
            {{"serve", "kickoff_3v3", "--referee", "external"}, "--referee external needs --firasim"},
            {{"serve", "kickoff_3v3", "--referee", "maybe"}, "--referee"},
            {{"serve", "kickoff_3v3", "--camera", "fisheye"}, "--camera: expected ideal or realistic, got \"fisheye\""},
            {{"serve", "kickoff_3v3", "--left-team", "left"}, "--left-team: expected yellow or blue, got \"left\""},
            {{"serve", "kickoff_3v3", "--vssref-address", "127.0.0.1"}, "--vssref-address needs --vssref"},
            {{"serve", "kickoff_3v3", "--vssref", "--referee", "off"}, "--vssref speaks for the built-in referee"},
            {{"serve", "kickoff_3v3", "--vssref", "--vssref-placement-port", "0"}, "--vssref-placement-port"},
        };
        for (const auto& b : bad) {
            const test::Result r = runVssim(b.args);
            QVERIFY2(r.exitCode == 2, qPrintable(b.args.join(' ') + ": exit " + QString::number(r.exitCode)));
            QVERIFY2(r.err.contains(b.says), qPrintable(b.args.join(' ') + ": " + r.err));
        }
        // A port in use: exit 1 with the reason.
        ServeProcess first({"kickoff_3v3", "--lockstep"});
        QVERIFY(first.port != 0);
        QCOMPARE(first.firstLine, QString("listening on 127.0.0.1:%1").arg(first.port));
        const test::Result busy = runVssim({"serve", "kickoff_3v3", "--port", QString::number(first.port)});
        QCOMPARE(busy.exitCode, 1);
        QVERIFY2(busy.err.contains("cannot listen"), busy.err.constData());
        // --quit-after ends a server cleanly.
        const test::Result quits = runVssim({"serve", "kickoff_3v3", "--port", "0", "--quit-after", "0.3"});
        QCOMPARE(quits.exitCode, 0);
        QVERIFY(quits.out.startsWith("listening on 127.0.0.1:"));
    }
};

QTEST_GUILESS_MAIN(TestClosedLoop)
#include "test_closed_loop.moc"
