#include "serve_command.h"

#include <QCommandLineParser>
#include <QCoreApplication>
#include <QDateTime>
#include <QFileInfo>
#include <QHostAddress>
#include <QTextStream>
#include <QTimer>
#include <atomic>
#include <cmath>
#include <csignal>
#include <memory>

#include "firasim/firasim_server.h"
#include "firasim/vssref_bridge.h"
#include "vssim/camera/camera_renderer.h"
#include "io/scene_io.h"
#include "net/control_server.h"
#include "net/network_address.h"
#include "realtime/engine_thread.h"
#include "realtime/monotonic_clock.h"

namespace vssim {

namespace {

std::atomic<int> stopSignal{0};

extern "C" void onStopSignal(int signal) { stopSignal.store(signal); }

QTextStream& err() {
    static QTextStream stream(stderr);
    return stream;
}

}  // namespace

// The FIRASim vision rates accepted, Hz of simulated time.
constexpr double kMinVisionRate = 1.0;
constexpr double kMaxVisionRate = 1000.0;

QString serveHelpText() {
    return QStringLiteral(
               "Usage: vssim serve SCENE [options]\n"
               "\n"
               "Runs SCENE (a scene file or a built-in scene name) headless and serves it over TCP:\n"
               "clients send motor voltages and receive camera images every 30 ms of simulated\n"
               "time and, if they ask, the ground truth (protocol: docs/protocol.md).\n"
               "\n"
               "Options:\n"
               "  --port N             TCP port (default %1; 0: any free port)\n"
               "  --listen ADDR        address to listen on (default 127.0.0.1; 0.0.0.0: every interface,\n"
               "                       with no authentication: only on a network you trust)\n"
               "  --speed X|max        simulated seconds per wall second, 0.001 to 100 (default 1), or max:\n"
               "                       as fast as possible\n"
               "  --lockstep           time advances only when a client sends CONTROL step\n"
               "  --paused             start paused (CONTROL resume or step)\n"
               "  --scene-commands     also apply the scene's own voltage commands (by default only the\n"
               "                       clients drive the robots)\n"
               "  --read-only-observers\n"
               "                       observers may only watch and ask for stats: their pause, resume,\n"
               "                       step, reset, place_robot, place_ball, speed, halt, game_on and call\n"
               "                       get ERROR read_only\n"
               "                       (for matches: only the teams' clients control the game)\n"
               "  --yellow CONTROL, --blue CONTROL\n"
               "                       who drives the team, overriding the scene's game section: builtin\n"
               "                       (vssim's built-in team), tcp (a client: HELLO as that team) or idle\n"
               "                       (nobody: 0 V). A team that is not tcp refuses clients (ERROR\n"
               "                       role_not_remote)\n"
               "  --referee on|off|external\n"
               "                       the automatic referee (score, clock, fouls, placements; needs a field\n"
               "                       with goals), overriding the scene's game.referee; external: off, for a\n"
               "                       referee of your own such as VSSReferee (needs --firasim; the FIRASim\n"
               "                       vision's goals then stay 0:0, as FIRASim's do)\n"
               "  --left-team yellow|blue\n"
               "                       the team that defends the goal at x < 0 (and attacks x > 0) for the\n"
               "                       whole match, overriding the scene's game.left_team. Default: the\n"
               "                       scene's (yellow unless it says), but blue with --firasim when the\n"
               "                       scene does not say: FIRASim's layout, which FIRASim-based team\n"
               "                       software and VSSReferee assume\n"
               "  --camera ideal|realistic\n"
               "                       the camera preset, replacing the scene's camera (docs/scenes.md):\n"
               "                       ideal is today's exact top view and instant delivery; realistic a\n"
               "                       webcam's lens, light, noise, blur, 50 ms latency and drops, and\n"
               "                       millimetre-scale noise on STATE and the FIRASim vision (where a\n"
               "                       vanished ball leaves the frame without a ball). Every client gets\n"
               "                       that delivery and noise, observers and loggers too, unless its\n"
               "                       HELLO sets its own: \"camera\": {\"latency\": 0, ...} (docs/protocol.md)\n"
               "  --hello-timeout S    seconds a new client has to say HELLO (default 5)\n"
               "  --quit-after S       stop after S wall-clock seconds (for scripts and benchmarks)\n"
               "  -h, --help           this help\n"
               "\n"
               "FIRASim's interface (docs/firasim.md), beside the TCP server:\n"
               "  --firasim            receive FIRASim commands and replacement (UDP, on the --listen\n"
               "                       address) and send FIRASim vision at every camera instant\n"
               "  --firasim-port N     UDP port for commands and replacement (default %7; 0: any free port)\n"
               "  --vision-address ADDR\n"
               "                       where the vision goes: a multicast group or a unicast host\n"
               "                       (default %8)\n"
               "  --vision-port N      vision UDP port (default %9)\n"
               "  --vision-rate HZ     vision (and camera) messages per second of simulated time, %10 to %11\n"
               "                       (default 60: on average, each message at the first step at or\n"
               "                       after its multiple of the period, whatever the game's tick)\n"
               "  --multicast-ttl N    multicast hops, 0 to 255 (default 0: this machine only)\n"
               "  --firasim-sync       lockstep driven by FIRASim: each packet with commands advances one\n"
               "                       vision period and its vision goes out at the end (implies --firasim;\n"
               "                       excludes --speed and --lockstep)\n"
               "\n"
               "VSSReferee's protocol for the built-in referee (docs/firasim.md):\n"
               "  --vssref             send the referee's commands as VSSRef_Command and take the teams'\n"
               "                       VSSRef_Placement (needs the built-in referee)\n"
               "  --vssref-address ADDR\n"
               "                       multicast group (or unicast address) of both (default 224.5.23.2)\n"
               "  --vssref-command-port N\n"
               "                       where the commands go (default 10003)\n"
               "  --vssref-placement-port N\n"
               "                       where placements are read (default 10004)\n"
               "\n"
               "Clients are served fairly, and what the server holds for them is bounded: at most %2\n"
               "connections (when full, the oldest one without HELLO makes room for a new one), %3\n"
               "ERRORs per client in %4 s, %5 MiB unsent for a client and %6 MiB for all (a client that\n"
               "does not read is disconnected): docs/protocol.md, Limits.\n"
               "\n"
               "On start it prints \"listening on ADDR:PORT\" on standard output (and, with --firasim,\n"
               "\"firasim: commands on ADDR:PORT, vision to ADDR:PORT\"); the log (connections,\n"
               "errors, disconnections) goes to standard error. Stop it with Ctrl-C.\n"
               "Exit status: 0 stopped, 1 cannot listen, 2 bad usage or scene.\n")
        .arg(protocol::kDefaultPort)
        .arg(ServerSettings{}.maxClients)
        .arg(kMaxErrorsPerWindow)
        .arg(kErrorWindowNs / 1'000'000'000)
        .arg(ServerSettings{}.maxUnsentBytes >> 20)
        .arg(ServerSettings{}.maxTotalUnsentBytes >> 20)
        .arg(FirasimSettings{}.commandPort)
        .arg(FirasimSettings{}.visionAddress.toString())
        .arg(FirasimSettings{}.visionPort)
        .arg(kMinVisionRate)
        .arg(kMaxVisionRate);
}

int serveCommand(const QStringList& arguments) {
    QCommandLineParser parser;
    parser.setSingleDashWordOptionMode(QCommandLineParser::ParseAsLongOptions);
    const QCommandLineOption help({"h", "help"}, "help");
    const QCommandLineOption port("port", "port", "N");
    const QCommandLineOption listen("listen", "address", "ADDR");
    const QCommandLineOption speed("speed", "speed", "X");
    const QCommandLineOption lockstep("lockstep", "lockstep");
    const QCommandLineOption paused("paused", "paused");
    const QCommandLineOption helloTimeout("hello-timeout", "s", "S");
    const QCommandLineOption quitAfter("quit-after", "s", "S");
    const QCommandLineOption sceneCommands("scene-commands", "scene commands");
    const QCommandLineOption readOnlyObservers("read-only-observers", "read-only observers");
    const QCommandLineOption yellow("yellow", "control", "CONTROL");
    const QCommandLineOption blue("blue", "control", "CONTROL");
    const QCommandLineOption referee("referee", "on|off|external", "ON");
    const QCommandLineOption camera("camera", "ideal|realistic", "PRESET");
    const QCommandLineOption leftTeam("left-team", "yellow|blue", "TEAM");
    const QCommandLineOption firasim("firasim", "firasim");
    const QCommandLineOption firasimPort("firasim-port", "port", "N");
    const QCommandLineOption visionAddress("vision-address", "address", "ADDR");
    const QCommandLineOption visionPort("vision-port", "port", "N");
    const QCommandLineOption visionRate("vision-rate", "Hz", "HZ");
    const QCommandLineOption multicastTtl("multicast-ttl", "hops", "N");
    const QCommandLineOption firasimSync("firasim-sync", "sync");
    const QCommandLineOption vssref("vssref", "vssref");
    const QCommandLineOption vssrefAddress("vssref-address", "address", "ADDR");
    const QCommandLineOption vssrefCommandPort("vssref-command-port", "port", "N");
    const QCommandLineOption vssrefPlacementPort("vssref-placement-port", "port", "N");
    parser.addOptions({help,          port,         listen,     speed,         lockstep,
                       paused,        helloTimeout, quitAfter,  sceneCommands, readOnlyObservers,
                       yellow,        blue,         referee,    firasim,       firasimPort,
                       visionAddress, visionPort,   visionRate, multicastTtl,  firasimSync,
                       vssref,        vssrefAddress, vssrefCommandPort, vssrefPlacementPort, camera, leftTeam});
    auto usage = [](const QString& message) {
        err() << "vssim serve: " << message << "\n(see vssim serve --help)\n";
        err().flush();
        return 2;
    };
    if (!parser.parse(arguments)) return usage(parser.errorText());
    if (parser.isSet(help)) {
        QTextStream(stdout) << serveHelpText();
        return 0;
    }
    if (parser.positionalArguments().size() != 1)
        return usage(parser.positionalArguments().isEmpty()
                         ? QStringLiteral("a scene is required")
                         : QStringLiteral("one scene only, got %1").arg(parser.positionalArguments().join(' ')));

    ServerSettings server;
    EngineLoopSettings loop;
    // An option's port (`lowest` 0: any free port allowed) or address, into
    // *out if given; false after a usage error.
    auto portOption = [&](const QCommandLineOption& option, quint16 lowest, quint16* out) {
        if (!parser.isSet(option)) return true;
        const std::optional<quint16> value = parsePort(parser.value(option));
        if (!value || *value < lowest) {
            usage(QStringLiteral("--%1: expected %2 to 65535, got \"%3\"")
                      .arg(option.names().first())
                      .arg(lowest)
                      .arg(parser.value(option)));
            return false;
        }
        *out = *value;
        return true;
    };
    auto addressOption = [&](const QCommandLineOption& option, QHostAddress* out) {
        if (!parser.isSet(option)) return true;
        QHostAddress address;
        if (!address.setAddress(parser.value(option))) {
            usage(QStringLiteral("--%1: \"%2\" is not an IPv4 or IPv6 address")
                      .arg(option.names().first(), parser.value(option)));
            return false;
        }
        *out = address;
        return true;
    };
    if (!portOption(port, 0, &server.port) || !addressOption(listen, &server.address)) return 2;
    auto seconds = [&](const QCommandLineOption& option, const QString& name, double* out) {
        bool ok = false;
        const double value = parser.value(option).toDouble(&ok);
        if (!ok || !std::isfinite(value) || value <= 0 || value > 1e6) {
            usage(QStringLiteral("--%1: expected a number of seconds > 0, got \"%2\"").arg(name, parser.value(option)));
            return false;
        }
        *out = value;
        return true;
    };
    if (parser.isSet(speed)) {
        const QString text = parser.value(speed);
        bool ok = false;
        const double value = text.toDouble(&ok);
        if (text == "max") {
            loop.mode = RunMode::Max;
        } else if (ok && value >= kMinSpeed && value <= kMaxSpeed) {
            loop.speed = value;
        } else {
            return usage(
                QStringLiteral("--speed: expected a factor from %1 to %2 (1 = real time) or \"max\", got \"%3\"")
                    .arg(kMinSpeed)
                    .arg(kMaxSpeed)
                    .arg(text));
        }
    }
    if (parser.isSet(lockstep)) {
        if (parser.isSet(speed)) return usage("--lockstep and --speed exclude each other");
        loop.mode = RunMode::Lockstep;
    }
    // FIRASim's interface.
    FirasimSettings fira;
    const bool firasimOn = parser.isSet(firasim) || parser.isSet(firasimSync);
    for (const QCommandLineOption* option : {&firasimPort, &visionAddress, &visionPort, &visionRate}) {
        if (parser.isSet(*option) && !firasimOn)
            return usage(QStringLiteral("--%1 needs --firasim").arg(option->names().first()));
    }
    if (parser.isSet(multicastTtl) && !firasimOn && !parser.isSet(vssref))
        return usage("--multicast-ttl needs --firasim or --vssref");
    if (parser.isSet(firasimSync)) {
        if (parser.isSet(speed)) return usage("--firasim-sync and --speed exclude each other");
        if (parser.isSet(lockstep)) return usage("--firasim-sync and --lockstep exclude each other");
        loop.mode = RunMode::Lockstep;
        fira.sync = true;
    }
    fira.listenAddress = server.address;
    if (!portOption(firasimPort, 0, &fira.commandPort) || !portOption(visionPort, 1, &fira.visionPort) ||
        !addressOption(visionAddress, &fira.visionAddress))
        return 2;
    if (parser.isSet(multicastTtl)) {
        bool ok = false;
        const int value = parser.value(multicastTtl).toInt(&ok);
        if (!ok || value < 0 || value > 255)
            return usage(
                QStringLiteral("--multicast-ttl: expected 0 to 255, got \"%1\"").arg(parser.value(multicastTtl)));
        fira.multicastTtl = value;
    }
    // VSSReferee's protocol.
    VssRefSettings ref;
    for (const QCommandLineOption* option : {&vssrefAddress, &vssrefCommandPort, &vssrefPlacementPort})
        if (parser.isSet(*option) && !parser.isSet(vssref))
            return usage(QStringLiteral("--%1 needs --vssref").arg(option->names().first()));
    if (!addressOption(vssrefAddress, &ref.commandAddress) || !portOption(vssrefCommandPort, 1, &ref.commandPort) ||
        !portOption(vssrefPlacementPort, 1, &ref.placementPort))
        return 2;
    ref.placementAddress = ref.commandAddress;
    if (parser.isSet(multicastTtl)) ref.multicastTtl = fira.multicastTtl;
    double rate = 60.0;  // FIRASim vision, Hz asked for
    if (firasimOn) {
        if (parser.isSet(visionRate)) {
            bool ok = false;
            rate = parser.value(visionRate).toDouble(&ok);
            if (!ok || !std::isfinite(rate) || rate < kMinVisionRate || rate > kMaxVisionRate)
                return usage(QStringLiteral("--vision-rate: expected %1 to %2 messages per second, got \"%3\"")
                                 .arg(kMinVisionRate)
                                 .arg(kMaxVisionRate)
                                 .arg(parser.value(visionRate)));
        }
        loop.framePeriod = 1.0 / rate;
    }
    double helloSeconds = 5.0;
    if (parser.isSet(helloTimeout) && !seconds(helloTimeout, "hello-timeout", &helloSeconds)) return 2;
    server.helloTimeoutMs = static_cast<int>(std::ceil(helloSeconds * 1000));
    server.readOnlyObservers = parser.isSet(readOnlyObservers);
    double quitSeconds = 0.0;
    if (parser.isSet(quitAfter) && !seconds(quitAfter, "quit-after", &quitSeconds)) return 2;

    const QString sceneArgument = parser.positionalArguments().first();
    const QString scenePath = resolveScenePath(sceneArgument);
    if (scenePath.isEmpty())
        return usage(QStringLiteral("no scene file or built-in scene \"%1\" (built in: %2)")
                         .arg(sceneArgument, builtinSceneNames().join(", ")));
    QString error;
    std::optional<Scene> scene = loadSceneFile(scenePath, &error);
    if (!scene) {
        err() << "vssim serve: " << error << "\n";
        return 2;
    }
    // The game: who drives each team, and the referee.
    for (const auto& [option, control] :
         {std::pair{&yellow, &scene->game.yellow}, std::pair{&blue, &scene->game.blue}}) {
        if (!parser.isSet(*option)) continue;
        const QString text = parser.value(*option);
        const std::optional<TeamControl> value =
            text == "tcp" ? std::optional(TeamControl::Remote) : teamControlFromName(text);
        if (!value)
            return usage(
                QStringLiteral("--%1: expected builtin, tcp or idle, got \"%2\"").arg(option->names().first(), text));
        *control = *value;
    }
    bool externalReferee = false;
    if (parser.isSet(referee)) {
        const QString text = parser.value(referee);
        if (text != "on" && text != "off" && text != "external")
            return usage(QStringLiteral("--referee: expected on, off or external, got \"%1\"").arg(text));
        externalReferee = text == "external";
        if (externalReferee && !firasimOn)
            return usage("--referee external needs --firasim (the external referee speaks FIRASim's interface)");
        scene->game.rules.referee = text == "on";
        if (scene->game.rules.referee && !fieldHasGoals(scene->field))
            return usage(QStringLiteral("--referee on: %1: %2").arg(scenePath, refereeFieldProblem()));
    }
    // The sides: --left-team, else the scene file's game.left_team, else
    // FIRASim's layout (blue on the left) when FIRASim's interface is on.
    if (parser.isSet(leftTeam)) {
        const QString text = parser.value(leftTeam);
        const std::optional<Team> team = teamFromName(text);
        if (!team) return usage(QStringLiteral("--left-team: expected yellow or blue, got \"%1\"").arg(text));
        scene->game.rules.left_team = *team;
    } else if (firasimOn && !sceneNamesLeftTeam(scenePath)) {
        scene->game.rules.left_team = Team::Blue;
    }
    if (parser.isSet(camera)) {
        const QString text = parser.value(camera);
        if (text != "ideal" && text != "realistic")
            return usage(QStringLiteral("--camera: expected ideal or realistic, got \"%1\"").arg(text));
        scene->camera = text == "ideal" ? idealCamera() : realisticCamera();
    }
    if (const std::string problem = cameraProblem(*scene); !problem.empty()) {
        err() << "vssim serve: " << scenePath << ": " << QString::fromStdString(problem) << "\n";
        return 2;
    }
    const std::size_t scheduled = scene->commands.size();
    if (!parser.isSet(sceneCommands)) scene->commands.clear();
    if (scene->robots.size() > 255) {
        err() << "vssim serve: " << scenePath << ": " << scene->robots.size()
              << " robots; the protocol addresses at most 255 (robot indices are one byte)\n";
        return 2;
    }

    auto log = [](const QString& line) {
        err() << QDateTime::currentDateTime().toString("HH:mm:ss.zzz") << " " << line << "\n";
        err().flush();
    };
    EngineThread engine(*scene, loop);
    ControlServer control(*scene, engine, server);
    QObject::connect(&control, &ControlServer::logLine, log);
    if (!control.listen(&error)) {
        err() << "vssim serve: " << error << "\n";
        return 1;
    }
    if (parser.isSet(vssref) && !scene->game.rules.referee)
        return usage(QStringLiteral("--vssref speaks for the built-in referee, which is off (%1)")
                         .arg(parser.isSet(referee) ? QStringLiteral("--referee %1").arg(parser.value(referee))
                                                    : QStringLiteral("the scene's game.referee; --referee on")));
    std::unique_ptr<VssRefBridge> vssrefBridge;
    if (parser.isSet(vssref)) {  // before engine.start(): it observes the engine
        vssrefBridge = std::make_unique<VssRefBridge>(*scene, engine, ref);
        QObject::connect(vssrefBridge.get(), &VssRefBridge::logLine, log);
        if (!vssrefBridge->open(&error)) {
            err() << "vssim serve: --vssref: " << error << "\n";
            return 1;
        }
    }
    std::unique_ptr<FirasimServer> firasimServer;
    if (firasimOn) {
        firasimServer = std::make_unique<FirasimServer>(*scene, engine, fira);
        QObject::connect(firasimServer.get(), &FirasimServer::logLine, log);
        if (!firasimServer->listen(&error)) {
            err() << "vssim serve: " << error << "\n";
            return 1;
        }
    }
    if (parser.isSet(paused)) {
        EngineRequest pause;
        pause.kind = EngineRequest::Kind::Pause;
        pause.arrivalNs = monotonicNs();
        engine.post(pause);
    }
    engine.start();
    QTextStream out(stdout);
    out << "listening on " << control.address().toString() << ":" << control.port() << "\n";
    if (firasimServer)
        out << "firasim: commands on " << firasimServer->address().toString() << ":" << firasimServer->port()
            << ", vision to " << fira.visionAddress.toString() << ":" << fira.visionPort << "\n";
    if (vssrefBridge)
        out << "vssref: commands to " << ref.commandAddress.toString() << ":" << ref.commandPort
            << ", placements on " << ref.placementAddress.toString() << ":" << vssrefBridge->placementPort() << "\n";
    out.flush();
    const GameSettings& game = scene->game;
    log(QStringLiteral("serving %1: %2 robots, %3 mode%4, dt %5 s, %6%7; referee %8, yellow %9, blue %10; "
                       "camera %11; %12 defends x < 0")
            .arg(scenePath.startsWith(":/") ? QStringLiteral("built-in scene %1").arg(QFileInfo(scenePath).baseName())
                                            : scenePath)
            .arg(scene->robots.size())
            .arg(runModeName(loop.mode))
            .arg(loop.mode == RunMode::Realtime ? QStringLiteral(" x%1").arg(loop.speed) : QString())
            .arg(scene->simulation.dt)
            .arg(parser.isSet(sceneCommands)
                     ? QStringLiteral("%1 scene commands applied").arg(scheduled)
                     : QStringLiteral("%1 scene commands ignored (--scene-commands applies them)").arg(scheduled))
            .arg(server.readOnlyObservers ? QStringLiteral("; observers are read-only") : QString())
            .arg(game.rules.referee ? "on" : "off")
            .arg(game.yellow == TeamControl::Remote ? QStringLiteral("tcp") : teamControlName(game.yellow))
            .arg(game.blue == TeamControl::Remote ? QStringLiteral("tcp") : teamControlName(game.blue))
            .arg(cameraPresetName(scene->camera))
            .arg(teamLabel(game.rules.left_team)));

    if (firasimServer)
        log(QStringLiteral("firasim: %1 vision every %2 s of simulated time on average (%3 Hz; %6 Hz asked for, "
                           "each message on the first step at or after its time)%4; goals in the vision: %5")
                .arg(fira.visionAddress.isMulticast()
                         ? QStringLiteral("multicast (TTL %1, loopback on)").arg(fira.multicastTtl)
                         : QStringLiteral("unicast"))
                .arg(engine.framePeriod())
                .arg(1.0 / engine.framePeriod(), 0, 'g', 6)
                .arg(fira.sync ? QStringLiteral("; sync: each command packet steps one period") : QString())
                .arg(game.rules.referee ? QStringLiteral("the built-in referee's")
                     : externalReferee
                         ? QStringLiteral("0:0, as FIRASim sends them (--referee external: the external referee "
                                          "keeps the score)")
                         : QStringLiteral("0:0, as FIRASim sends them (no built-in referee)"))
                .arg(rate));

    std::signal(SIGINT, onStopSignal);
    std::signal(SIGTERM, onStopSignal);
    QTimer signalPoll;
    QObject::connect(&signalPoll, &QTimer::timeout, [] {
        if (stopSignal.load() != 0) QCoreApplication::quit();
    });
    signalPoll.start(100);
    if (quitSeconds > 0) QTimer::singleShot(static_cast<int>(quitSeconds * 1000), [] { QCoreApplication::quit(); });
    QCoreApplication::exec();
    log("stopping");
    firasimServer.reset();
    vssrefBridge.reset();
    engine.requestStop();
    engine.wait();
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    return 0;
}

}  // namespace vssim
