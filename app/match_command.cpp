#include "match_command.h"

#include "progress_line.h"

#include <QCommandLineParser>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTextStream>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>

#include "io/output_file.h"
#include "io/scene_io.h"
#include "match_setup.h"
#include "realtime/simulation_fault.h"
#include "vssim/state_hash.h"

namespace vssim {

namespace {

constexpr std::int64_t kMaxSteps = 2'000'000'000;     // of game time at dt: refuse matches that could not end
constexpr int kMaxHalves = 1000;                      // more is a typing mistake
constexpr std::uint64_t kMaxSeed = (1ull << 53) - 1;  // exact as a JSON number
constexpr const char* kDefaultSceneName = "the official 3 vs 3 field, three robots per team (built in)";

QTextStream& err() {
    static QTextStream stream(stderr);
    return stream;
}

struct MatchOptions {
    QString scene;  // empty: the default match scene
    std::optional<int> halves;
    std::optional<double> halfDuration;  // s
    std::uint64_t seed = 0;
    std::optional<TeamControl> yellow, blue;  // unset: the scene's, if builtin or idle; else builtin
    std::optional<Team> leftTeam;             // unset: the scene's
    bool json = false;
    QString outPath;  // empty: stdout
};

std::optional<TeamControl> parseTeamControl(const QString& option, const QString& text, QString* error) {
    if (text == "builtin") return TeamControl::Builtin;
    if (text == "idle") return TeamControl::Idle;
    if (text == "remote")
        *error =
            QStringLiteral("--%1: remote teams play over TCP (vssim serve); vssim match plays builtin or idle teams")
                .arg(option);
    else
        *error = QStringLiteral("--%1: expected builtin or idle, got \"%2\"").arg(option, text);
    return std::nullopt;
}

std::optional<MatchOptions> parseMatchOptions(const QStringList& arguments, QString* error, bool* helpAsked) {
    QCommandLineParser parser;
    parser.setSingleDashWordOptionMode(QCommandLineParser::ParseAsLongOptions);
    const QCommandLineOption help({"h", "help"}, "Show this help.");
    const QCommandLineOption halves("halves", "Halves to play.", "N");
    const QCommandLineOption halfDuration("half-duration", "Game time per half, s.", "S");
    const QCommandLineOption seed("seed", "Jitter of the robots' kick-off spots.", "S");
    const QCommandLineOption yellow("yellow", "builtin or idle.", "CONTROL");
    const QCommandLineOption blue("blue", "builtin or idle.", "CONTROL");
    const QCommandLineOption leftTeam("left-team", "yellow or blue.", "TEAM");
    const QCommandLineOption json("json", "JSON output.");
    const QCommandLineOption out("out", "Write to FILE instead of standard output.", "FILE");
    parser.addOptions({help, halves, halfDuration, seed, yellow, blue, leftTeam, json, out});
    parser.addPositionalArgument("scene", "Scene file (JSON) or built-in scene name.");
    if (!parser.parse(arguments)) {
        *error = parser.errorText();
        return std::nullopt;
    }
    if (parser.isSet(help)) {
        *helpAsked = true;
        return std::nullopt;
    }
    MatchOptions o;
    const QStringList positional = parser.positionalArguments();
    if (positional.size() > 1) {
        *error =
            QStringLiteral("expected at most one scene, got %1: %2").arg(positional.size()).arg(positional.join(' '));
        return std::nullopt;
    }
    if (!positional.isEmpty()) o.scene = positional[0];
    if (parser.isSet(halves)) {
        bool ok = false;
        const int n = parser.value(halves).toInt(&ok);
        if (!ok || n < 1 || n > kMaxHalves) {
            *error = QStringLiteral("--halves: expected a whole number from 1 to %1, got \"%2\"")
                         .arg(kMaxHalves)
                         .arg(parser.value(halves));
            return std::nullopt;
        }
        o.halves = n;
    }
    if (parser.isSet(halfDuration)) {
        bool ok = false;
        const double s = parser.value(halfDuration).toDouble(&ok);
        if (!ok || !std::isfinite(s)) {
            *error = QStringLiteral("--half-duration: expected a number of seconds, got \"%1\"")
                         .arg(parser.value(halfDuration));
            return std::nullopt;
        }
        if (s <= 0.0) {
            *error = QStringLiteral("--half-duration: must be > 0 s (got %1)").arg(parser.value(halfDuration));
            return std::nullopt;
        }
        o.halfDuration = s;
    }
    if (parser.isSet(seed)) {
        const QString text = parser.value(seed);
        bool ok = false;
        const qulonglong s = text.toULongLong(&ok);
        if (!ok || text.startsWith('-') || text.startsWith('+') || s > kMaxSeed) {
            *error = QStringLiteral("--seed: expected a whole number from 0 to %1, got \"%2\"").arg(kMaxSeed).arg(text);
            return std::nullopt;
        }
        o.seed = s;
    }
    if (parser.isSet(yellow)) {
        const auto c = parseTeamControl("yellow", parser.value(yellow), error);
        if (!c) return std::nullopt;
        o.yellow = *c;
    }
    if (parser.isSet(blue)) {
        const auto c = parseTeamControl("blue", parser.value(blue), error);
        if (!c) return std::nullopt;
        o.blue = *c;
    }
    if (parser.isSet(leftTeam)) {
        const QString text = parser.value(leftTeam);
        o.leftTeam = teamFromName(text);
        if (!o.leftTeam) {
            *error = QStringLiteral("--left-team: expected yellow or blue, got \"%1\"").arg(text);
            return std::nullopt;
        }
    }
    o.json = parser.isSet(json);
    o.outPath = parser.value(out);
    if (parser.isSet(out) && o.outPath.isEmpty()) {
        *error = QStringLiteral("--out: expected a file name");
        return std::nullopt;
    }
    return o;
}

// The scene to play, with the options applied: the referee on, the teams as
// asked, the scene's own voltage commands dropped (the teams drive).
std::optional<Scene> matchScene(const MatchOptions& o, QString* error) {
    Scene scene;
    if (o.scene.isEmpty()) {
        scene = defaultMatchScene(o.yellow.value_or(TeamControl::Builtin), o.blue.value_or(TeamControl::Builtin));
    } else {
        const QString path = resolveScenePath(o.scene);
        if (path.isEmpty()) {
            *error = sceneNotFoundMessage(o.scene);
            return std::nullopt;
        }
        std::optional<Scene> loaded = loadSceneFile(path, error);
        if (!loaded) return std::nullopt;
        scene = std::move(*loaded);
        if (!hasGoals(scene.field)) {
            *error = QStringLiteral(
                         "%1: the field has no goals (a box); a match needs an official field "
                         "(\"field\": {\"type\": \"vsss_3v3\"} or \"vsss_5v5\", docs/scenes.md)")
                         .arg(o.scene);
            return std::nullopt;
        }
        scene.game.rules.referee = true;
        // Nobody would drive a remote team here: the built-in team does.
        auto control = [](const std::optional<TeamControl>& asked, TeamControl scenes) {
            if (asked) return *asked;
            return scenes == TeamControl::Remote ? TeamControl::Builtin : scenes;
        };
        scene.game.yellow = control(o.yellow, scene.game.yellow);
        scene.game.blue = control(o.blue, scene.game.blue);
        scene.commands.clear();
    }
    GameRules& rules = scene.game.rules;
    if (o.leftTeam) rules.left_team = *o.leftTeam;
    if (o.halves) rules.halves = *o.halves;
    if (o.halfDuration) rules.half_duration = *o.halfDuration;
    const double dt = scene.simulation.dt;
    if (static_cast<double>(rules.halves) * rules.half_duration / dt > static_cast<double>(kMaxSteps)) {
        *error = QStringLiteral("%1 halves of %2 s at dt = %3 s is more than %4 steps; play fewer or shorter halves")
                     .arg(rules.halves)
                     .arg(rules.half_duration)
                     .arg(dt)
                     .arg(kMaxSteps);
        return std::nullopt;
    }
    return scene;
}

// Seconds to the microsecond, for printing (the clock adds up ticks of 0.01 s).
double roundedSeconds(double t) { return std::round(t * 1e6) / 1e6; }

bool hasTeam(Call call) { return call == Call::KickOff || call == Call::PenaltyKick || call == Call::GoalKick; }

QString hashText(std::uint64_t hash) { return QStringLiteral("%1").arg(hash, 16, 16, QChar('0')); }

QString sceneLabel(const MatchOptions& o) { return o.scene.isEmpty() ? QString(kDefaultSceneName) : o.scene; }

// The match's fingerprint: FNV-1a over the hashes of the world state after
// every game tick (hashState), so two matches that part anywhere differ.
class MatchHash {
public:
    void add(const WorldState& state) {
        const std::uint64_t h = hashState(state);
        for (int k = 0; k < 8; ++k) hash_ = (hash_ ^ ((h >> (8 * k)) & 0xffu)) * 1099511628211ull;
    }
    std::uint64_t value() const { return hash_; }

private:
    std::uint64_t hash_ = 1469598103934665603ull;
};

struct Hashes {
    std::uint64_t finalState = 0;  // hashState of the state at full time
    std::uint64_t match = 0;       // MatchHash over every tick
};

QByteArray textReport(const MatchOptions& o, const Match& match, const Hashes& hashes) {
    const GameState& g = match.game();
    const GameRules& rules = match.scene().game.rules;
    QString text;
    QTextStream s(&text);
    s << "scene: " << sceneLabel(o) << "\n";
    const bool yellowLeft = rules.left_team == Team::Yellow;
    s << QStringLiteral("match: %1 %2 of %3 s, seed %4, yellow %5 (defends x %6 0) vs blue %7\n")
             .arg(rules.halves)
             .arg(rules.halves == 1 ? "half" : "halves")
             .arg(rules.half_duration)
             .arg(o.seed)
             .arg(teamControlName(match.control(Team::Yellow)))
             .arg(yellowLeft ? "<" : ">")
             .arg(teamControlName(match.control(Team::Blue)));
    s << QStringLiteral("final score: yellow %1 - %2 blue\n").arg(g.goals[0]).arg(g.goals[1]);
    s << "\n" << g.calls.size() << " call" << (g.calls.size() == 1 ? "" : "s") << ":\n";
    s << QStringLiteral("%1  %2  %3  %4  %5  %6  %7\n")
             .arg("time [s]", 9)
             .arg("half", 4)
             .arg("clock [s]", 9)
             .arg("call", -12)
             .arg("team", -6)
             .arg("quadrant", 8)
             .arg("reason");
    for (const RefereeCall& c : g.calls) {
        s << QStringLiteral("%1  %2  %3  %4  %5  %6  %7\n")
                 .arg(c.time, 9, 'f', 3)
                 .arg(c.half, 4)
                 .arg(roundedSeconds(c.clock), 9, 'f', 3)
                 .arg(callName(c.call), -12)
                 .arg(hasTeam(c.call) ? teamLabel(c.team) : "-", -6)
                 .arg(c.call == Call::FreeBall ? QString::number(c.quadrant) : QStringLiteral("-"), 8)
                 .arg(QString::fromStdString(c.reason));
    }
    const WorldState& w = match.simulation().state();
    s << QStringLiteral("\nfull time at %1 s of simulated time (%2 steps of %3 s)\n")
             .arg(w.time, 0, 'f', 3)
             .arg(w.step)
             .arg(match.simulation().dt());
    s << QStringLiteral("match hash %1, final state hash %2\n")
             .arg(hashText(hashes.match), hashText(hashes.finalState));
    s.flush();
    return text.toUtf8();
}

QByteArray jsonReport(const MatchOptions& o, const Match& match, const Hashes& hashes) {
    const GameState& g = match.game();
    const GameRules& rules = match.scene().game.rules;
    QJsonArray calls;
    for (const RefereeCall& c : g.calls) {
        calls.append(QJsonObject{
            {"time", roundedSeconds(c.time)},
            {"half", c.half},
            {"clock", roundedSeconds(c.clock)},
            {"call", callName(c.call)},
            {"team", hasTeam(c.call) ? QJsonValue(teamLabel(c.team)) : QJsonValue()},
            {"quadrant", c.call == Call::FreeBall ? QJsonValue(c.quadrant) : QJsonValue()},
            {"reason", QString::fromStdString(c.reason)},
        });
    }
    const WorldState& w = match.simulation().state();
    const QJsonObject root{
        {"scene", o.scene.isEmpty() ? QJsonValue() : QJsonValue(o.scene)},
        {"seed", static_cast<qint64>(o.seed)},
        {"halves", rules.halves},
        {"half_duration", rules.half_duration},
        {"yellow", teamControlName(match.control(Team::Yellow))},
        {"blue", teamControlName(match.control(Team::Blue))},
        {"left_team", teamName(rules.left_team)},
        {"goals", QJsonObject{{"yellow", g.goals[0]}, {"blue", g.goals[1]}}},
        {"calls", calls},
        {"simulated_time", roundedSeconds(w.time)},
        {"steps", static_cast<qint64>(w.step)},
        {"dt", match.simulation().dt()},
        {"match_hash", hashText(hashes.match)},
        {"state_hash", hashText(hashes.finalState)},
    };
    return QJsonDocument(root).toJson(QJsonDocument::Indented);
}

// The progress line's text: where the match is.
QString progressText(const Match& match) {
    const GameState& g = match.game();
    return QStringLiteral("vssim match: half %1, %2 of %3 s, yellow %4 - %5 blue")
        .arg(g.half)
        .arg(g.clock, 0, 'f', 0)
        .arg(match.scene().game.rules.half_duration)
        .arg(g.goals[0])
        .arg(g.goals[1]);
}

}  // namespace

QString matchHelpText() {
    return QStringLiteral(
               "Usage: vssim match [SCENE] [options]\n"
               "\n"
               "Plays a whole match headless, as fast as the computer goes: the automatic referee on\n"
               "(goals, halves, stuck ball, two defenders, two attackers, the goalkeeper), both teams\n"
               "driven by vssim's built-in team (or standing idle), and prints the final score and\n"
               "every call of the referee (docs/game.md). Yellow defends the goal at x < 0 and blue\n"
               "the one at x > 0 for the whole match (--left-team blue swaps them); yellow kicks off\n"
               "the odd halves.\n"
               "\n"
               "SCENE is a scene file (JSON, docs/scenes.md) or a built-in scene name, on a field\n"
               "with goals; its robots start on the referee's kick-off spots and its voltage commands\n"
               "are ignored (the teams drive). Without SCENE: the official 3 vs 3 field (1.50 x 1.30 m)\n"
               "with three default robots per team, the exact integrator at 1 ms (the default).\n"
               "\n"
               "Options:\n"
               "  --halves N            halves to play, 1 to %1 (default: the scene's, 2)\n"
               "  --half-duration S     game time per half, s, > 0 (default: the scene's, 300); the\n"
               "                        clock stops while the game is stopped after a call (4 s each)\n"
               "  --seed S              a whole number from 0 to %2 (default 0): every time the referee\n"
               "                        places the robots (before the first kick-off and after every\n"
               "                        call), it moves each one by up to %3 mm along x and y and turns\n"
               "                        it by up to %4 rad, drawn from S (splitmix64; a jittered\n"
               "                        placement that breaks the rules is not used); 0 moves nothing.\n"
               "                        The same seed gives the same match, bit for bit; another seed,\n"
               "                        another match\n"
               "  --yellow CONTROL      builtin | idle: who drives the yellow robots (default: the\n"
               "                        scene's if it is builtin or idle, otherwise builtin)\n"
               "  --blue CONTROL        builtin | idle (default: as for --yellow)\n"
               "  --left-team TEAM      yellow | blue: the team that defends the goal at x < 0 for the\n"
               "                        whole match (default: the scene's game.left_team, yellow)\n"
               "  --json                write the result as JSON (one object: scene, seed, halves,\n"
               "                        half_duration, yellow, blue, left_team, goals, calls, simulated_time,\n"
               "                        steps, dt, match_hash, state_hash) instead of text\n"
               "  --out FILE            write the result to FILE instead of standard output (replaced\n"
               "                        only when the match completes; a match killed before leaves no\n"
               "                        temporary file beside it)\n"
               "  -h, --help            show this help\n"
               "\n"
               "Each call is listed with its simulated time, half, game clock, the call (kickoff,\n"
               "free_ball, penalty_kick, goal_kick), the team it favours, the quadrant of a free ball\n"
               "and the reason (\"goal by yellow\", \"ball stuck\", \"two defenders\", ...). The match\n"
               "hash (FNV-1a over the state after every tick of 0.01 s) tells two matches apart; the\n"
               "state hash is the final state's alone.\n"
               "Standard output depends only on the scene and the options; the run time and the\n"
               "real-time factor go to standard error, with a progress line when it is a terminal.\n"
               "\n"
               "Built-in scenes: %5\n"
               "Exit status: 0 success, 2 bad option or scene, 1 a write failed or the state stopped\n"
               "being finite.\n")
        .arg(kMaxHalves)
        .arg(kMaxSeed)
        .arg(Match::kPlacementJitter * 1e3)
        .arg(Match::kHeadingJitter)
        .arg(builtinSceneNames().join(", "));
}

int matchCommand(const QStringList& arguments) {
    QString error;
    bool helpAsked = false;
    const std::optional<MatchOptions> options = parseMatchOptions(arguments, &error, &helpAsked);
    if (helpAsked) {
        QTextStream(stdout) << matchHelpText();
        return 0;
    }
    if (!options) {
        err() << "vssim match: " << error << "\n";
        return 2;
    }
    const std::optional<Scene> scene = matchScene(*options, &error);
    if (!scene) {
        err() << "vssim match: " << error << "\n";
        return 2;
    }
    const std::unique_ptr<OutputFile> out = OutputFile::openOrStandardOutput(options->outPath, &error);
    if (!out) {
        err() << "vssim match: cannot write " << error << "\n";
        return 2;
    }

    Match match(*scene, options->seed);
    ProgressLine progress(err());
    MatchHash matchHash;
    const bool finished = playToFullTime(match, matchTimeLimit(scene->game.rules), [&] {
        matchHash.add(match.simulation().state());
        if (progress.due()) progress.show(progressText(match));
    });
    progress.clear();
    if (!finished) {
        if (const auto fault = findSimulationFault(match.simulation()))
            err() << "vssim match: stopped: " << fault->message() << "\n";
        else
            err() << "vssim match: stopped: the match had not finished after " << match.simulation().state().time
                  << " s of simulated time\n";
        return 1;
    }
    const Hashes hashes{hashState(match.simulation().state()), matchHash.value()};
    const QByteArray report = options->json ? jsonReport(*options, match, hashes) : textReport(*options, match, hashes);
    if (!out->write(report) || !out->commit()) {
        err() << "vssim match: failed to write " << out->name() << ": " << out->error() << "\n";
        return 1;
    }
    const double seconds = progress.elapsedSeconds();
    const double simulated = match.simulation().state().time;
    err() << QStringLiteral("vssim match: %1 s simulated in %2 s (%3x real time)\n")
                 .arg(simulated, 0, 'f', 2)
                 .arg(seconds, 0, 'g', 3)
                 .arg(simulated / std::max(seconds, 1e-9), 0, 'f', 0);
    return 0;
}

}  // namespace vssim
