#include "run_command.h"

#include "progress_line.h"

#include <QCommandLineParser>
#include <QCoreApplication>
#include <QElapsedTimer>
#include <QTextStream>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "io/csv_writer.h"
#include "io/output_file.h"
#include "io/scene_io.h"
#include "realtime/simulation_fault.h"
#include "vssim/game/match.h"
#include "vssim/integrator.h"
#include "vssim/robot_model.h"
#include "vssim/world.h"

namespace vssim {

namespace {

constexpr std::int64_t kMaxSteps = 2'000'000'000;  // refuse runs that could not end in reasonable time

QTextStream& err() {
    static QTextStream stream(stderr);
    return stream;
}

struct RunOptions {
    QString scenePath;
    double duration = 0.0;         // s
    std::optional<double> dt;      // s
    std::optional<double> sample;  // s
    std::optional<Integrator> integrator;
    std::optional<CollisionModel> collisionModel;
    std::optional<bool> referee;  // --referee on|off
    QString outPath;              // empty: stdout
};

// Parses a finite number with a unit for the message; nullopt and *error set otherwise.
std::optional<double> parseSeconds(const QString& option, const QString& text, QString* error) {
    bool ok = false;
    const double value = text.toDouble(&ok);
    if (!ok || !std::isfinite(value)) {
        *error = QStringLiteral("--%1: expected a number of seconds, got \"%2\"").arg(option, text);
        return std::nullopt;
    }
    if (value <= 0.0) {
        *error = QStringLiteral("--%1: must be > 0 s (got %2)").arg(option, text);
        return std::nullopt;
    }
    return value;
}

std::optional<RunOptions> parseRunOptions(const QStringList& arguments, QString* error, bool* helpAsked) {
    QCommandLineParser parser;
    parser.setSingleDashWordOptionMode(QCommandLineParser::ParseAsLongOptions);
    const QCommandLineOption help({"h", "help"}, "Show this help.");
    const QCommandLineOption duration("duration", "Simulated time to run, s (required).", "S");
    const QCommandLineOption dt("dt", "Integration step, s (default: the scene's, 0.001).", "S");
    const QCommandLineOption integrator("integrator", "euler, rk4 or exact (default: the scene's, exact).", "NAME");
    const QCommandLineOption collision("collision-model", "paper or impulse (default: the scene's, paper).", "NAME");
    const QCommandLineOption sample("sample", "Time between CSV samples, s (default: dt).", "S");
    const QCommandLineOption out("out", "Write the CSV to FILE instead of standard output.", "FILE");
    const QCommandLineOption referee("referee", "on|off", "ON");
    parser.addOptions({help, duration, dt, integrator, collision, sample, out, referee});
    parser.addPositionalArgument("scene", "Scene file (JSON) or built-in scene name.");
    if (!parser.parse(arguments)) {  // "run" plays the program name
        *error = parser.errorText();
        return std::nullopt;
    }
    if (parser.isSet(help)) {
        *helpAsked = true;
        return std::nullopt;
    }
    RunOptions o;
    const QStringList positional = parser.positionalArguments();
    if (positional.size() != 1) {
        *error = positional.isEmpty() ? QStringLiteral("missing the scene file (see vssim run --help)")
                                      : QStringLiteral("expected one scene file, got %1: %2")
                                            .arg(positional.size())
                                            .arg(positional.join(' '));
        return std::nullopt;
    }
    o.scenePath = resolveScenePath(positional[0]);
    if (o.scenePath.isEmpty()) {
        *error = sceneNotFoundMessage(positional[0]);
        return std::nullopt;
    }
    if (!parser.isSet(duration)) {
        *error = QStringLiteral("--duration is required (simulated seconds to run)");
        return std::nullopt;
    }
    const auto d = parseSeconds("duration", parser.value(duration), error);
    if (!d) return std::nullopt;
    o.duration = *d;
    if (parser.isSet(dt)) {
        o.dt = parseSeconds("dt", parser.value(dt), error);
        if (!o.dt) return std::nullopt;
        if (*o.dt > kMaxSceneTimeStep) {
            *error = QStringLiteral("--dt: must be <= %1 s (got %2)").arg(kMaxSceneTimeStep).arg(parser.value(dt));
            return std::nullopt;
        }
        if (*o.dt < kMinSceneTimeStep) {
            *error = QStringLiteral("--dt: must be >= %1 s (got %2)").arg(kMinSceneTimeStep).arg(parser.value(dt));
            return std::nullopt;
        }
    }
    if (parser.isSet(sample)) {
        o.sample = parseSeconds("sample", parser.value(sample), error);
        if (!o.sample) return std::nullopt;
    }
    if (parser.isSet(integrator)) {
        o.integrator = integratorFromName(parser.value(integrator));
        if (!o.integrator) {
            *error =
                QStringLiteral("--integrator: expected euler, rk4 or exact, got \"%1\"").arg(parser.value(integrator));
            return std::nullopt;
        }
    }
    if (parser.isSet(collision)) {
        o.collisionModel = collisionModelFromName(parser.value(collision));
        if (!o.collisionModel) {
            *error =
                QStringLiteral("--collision-model: expected paper or impulse, got \"%1\"").arg(parser.value(collision));
            return std::nullopt;
        }
    }
    if (parser.isSet(referee)) {
        const QString text = parser.value(referee);
        if (text != "on" && text != "off") {
            *error = QStringLiteral("--referee: expected on or off, got \"%1\"").arg(text);
            return std::nullopt;
        }
        o.referee = text == "on";
    }
    o.outPath = parser.value(out);
    if (parser.isSet(out) && o.outPath.isEmpty()) {
        *error = QStringLiteral("--out: expected a file name");
        return std::nullopt;
    }
    return o;
}

// Applies the command-line overrides to the scene and checks the combination.
bool applyOptions(const RunOptions& o, Scene& scene, QString* error) {
    if (o.dt) scene.simulation.dt = *o.dt;
    if (o.integrator) scene.simulation.integrator = *o.integrator;
    if (o.collisionModel) scene.simulation.collision_model = *o.collisionModel;
    if (o.referee) {
        scene.game.rules.referee = *o.referee;
        if (*o.referee && !fieldHasGoals(scene.field)) {
            *error = QStringLiteral("--referee on: %1: %2").arg(o.scenePath, refereeFieldProblem());
            return false;
        }
    }
    const double dt = scene.simulation.dt;
    if (o.sample && *o.sample < dt * (1.0 - 1e-9)) {
        *error = QStringLiteral("--sample: must be >= dt = %1 s (got %2 s)").arg(dt).arg(*o.sample);
        return false;
    }
    if (static_cast<double>(Simulation::stepIndexAtOrAfter(o.duration, dt)) > kMaxSteps) {
        *error =
            QStringLiteral("--duration %1 s at dt = %2 s is more than %3 steps; use a longer --dt or a shorter run")
                .arg(o.duration)
                .arg(dt)
                .arg(kMaxSteps);
        return false;
    }
    return true;
}

// Steps beyond the integrator's stability limit for some robot (stiff
// motors) or for the ball (strong friction on a light ball): the run is
// allowed (the user may want to see it), but said.
QStringList stabilityWarnings(const Scene& scene) {
    QStringList warnings;
    const SimulationSettings& s = scene.simulation;
    for (const RobotSpec& robot : scene.robots) {
        const double rate = makeRobotModel(robot.params).fastestRate;  // 1/s
        const double limit = stableStepLimit(s.integrator, rate);      // s
        if (s.dt > limit)
            warnings << QStringLiteral(
                            "warning: robot \"%1\" has a motor time constant of %2 ms: %3 is unstable "
                            "for dt > %4 ms (dt = %5 ms); use --integrator exact or a --dt below %4 ms")
                            .arg(QString::fromStdString(robot.name))
                            .arg(1e3 / rate, 0, 'g', 3)
                            .arg(integratorName(s.integrator))
                            .arg(limit * 1e3, 0, 'g', 3)
                            .arg(s.dt * 1e3, 0, 'g', 3);
    }
    // The ball's velocity decays as exp(lambda t) with lambda = -friction/mass
    // (model.md eq. 9): one real eigenvalue, with the same limits as a robot's.
    const double ballRate = scene.ball_params.friction / scene.ball_params.mass;  // 1/s
    const double ballLimit = stableStepLimit(s.integrator, ballRate);             // s
    if (s.dt > ballLimit)
        warnings << QStringLiteral(
                        "warning: the ball has a friction time constant (mass/friction) of %1 ms: %2 is unstable "
                        "for dt > %3 ms (dt = %4 ms); use --integrator exact or a --dt below %3 ms")
                        .arg(1e3 / ballRate, 0, 'g', 3)
                        .arg(integratorName(s.integrator))
                        .arg(ballLimit * 1e3, 0, 'g', 3)
                        .arg(s.dt * 1e3, 0, 'g', 3);
    return warnings;
}

// One line on the game at the end of a run.
QString gameSummary(const Match& match) {
    const GameState& g = match.game();
    return QStringLiteral("game: yellow %1 : %2 blue, %3 in half %4 at %5 s of game time, %6 call%7")
        .arg(g.goals[0])
        .arg(g.goals[1])
        .arg(gamePhaseName(g.phase))
        .arg(g.half)
        .arg(g.clock, 0, 'f', 2)
        .arg(g.calls.size())
        .arg(g.calls.size() == 1 ? "" : "s");
}

}  // namespace

QString runHelpText() {
    return QStringLiteral(
               "Usage: vssim run SCENE --duration S [options]\n"
               "\n"
               "Runs SCENE (a JSON scene file, see docs/scenes.md, or a built-in scene name) headless\n"
               "for S seconds of simulated time and writes CSV, one row per body per sample:\n"
               "  t,body,x,y,theta,v,omega,e_right,e_left,omega_right,omega_left,i_right,i_left\n"
               "  (s, name, m, m, rad, m/s, rad/s, V, V, rad/s, rad/s, A, A; for the ball theta is its\n"
               "  heading, v its speed and the robot-only columns are empty; 17 significant digits)\n"
               "\n"
               "Options:\n"
               "  --duration S            simulated time to run, s (required)\n"
               "  --dt S                  integration step, s, 1e-6 <= S <= 0.1 (default: the scene's, 0.001)\n"
               "  --integrator NAME       euler | rk4 | exact (default: the scene's, exact); exact solves the\n"
               "                          motor dynamics in closed form and, between voltage changes and\n"
               "                          away from contacts, steps straight to the next sample; euler\n"
               "                          and rk4 are the paper's fixed-step methods\n"
               "  --collision-model NAME  paper | impulse (default: the scene's, paper)\n"
               "  --sample S              time between samples, s, >= dt (default: dt)\n"
               "  --referee on|off        the scene's automatic referee on or off (docs/game.md; on needs a\n"
               "                          field with goals); built-in teams play as the scene says\n"
               "  --out FILE              write the CSV to FILE; a regular file is replaced only when the\n"
               "                          run succeeds, and a run killed before leaves no temporary file\n"
               "                          beside it; a device, a FIFO or a file with other hard links is\n"
               "                          written in place; a symbolic link's target gets the CSV\n"
               "  -h, --help              show this help\n"
               "\n"
               "Built-in scenes: %1\n"
               "A summary (steps, contacts, run time, real-time factor) goes to standard error, and a\n"
               "warning when dt is beyond Euler's or RK4's stability limit for a robot or the ball.\n"
               "Samples fall on the first step boundary at or after each multiple of --sample, and the\n"
               "run ends on the first step boundary at or after --duration; its final state is always\n"
               "written.\n"
               "A scene with a game (docs/game.md) is played: its referee and built-in teams act every\n"
               "tick (game.tick, 10 ms), and the score goes to standard error at the end.\n"
               "The run stops when the state stops being finite (NaN or infinity), naming the time and\n"
               "the body; the rows before it are written.\n"
               "Exit status: 0 success, 2 bad option or scene or an output file that cannot be created,\n"
               "1 a write failed (the message names the output and the system's reason) or the state\n"
               "stopped being finite.\n")
        .arg(builtinSceneNames().join(", "));
}

int runCommand(const QStringList& arguments) {
    QString error;
    bool helpAsked = false;
    const std::optional<RunOptions> options = parseRunOptions(arguments, &error, &helpAsked);
    if (helpAsked) {
        QTextStream(stdout) << runHelpText();
        return 0;
    }
    if (!options) {
        err() << "vssim run: " << error << "\n";
        return 2;
    }
    std::optional<Scene> scene = loadSceneFile(options->scenePath, &error);
    if (!scene) {
        err() << "vssim run: " << error << "\n";
        return 2;
    }
    if (!applyOptions(*options, *scene, &error)) {
        err() << "vssim run: " << error << "\n";
        return 2;
    }
    for (const QString& warning : stabilityWarnings(*scene)) err() << "vssim run: " << warning << "\n";

    const std::unique_ptr<OutputFile> out = OutputFile::openOrStandardOutput(options->outPath, &error);
    if (!out) {
        err() << "vssim run: cannot write " << error << "\n";
        return 2;
    }

    // A Match: the scene's game if it has one (referee, built-in teams);
    // otherwise exactly the Simulation.
    Match match(*scene);
    const Simulation& simulation = match.simulation();
    const double dt = simulation.dt();
    const std::int64_t lastStep = Simulation::stepIndexAtOrAfter(options->duration, dt);
    const double sample = options->sample.value_or(dt);
    CsvWriter csv(*out);
    csv.writeHeader();
    csv.writeSample(simulation);
    std::optional<SimulationFault> fault;
    double lastFiniteTime = 0.0;  // s: the last time the state was checked and found finite
    std::int64_t sampleIndex = 1;
    std::int64_t nextSampleStep = Simulation::stepIndexAtOrAfter(sample, dt);
    std::int64_t contacts = 0, stepCalls = 0, longSteps = 0;
    std::int64_t lastWritten = 0;  // step of the last sample written
    ProgressLine progress(err());
    // Stops at the first failed write (nothing more would get through) and
    // at the first non-finite state (nothing after it means anything).
    while (simulation.state().step < lastStep && csv.ok()) {
        const AdvanceReport r = match.advanceTo(std::min(lastStep, nextSampleStep));
        contacts += r.contacts;
        stepCalls += r.stepCalls;
        longSteps += r.longSteps;
        fault = findSimulationFault(simulation);
        if (fault) break;
        lastFiniteTime = simulation.state().time;
        if (simulation.state().step >= nextSampleStep) {
            csv.writeSample(simulation);
            lastWritten = simulation.state().step;
            ++sampleIndex;
            nextSampleStep = std::max(simulation.state().step + 1,
                                      Simulation::stepIndexAtOrAfter(static_cast<double>(sampleIndex) * sample, dt));
        }
        if (progress.due())
            progress.show(QStringLiteral("vssim run: %1%").arg(100.0 * simulation.state().step / lastStep, 0, 'f', 1));
    }
    if (!fault && lastWritten != simulation.state().step) csv.writeSample(simulation);  // the final state, always
    progress.clear();
    if (fault) {
        // The rows up to the last finite sample are written (a file named by
        // --out, though, only where it is written in place: see OutputFile).
        csv.finish();
        if (out->inPlace()) out->commit();
        const QString since = fault->time - lastFiniteTime > 1.5 * dt
                                  ? QStringLiteral(" (it was finite at t = %1 s)").arg(lastFiniteTime, 0, 'g', 10)
                                  : QString();
        err() << "vssim run: stopped: " << fault->message() << since
              << "; a step beyond the integrator's stability limit or extreme parameters can cause this\n";
        return 1;
    }
    if (!csv.finish() || !out->commit()) {
        err() << "vssim run: failed to write " << out->name() << ": " << out->error() << "\n";
        return 1;
    }
    const double seconds = progress.elapsedSeconds();
    const QString steps =
        longSteps > 0 ? QStringLiteral("%1 steps of %2 s and %3 long steps").arg(stepCalls).arg(dt).arg(longSteps)
                      : QStringLiteral("%1 steps of %2 s").arg(stepCalls).arg(dt);
    err() << QStringLiteral(
                 "vssim run: %1 s simulated in %2 (%3), %4 contact%5, %6 s of run time including the CSV "
                 "(%7x real time)\n")
                 .arg(simulation.state().time)
                 .arg(steps)
                 .arg(integratorName(simulation.model().settings.integrator))
                 .arg(contacts)
                 .arg(contacts == 1 ? "" : "s")
                 .arg(seconds, 0, 'g', 3)
                 .arg(simulation.state().time / std::max(seconds, 1e-9), 0, 'f', 0);
    if (scene->game.rules.referee) err() << "vssim run: " << gameSummary(match) << "\n";
    return 0;
}

int demoCommand() {
    QString error;
    const std::optional<Scene> scene = loadSceneFile(resolveScenePath("kickoff_3v3"), &error);
    if (!scene) {
        err() << "vssim: " << error << "\n";
        return 1;
    }
    // The kick-off as a match: 4 s of STOP, then the built-in teams play.
    Match match(*scene);
    const Simulation& simulation = match.simulation();
    const double duration = 10.0;  // s
    QElapsedTimer clock;
    clock.start();
    const std::int64_t contacts = match.advanceTo(Simulation::stepIndexAtOrAfter(duration, simulation.dt())).contacts;
    const double seconds = std::max(1e-6, clock.nsecsElapsed() * 1e-9);
    QTextStream out(stdout);
    out << "vssim: built-in scene kickoff_3v3, " << duration << " s simulated in " << seconds * 1e3 << " ms ("
        << QString::number(duration / seconds, 'f', 0) << "x real time), " << contacts << " contacts\n\n";
    out << QStringLiteral("%1 %2 %3 %4 %5 %6\n")
               .arg("body", -8)
               .arg("x [m]", 9)
               .arg("y [m]", 9)
               .arg("theta [rad]", 12)
               .arg("v [m/s]", 9)
               .arg("omega [rad/s]", 14);
    const WorldState& s = simulation.state();
    for (std::size_t i = 0; i < s.robots.size(); ++i) {
        const RobotState& r = s.robots[i];
        out << QStringLiteral("%1 %2 %3 %4 %5 %6\n")
                   .arg(QString::fromStdString(scene->robots[i].name), -8)
                   .arg(r.x, 9, 'f', 4)
                   .arg(r.y, 9, 'f', 4)
                   .arg(r.theta, 12, 'f', 4)
                   .arg(r.v, 9, 'f', 4)
                   .arg(r.omega, 14, 'f', 4);
    }
    out << QStringLiteral("%1 %2 %3 %4 %5\n")
               .arg("ball", -8)
               .arg(s.ball.x, 9, 'f', 4)
               .arg(s.ball.y, 9, 'f', 4)
               .arg(std::atan2(s.ball.vy, s.ball.vx), 12, 'f', 4)
               .arg(std::hypot(s.ball.vx, s.ball.vy), 9, 'f', 4);
    if (scene->game.rules.referee) out << "\n" << gameSummary(match) << "\n";
    out << "\nNext: " << QCoreApplication::arguments().value(0, "vssim")
        << " run kickoff_3v3 --duration 10 --out run.csv   (see --help)\n";
    return 0;
}

}  // namespace vssim
