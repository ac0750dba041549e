// vssim_bench_gui: what the desktop app costs (docs/performance.md, "The
// desktop app"). Runs the real window under a real X server (xvfb-run, xcb)
// on the 3-vs-3 kick-off with its own commands (four robots drive), a robot
// selected (inspector and plots) and the camera dock floating beside it, and
// measures, each phase in turn:
//
//   running     main-thread CPU time per refresh (the field, trails, panels,
//               plots and camera drawn at the default 30 Hz), the process's
//               CPU (the software renderer's threads included), memory
//   paused      the process's CPU while paused and idle
//   max         simulated seconds per wall second at Speed "max", against the
//               same scene stepped headless in this process (Simulation)
//   soak        (--soak MINUTES) resident memory every 10 s
//
//   xvfb-run -a -s "-screen 0 1920x1200x24" env QT_QPA_PLATFORM=xcb
//       build/bench/vssim_bench_gui [--seconds S] [--soak MINUTES] [--out FILE.csv]
#include <QApplication>
#include <QDockWidget>
#include <QElapsedTimer>
#include <QFile>
#include <QTest>
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <string>
#include <sys/resource.h>
#include <unistd.h>

#include "field_view.h"
#include "io/scene_io.h"
#include "main_window.h"
#include "vssim/world.h"

namespace {

using vssim::MainWindow;

double threadCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double processCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double residentMiB() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    statm >> pages >> resident;
    return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

// Counts the field view's paints (its redraws).
class PaintCounter : public QObject {
public:
    int paints = 0;
    bool eventFilter(QObject*, QEvent* e) override {
        if (e->type() == QEvent::Paint) ++paints;
        return false;
    }
};

struct Row {
    std::string phase, metric, unit;
    double value;
};

}  // namespace

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    double seconds = 20.0, soakMinutes = 0.0;
    std::string out;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--seconds" && i + 1 < argc) seconds = std::stod(argv[++i]);
        else if (a == "--soak" && i + 1 < argc) soakMinutes = std::stod(argv[++i]);
        else if (a == "--out" && i + 1 < argc) out = argv[++i];
        else {
            std::cerr << "Usage: vssim_bench_gui [--seconds S] [--soak MINUTES] [--out FILE.csv]\n"
                         "  under xvfb-run with QT_QPA_PLATFORM=xcb (docs/performance.md)\n";
            return a == "-h" || a == "--help" ? 0 : 2;
        }
    }
    QString error;
    const std::optional<vssim::Scene> scene = vssim::loadSceneFile(":/scenes/kickoff_3v3.json", &error);
    if (!scene) {
        std::cerr << "vssim_bench_gui: " << error.toStdString() << "\n";
        return 1;
    }
    std::vector<Row> rows;
    vssim::ServerSettings server;
    server.port = 0;
    MainWindow window(*scene, ":/scenes/kickoff_3v3.json", server);
    window.resize(1400, 1000);
    window.show();
    if (!QTest::qWaitForWindowExposed(&window)) {
        std::cerr << "vssim_bench_gui: the window was never exposed (no X server? run under xvfb-run)\n";
        return 1;
    }
    // A robot selected (inspector and plots), the camera dock floating beside the field.
    window.fieldView().setSelectedRobot(0);
    if (auto* camera = window.findChild<QDockWidget*>("dock.camera")) {
        camera->setFloating(true);
        camera->show();
    }
    PaintCounter counter;
    window.fieldView().installEventFilter(&counter);
    QTest::qWait(2000);  // warm up: fonts, GL context, caches

    // Running at x1, 30 Hz.
    const double rss0 = residentMiB();
    counter.paints = 0;
    const double main0 = threadCpuSeconds(), proc0 = processCpuSeconds();
    QElapsedTimer wall;
    wall.start();
    QTest::qWait(static_cast<int>(seconds * 1000));
    const double wallS = 1e-3 * static_cast<double>(wall.elapsed());
    const double mainS = threadCpuSeconds() - main0, procS = processCpuSeconds() - proc0;
    const int paints = std::max(1, counter.paints);
    rows.push_back({"running", "field_paints", "1/s", paints / wallS});
    rows.push_back({"running", "main_thread_per_paint", "ms", 1e3 * mainS / paints});
    rows.push_back({"running", "main_thread_cpu", "%", 100.0 * mainS / wallS});
    rows.push_back({"running", "process_cpu", "%", 100.0 * procS / wallS});
    rows.push_back({"running", "resident_start", "MiB", rss0});
    rows.push_back({"running", "resident_end", "MiB", residentMiB()});

    // Paused and idle.
    window.session().post(vssim::EngineRequest::Kind::Pause);
    QTest::qWait(1500);
    const double proc1 = processCpuSeconds(), mainP = threadCpuSeconds();
    counter.paints = 0;
    wall.restart();
    QTest::qWait(static_cast<int>(std::min(seconds, 10.0) * 1000));
    const double pausedWall = 1e-3 * static_cast<double>(wall.elapsed());
    rows.push_back({"paused", "process_cpu", "%", 100.0 * (processCpuSeconds() - proc1) / pausedWall});
    rows.push_back({"paused", "main_thread_cpu", "%", 100.0 * (threadCpuSeconds() - mainP) / pausedWall});
    rows.push_back({"paused", "field_paints", "1/s", counter.paints / pausedWall});

    // Max speed in the app against the same scene headless.
    window.session().post(vssim::EngineRequest::Kind::Reset);
    window.session().setSpeed(0.0);
    window.session().post(vssim::EngineRequest::Kind::Resume);
    QTest::qWait(500);
    const double simStart = window.session().latest()->time;
    wall.restart();
    QTest::qWait(static_cast<int>(std::min(seconds, 10.0) * 1000));
    const double appRate = (window.session().latest()->time - simStart) / (1e-3 * static_cast<double>(wall.elapsed()));
    window.session().post(vssim::EngineRequest::Kind::Pause);
    QTest::qWait(300);
    vssim::Simulation headless(*scene);
    const std::int64_t steps = vssim::Simulation::stepIndexAtOrAfter(std::max(1.0, appRate * 2.0), headless.dt());
    wall.restart();
    headless.advanceTo(steps);
    const double headlessRate = headless.state().time / std::max(1e-9, 1e-3 * static_cast<double>(wall.elapsed()));
    rows.push_back({"max", "app_real_time_factor", "x", appRate});
    rows.push_back({"max", "headless_real_time_factor", "x", headlessRate});
    rows.push_back({"max", "headless_over_app", "ratio", headlessRate / std::max(1e-9, appRate)});

    // Memory over a long run at x1.
    if (soakMinutes > 0.0) {
        window.session().setSpeed(1.0);
        window.session().post(vssim::EngineRequest::Kind::Resume);
        const int samples = static_cast<int>(soakMinutes * 6.0);
        for (int k = 0; k <= samples; ++k) {
            rows.push_back({"soak", "resident_at_" + std::to_string(10 * k) + "s", "MiB", residentMiB()});
            if (k < samples) QTest::qWait(10000);
        }
    }

    std::ofstream file;
    if (!out.empty()) file.open(out);
    std::ostream& csv = out.empty() ? std::cout : file;
    csv << "phase,metric,unit,value\n";
    for (const Row& r : rows) csv << r.phase << ',' << r.metric << ',' << r.unit << ',' << r.value << '\n';
    for (const Row& r : rows) std::fprintf(stderr, "%-8s %-28s %10.3f %s\n", r.phase.c_str(), r.metric.c_str(), r.value, r.unit.c_str());
    return 0;
}
