#include "stress_command.h"

#include <unistd.h>
#include <QCommandLineParser>
#include <QElapsedTimer>
#include <QTextStream>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "stress_checks.h"
#include "stress_scenes.h"
#include "vssim/state_hash.h"
#include "vssim/world.h"

namespace vssim {

namespace {

using stress::RunFigures;
using stress::SceneKind;

// Option limits. A scene-second (one scene run for one simulated second with
// its 12 to 21 runs, each twice) takes about kCpuPerSceneSecond of one core.
constexpr int kDefaultScenes = 20;
constexpr double kDefaultSeconds = 5.0;  // s
constexpr std::uint32_t kDefaultSeed = 1;
constexpr long long kMaxScenes = 100000;
constexpr long long kMaxOnly = 1000000000;
constexpr double kMaxSeconds = 120.0;          // s of simulated time per run
constexpr double kMaxSceneSeconds = 100000.0;  // scenes x seconds
constexpr double kCpuPerSceneSecond = 0.1;     // s of one core (measured: seed 1, 20 scenes x 5 s in 10 s)
constexpr int kMaxJobs = 256;
constexpr double kAdvanceInterval = 0.030;  // s: the camera period, the boundaries of the advanceTo runs

QTextStream& out() {
    static QTextStream stream(stdout);
    return stream;
}

QTextStream& err() {
    static QTextStream stream(stderr);
    return stream;
}

struct StressOptions {
    int scenes = kDefaultScenes;
    double seconds = kDefaultSeconds;  // s
    std::uint32_t seed = kDefaultSeed;
    int only = 0;  // a scene number, 0: all scenes
    int jobs = 1;  // worker threads
};

// How a run is driven and checked, besides its scene.
enum class Stepping { Euler, Rk4, Exact, ExactAdvance };
constexpr Stepping kSteppings[] = {Stepping::Euler, Stepping::Rk4, Stepping::Exact, Stepping::ExactAdvance};
enum class ModelChoice { Paper, ImpulseElastic, ImpulseRandom };
constexpr ModelChoice kModels[] = {ModelChoice::Paper, ModelChoice::ImpulseElastic, ModelChoice::ImpulseRandom};

const char* steppingName(Stepping s) {
    switch (s) {
        case Stepping::Euler: return "euler";
        case Stepping::Rk4: return "rk4";
        case Stepping::Exact: return "exact";
        case Stepping::ExactAdvance: return "exact/30ms";
    }
    return "?";
}

const char* modelGroupName(ModelChoice m) {
    switch (m) {
        case ModelChoice::Paper: return "paper";
        case ModelChoice::ImpulseElastic: return "impulse e=1";
        case ModelChoice::ImpulseRandom: return "impulse e<1";
    }
    return "?";
}

struct RunJob {
    int scene = 1;             // scene number
    bool zeroVoltage = false;  // the pile's zero-voltage twin (energy check)
    Stepping stepping = Stepping::Euler;
    ModelChoice model = ModelChoice::Paper;
};

struct RunResult {
    SceneKind kind = SceneKind::Pile;
    double dt = 0.0;           // s
    double restitution = 1.0;  // of the impulse model
    RunFigures figures;
};

// ---------------------------------------------------------------- options

std::optional<long long> parseWhole(const QString& option, const QString& text, long long lo, long long hi,
                                    const QString& what, QString* error) {
    bool ok = false;
    const long long value = text.toLongLong(&ok);
    if (!ok) {
        *error = QStringLiteral("--%1: expected a whole number (%2), got \"%3\"").arg(option, what, text);
        return std::nullopt;
    }
    if (value < lo || value > hi) {
        *error = QStringLiteral("--%1: must be from %2 to %3 (got %4)").arg(option).arg(lo).arg(hi).arg(text);
        return std::nullopt;
    }
    return value;
}

std::optional<StressOptions> parseStressOptions(const QStringList& arguments, QString* error, bool* helpAsked) {
    QCommandLineParser parser;
    parser.setSingleDashWordOptionMode(QCommandLineParser::ParseAsLongOptions);
    const QCommandLineOption help({"h", "help"}, "Show this help.");
    const QCommandLineOption scenes("scenes", "Number of random scenes.", "N");
    const QCommandLineOption seconds("seconds", "Simulated seconds per run.", "S");
    const QCommandLineOption seed("seed", "Seed of the scene generator.", "K");
    const QCommandLineOption only("only", "Run only scene K.", "K");
    const QCommandLineOption jobs("jobs", "Worker threads.", "N");
    parser.addOptions({help, scenes, seconds, seed, only, jobs});
    if (!parser.parse(arguments)) {  // "stress" plays the program name
        *error = parser.errorText();
        return std::nullopt;
    }
    if (parser.isSet(help)) {
        *helpAsked = true;
        return std::nullopt;
    }
    if (!parser.positionalArguments().isEmpty()) {
        *error = QStringLiteral("unexpected argument \"%1\" (see vssim stress --help)")
                     .arg(parser.positionalArguments().constFirst());
        return std::nullopt;
    }
    StressOptions o;
    const unsigned cores = std::thread::hardware_concurrency();
    o.jobs = static_cast<int>(std::clamp(cores, 1u, static_cast<unsigned>(kMaxJobs)));
    if (parser.isSet(scenes)) {
        const auto n = parseWhole("scenes", parser.value(scenes), 1, kMaxScenes, "of scenes", error);
        if (!n) return std::nullopt;
        o.scenes = static_cast<int>(*n);
    }
    if (parser.isSet(seconds)) {
        bool ok = false;
        const QString text = parser.value(seconds);
        const double value = text.toDouble(&ok);
        if (!ok || !std::isfinite(value)) {
            *error = QStringLiteral("--seconds: expected a number of seconds, got \"%1\"").arg(text);
            return std::nullopt;
        }
        if (value <= 0.0 || value > kMaxSeconds) {
            *error = QStringLiteral("--seconds: must be > 0 and <= %1 s (got %2)").arg(kMaxSeconds).arg(text);
            return std::nullopt;
        }
        o.seconds = value;
    }
    if (parser.isSet(seed)) {
        const auto k = parseWhole("seed", parser.value(seed), 0, 4294967295LL, "from 0 to 4294967295", error);
        if (!k) return std::nullopt;
        o.seed = static_cast<std::uint32_t>(*k);
    }
    if (parser.isSet(only)) {
        const auto k = parseWhole("only", parser.value(only), 1, kMaxOnly, "a scene number", error);
        if (!k) return std::nullopt;
        o.only = static_cast<int>(*k);
    }
    if (parser.isSet(jobs)) {
        const auto n = parseWhole("jobs", parser.value(jobs), 1, kMaxJobs, "of threads", error);
        if (!n) return std::nullopt;
        o.jobs = static_cast<int>(*n);
    }
    const double sceneCount = o.only > 0 ? 1.0 : static_cast<double>(o.scenes);
    if (sceneCount * o.seconds > kMaxSceneSeconds) {
        *error = QStringLiteral(
                     "--scenes %1 x --seconds %2 is %3 scene-seconds, about %4 hours of one core; the limit is %5 "
                     "(for example --scenes %6 --seconds %7)")
                     .arg(o.scenes)
                     .arg(o.seconds)
                     .arg(sceneCount * o.seconds, 0, 'g', 6)
                     .arg(sceneCount * o.seconds * kCpuPerSceneSecond / 3600.0, 0, 'f', 1)
                     .arg(kMaxSceneSeconds, 0, 'f', 0)
                     .arg(static_cast<long long>(std::max(1.0, std::floor(kMaxSceneSeconds / o.seconds))))
                     .arg(o.seconds);
        return std::nullopt;
    }
    return o;
}

// ---------------------------------------------------------------- runs

std::vector<RunJob> jobsFor(const StressOptions& o) {
    std::vector<RunJob> jobs;
    const int first = o.only > 0 ? o.only : 1;
    const int last = o.only > 0 ? o.only : o.scenes;
    for (int scene = first; scene <= last; ++scene) {
        const bool pile = static_cast<SceneKind>((scene - 1) % stress::kSceneKinds) == SceneKind::Pile;
        for (bool zeroVoltage : {false, true}) {
            if (zeroVoltage && !pile) continue;
            for (Stepping stepping : kSteppings) {
                // The energy check needs every step: no long advances for the twin.
                if (zeroVoltage && stepping == Stepping::ExactAdvance) continue;
                for (ModelChoice model : kModels) jobs.push_back({scene, zeroVoltage, stepping, model});
            }
        }
    }
    return jobs;
}

// Drives a simulation to step `last` the way the run does: one step() at a
// time, or advanceTo() to each 30 ms boundary. before() is called before
// each call and after(contacts, substeps) after it; the drive stops when
// after() returns false.
template <typename Before, typename After>
void drive(Simulation& sim, Stepping stepping, std::int64_t last, Before before, After after) {
    if (stepping != Stepping::ExactAdvance) {
        while (sim.state().step < last) {
            before();
            const StepReport report = sim.step();
            if (!after(std::int64_t(report.contacts), report.substeps)) return;
        }
        return;
    }
    for (std::int64_t k = 1; sim.state().step < last; ++k) {
        const std::int64_t target =
            std::min(last, Simulation::stepIndexAtOrAfter(static_cast<double>(k) * kAdvanceInterval, sim.dt()));
        if (target <= sim.state().step) continue;
        before();
        if (!after(sim.advanceTo(target).contacts, 0)) return;
    }
}

RunResult execute(const RunJob& job, const StressOptions& o) {
    const stress::StressScene s = stress::makeStressScene(o.seed, job.scene, o.seconds);
    Scene scene = job.zeroVoltage ? s.zeroVoltage : s.scene;
    RunResult result;
    result.kind = s.kind;
    switch (job.stepping) {
        case Stepping::Euler:
            scene.simulation.integrator = Integrator::Euler;
            result.dt = s.dtEuler;
            break;
        case Stepping::Rk4:
            scene.simulation.integrator = Integrator::Rk4;
            result.dt = s.dtRk4;
            break;
        case Stepping::Exact:
        case Stepping::ExactAdvance:
            scene.simulation.integrator = Integrator::Exact;
            result.dt = s.dtExact;
            break;
    }
    scene.simulation.dt = result.dt;
    scene.simulation.collision_model =
        job.model == ModelChoice::Paper ? CollisionModel::Paper : CollisionModel::Impulse;
    result.restitution = job.model == ModelChoice::ImpulseRandom ? s.restitution : 1.0;
    scene.simulation.restitution = result.restitution;

    const std::int64_t last = Simulation::stepIndexAtOrAfter(o.seconds, result.dt);
    std::int64_t reached = 0;
    std::uint64_t hash = 0;
    {
        Simulation sim(scene);
        stress::RunChecker checker(sim.model(), sim.state(), job.zeroVoltage);
        drive(
            sim, job.stepping, last, [&] { checker.beforeStep(sim.state()); },
            [&](std::int64_t contacts, int substeps) { return checker.afterStep(sim.state(), contacts, substeps); });
        reached = sim.state().step;
        hash = hashState(sim.state());
        result.figures = checker.figures();
    }
    // Determinism: the same scene driven the same way to the same step.
    Simulation again(scene);
    drive(
        again, job.stepping, reached, [] {}, [](std::int64_t, int) { return true; });
    result.figures.determinismChecked = true;
    result.figures.deterministic = again.state().step == reached && hashState(again.state()) == hash;
    return result;
}

// ---------------------------------------------------------------- report

QString figure(double value) { return value == 0.0 ? QStringLiteral("0") : QString::number(value, 'e', 2); }

QString modelLabel(const RunJob& job, const RunResult& r) {
    if (job.model == ModelChoice::Paper) return QStringLiteral("paper");
    return QStringLiteral("impulse e=%1")
        .arg(r.restitution == 1.0 ? QStringLiteral("1") : QString::number(r.restitution, 'f', 2));
}

QString kindLabel(const RunJob& job, const RunResult& r) {
    return QString::fromLatin1(stress::sceneKindName(r.kind)) + (job.zeroVoltage ? QStringLiteral("-0V") : QString());
}

QString tableHeader() {
    return QStringLiteral("%1 %2 %3 %4 %5 %6 %7 %8 %9 %10 %11 %12\n")
        .arg("scene", 5)
        .arg("kind", -14)
        .arg("integrator", -10)
        .arg("dt [ms]", 8)
        .arg("model", -15)
        .arg("steps", 8)
        .arg("contacts", 9)
        .arg("outside [m]", 11)
        .arg("overlap [m]", 11)
        .arg("energy [J]", 10)
        .arg("deterministic", -13)
        .arg("check");
}

QString tableRow(const RunJob& job, const RunResult& r) {
    const RunFigures& f = r.figures;
    return QStringLiteral("%1 %2 %3 %4 %5 %6 %7 %8 %9 %10 %11 %12\n")
        .arg(job.scene, 5)
        .arg(kindLabel(job, r), -14)
        .arg(steppingName(job.stepping), -10)
        .arg(r.dt * 1e3, 8, 'f', 3)
        .arg(modelLabel(job, r), -15)
        .arg(f.steps, 8)
        .arg(f.contacts, 9)
        .arg(f.finite ? figure(f.outside) : QStringLiteral("NaN/inf"), 11)
        .arg(f.finite ? figure(f.overlap) : QStringLiteral("NaN/inf"), 11)
        .arg(f.energyMeasured ? figure(f.energyGain) : QStringLiteral("-"), 10)
        .arg(f.deterministic ? "yes" : "NO", -13)
        .arg(stress::failedChecks(f).isEmpty() ? "ok" : "FAIL");
}

// The worst figures of a group of runs.
struct Worst {
    int runs = 0;
    int nonFinite = 0;
    int nondeterministic = 0;
    int energyRuns = 0;
    double outside = 0.0;         // m
    double overlap = 0.0;         // m
    double energyGain = 0.0;      // J
    double energyRelative = 0.0;  // relative to the energy before the step

    void add(const RunFigures& f) {
        ++runs;
        if (!f.finite) ++nonFinite;
        if (!f.deterministic) ++nondeterministic;
        outside = std::max(outside, f.outside);
        overlap = std::max(overlap, f.overlap);
        if (f.energyMeasured) {
            ++energyRuns;
            energyGain = std::max(energyGain, f.energyGain);
            energyRelative = std::max(energyRelative, f.energyGainRelative);
        }
    }
};

QString summaryRow(const QString& name, const Worst& w) {
    return QStringLiteral("  %1 %2 %3 %4 %5 %6 %7 %8\n")
        .arg(name, -12)
        .arg(w.runs, 5)
        .arg(w.nonFinite, 8)
        .arg(figure(w.outside), 11)
        .arg(figure(w.overlap), 11)
        .arg(w.energyRuns > 0 ? figure(w.energyGain) : QStringLiteral("-"), 10)
        .arg(w.energyRuns > 0 ? figure(w.energyRelative) : QStringLiteral("-"), 10)
        .arg(w.nondeterministic, 16);
}

QString summaryHeader(const QString& group) {
    return QStringLiteral("  %1 %2 %3 %4 %5 %6 %7 %8\n")
        .arg(group, -12)
        .arg("runs", 5)
        .arg("NaN/inf", 8)
        .arg("outside [m]", 11)
        .arg("overlap [m]", 11)
        .arg("energy [J]", 10)
        .arg("energy rel", 10)
        .arg("nondeterministic", 16);
}

QString reproduceCommand(const StressOptions& o, int scene) {
    return QStringLiteral("vssim stress --seed %1 --seconds %2 --only %3").arg(o.seed).arg(o.seconds).arg(scene);
}

class Progress {
public:
    explicit Progress(std::size_t total) : total_(total), enabled_(isatty(STDERR_FILENO)) {}
    void update(std::size_t done, int scene) {
        if (!enabled_) return;
        err() << QStringLiteral("\rvssim stress: %1/%2 runs, scene %3 ").arg(done).arg(total_).arg(scene) << Qt::flush;
        shown_ = true;
    }
    void done() {
        if (shown_) err() << "\r" << QString(60, ' ') << "\r" << Qt::flush;
        shown_ = false;
    }
    bool enabled() const { return enabled_; }

private:
    std::size_t total_;
    bool enabled_;
    bool shown_ = false;
};

}  // namespace

QString stressHelpText() {
    return QStringLiteral(
               "Usage: vssim stress [--scenes N] [--seconds S] [--seed K] [--only K] [--jobs N]\n"
               "\n"
               "Numerical-stability stress test: runs N random scenes for S simulated seconds each\n"
               "and checks every step for problems. Scene k cycles through seven kinds: robot piles\n"
               "(6-16 robots packed around the ball, full voltage, signs flipping every 0.1-0.5 s),\n"
               "alternating voltages (+-7.4 V every 2-100 ms, robots spread over the field), corner\n"
               "shots (the ball fired at 5-10 m/s into a corner, robots near the corners), extreme\n"
               "parameters (light and heavy, stiff and asymmetric robots, varied balls), and on an\n"
               "official field with goals: goal corners (robots in the goals and against the corner\n"
               "triangles, the ball fired into a goal), post wedge (the ball against a goal post, a\n"
               "robot pushing it into the post) and in goal (a robot inside each goal, others at it).\n"
               "Each scene runs with euler, rk4 and exact (a random dt of %1-%2 ms, exact up to %3 ms),\n"
               "exact also advancing to 30 ms boundaries with long steps (exact/30ms), each with the\n"
               "paper model, the impulse model at restitution 1 and at a random restitution < 1;\n"
               "every pile also runs at 0 V from random velocities to measure energy created by\n"
               "collisions (kind pile-0V). Every run is done twice to check determinism.\n"
               "\n"
               "Options:\n"
               "  --scenes N   number of random scenes, 1 to %4 (default %5)\n"
               "  --seconds S  simulated seconds per run, 0 < S <= %6 (default %7)\n"
               "  --seed K     seed of the scene generator, 0 to 4294967295 (default %8)\n"
               "  --only K     run only scene K (>= 1) of this seed, to reproduce a failure;\n"
               "               --scenes is then ignored\n"
               "  --jobs N     worker threads, 1 to %9 (default: the number of cores); the\n"
               "               results do not depend on it\n"
               "  -h, --help   show this help\n"
               "scenes x seconds may be at most %10 scene-seconds (about %11 hours of one core).\n"
               "\n"
               "Table, one line per run: scene number, kind, integrator, dt [ms], collision model,\n"
               "steps, contacts (summed over the steps), outside [m] (worst distance of a robot\n"
               "vertex or the ball's edge beyond the walls, or of a goal post inside a robot),\n"
               "overlap [m] (deepest overlap between two bodies after a step), energy [J] (0 V runs\n"
               "only: the most kinetic energy the contacts of one step created, i.e. the energy\n"
               "after the step minus the energy the same step reaches without contacts),\n"
               "deterministic (a second run ended bit-identical), check (ok or FAIL). Then the worst\n"
               "figures per integrator and per collision model, with the energy also relative to the\n"
               "energy before the step.\n"
               "A progress line goes to standard error when it is a terminal.\n"
               "\n"
               "Exit status: 0 every run passed (no NaN/inf, nothing outside the field by more than\n"
               "1e-9 m, no overlap beyond 1 mm, no energy created beyond 1e-9 of the energy before\n"
               "the step, every run deterministic), 1 a check failed (the failures are listed with\n"
               "the command that reruns the scene), 2 bad option.\n")
        .arg(stress::kMinDt * 1e3)
        .arg(stress::kMaxDt * 1e3)
        .arg(stress::kMaxExactDt * 1e3)
        .arg(kMaxScenes)
        .arg(kDefaultScenes)
        .arg(kMaxSeconds)
        .arg(kDefaultSeconds)
        .arg(kDefaultSeed)
        .arg(kMaxJobs)
        .arg(kMaxSceneSeconds)
        .arg(kMaxSceneSeconds * kCpuPerSceneSecond / 3600.0, 0, 'f', 0);
}

int stressCommand(const QStringList& arguments) {
    QString error;
    bool helpAsked = false;
    const std::optional<StressOptions> parsed = parseStressOptions(arguments, &error, &helpAsked);
    if (helpAsked) {
        out() << stressHelpText();
        return 0;
    }
    if (!parsed) {
        err() << "vssim stress: " << error << "\n";
        return 2;
    }
    const StressOptions o = *parsed;
    const std::vector<RunJob> jobs = jobsFor(o);
    QElapsedTimer clock;
    clock.start();
    out() << QStringLiteral("vssim stress: seed %1, %2, %3 s per run, %4 runs (each twice), %5 threads\n\n")
                 .arg(o.seed)
                 .arg(o.only > 0 ? QStringLiteral("scene %1 only").arg(o.only)
                                 : QStringLiteral("%1 scenes").arg(o.scenes))
                 .arg(o.seconds)
                 .arg(jobs.size())
                 .arg(std::min<std::size_t>(o.jobs, jobs.size()))
          << tableHeader() << Qt::flush;

    // Workers take runs in order; the main thread prints them in order as they finish.
    std::vector<RunResult> results(jobs.size());
    std::vector<char> finished(jobs.size(), 0);
    std::mutex mutex;
    std::condition_variable finishedOne;
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> workers;
    for (int t = 0; t < std::min<int>(o.jobs, static_cast<int>(jobs.size())); ++t)
        workers.emplace_back([&] {
            for (std::size_t i = next++; i < jobs.size(); i = next++) {
                RunResult r = execute(jobs[i], o);
                {
                    const std::lock_guard<std::mutex> lock(mutex);
                    results[i] = r;
                    finished[i] = 1;
                }
                finishedOne.notify_one();
            }
        });

    Progress progress(jobs.size());
    std::map<QString, Worst> byIntegrator, byModel;
    QStringList failures;
    for (std::size_t printed = 0; printed < jobs.size(); ++printed) {
        RunResult r;
        {
            std::unique_lock<std::mutex> lock(mutex);
            while (!finished[printed]) {
                finishedOne.wait_for(lock, std::chrono::milliseconds(500));
                if (progress.enabled() && !finished[printed]) {
                    const std::size_t done = static_cast<std::size_t>(std::count(finished.begin(), finished.end(), 1));
                    lock.unlock();
                    progress.update(done, jobs[printed].scene);
                    lock.lock();
                }
            }
            r = results[printed];
        }
        const RunJob& job = jobs[printed];
        progress.done();
        out() << tableRow(job, r) << Qt::flush;
        byIntegrator[steppingName(job.stepping)].add(r.figures);
        byModel[modelGroupName(job.model)].add(r.figures);
        for (const QString& failure : stress::failedChecks(r.figures))
            failures << QStringLiteral("scene %1 (seed %2; %3, %4, dt %5 ms, %6): %7\n    rerun: %8")
                            .arg(job.scene)
                            .arg(o.seed)
                            .arg(kindLabel(job, r), steppingName(job.stepping))
                            .arg(r.dt * 1e3, 0, 'f', 3)
                            .arg(modelLabel(job, r), failure, reproduceCommand(o, job.scene));
    }
    for (std::thread& worker : workers) worker.join();
    progress.done();

    out() << "\nWorst figures per integrator (energy: 0 V runs only; energy rel: relative to the energy before the "
             "step):\n"
          << summaryHeader("integrator");
    for (Stepping s : kSteppings)
        if (byIntegrator.count(steppingName(s))) out() << summaryRow(steppingName(s), byIntegrator[steppingName(s)]);
    out() << "\nWorst figures per collision model:\n" << summaryHeader("model");
    for (ModelChoice m : kModels)
        if (byModel.count(modelGroupName(m))) out() << summaryRow(modelGroupName(m), byModel[modelGroupName(m)]);
    out() << QStringLiteral("\nLimits: outside %1 m, overlap %2 m, energy created %3 of the energy before a step.\n")
                 .arg(figure(stress::kMaxOutside), figure(stress::kMaxOverlap), figure(stress::kMaxEnergyGain));
    const double seconds = clock.elapsed() / 1000.0;
    if (failures.isEmpty()) {
        out() << QStringLiteral("vssim stress: all %1 runs passed every check (%2 s of run time)\n")
                     .arg(jobs.size())
                     .arg(seconds, 0, 'f', 1)
              << Qt::flush;
        return 0;
    }
    out() << QStringLiteral("\nFAILED checks (%1):\n").arg(failures.size());
    for (const QString& failure : failures) out() << "  " << failure << "\n";
    out() << QStringLiteral("vssim stress: %1 failed checks in %2 runs (%3 s of run time)\n")
                 .arg(failures.size())
                 .arg(jobs.size())
                 .arg(seconds, 0, 'f', 1)
          << Qt::flush;
    return 1;
}

}  // namespace vssim
