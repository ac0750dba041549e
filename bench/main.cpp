// vssim_bench: runs the benchmarks of docs/performance.md and writes CSV.
//
//   vssim_bench [--quick] [--out DIR] [--scene FILE] [--field NAME]
//               [all|work-precision|realtime|scale|stability|serve|firasim|match|camera|box2d]...
#include <QCoreApplication>
#include <QDir>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <string>

#include "benchmarks.h"

namespace {

const char* kHelp =
    "Usage: vssim_bench [options] [BENCHMARK...]\n"
    "\n"
    "Runs the benchmarks of docs/performance.md (Release build!) and writes one CSV per\n"
    "benchmark into the output folder, with a summary on standard error.\n"
    "\n"
    "Benchmarks (default: all):\n"
    "  work-precision   position error against run time, each integrator and step (work_precision.csv)\n"
    "  realtime         real-time factor of the 3-vs-3 scene headless (realtime.csv)\n"
    "  scale            cost per robot from 6 to 1000 robots (5 crowds each, 3 interleaved rounds), broad\n"
    "                   phase on/off (scale.csv)\n"
    "  stability        each integrator's stability limit in step size (stability.csv)\n"
    "  serve            vssim serve in real time for a minute: command latency, image period and\n"
    "                   jitter, render/encode time, bytes per frame (serve.csv)\n"
    "  firasim          vssim serve --firasim, both teams as UDP clients: command latency, vision\n"
    "                   period and jitter at 60 Hz, bytes per packet, with the TCP protocol beside\n"
    "                   as a baseline; --speed max and --firasim-sync rates (firasim.csv)\n"
    "  camera           the camera's render and encode time per frame: ideal, realistic without and\n"
    "                   with motion blur, on the moving 3-vs-3 kick-off (camera.csv)\n"
    "  match            whole 3-vs-3 matches with the referee: real-time factor, the built-in\n"
    "                   team's goals against an idle team and itself, the game layer's cost, and\n"
    "                   where exact's time goes: ticks with the ball squeezed against a wall, other\n"
    "                   contacts, none, at the 10 ms tick and at 30 ms (match.csv)\n"
    "  box2d            the 3-vs-3 scene with random voltages on the official field (8 games,\n"
    "                   seeds 7 to 14) in a Box2D 2.4 top-down baseline at 1 ms beside vssim (RK4\n"
    "                   1 ms, exact with long steps),\n"
    "                   timed in interleaved rounds, with a one-robot sanity check (box2d.csv;\n"
    "                   only when built with Box2D: Debian's libbox2d-dev)\n"
    "\n"
    "Options:\n"
    "  --out DIR      folder for the CSV files (default: bench-results), created if needed\n"
    "  --scene FILE   the 3-vs-3 scene (default: resources/scenes/kickoff_3v3.json of the source tree)\n"
    "  --field NAME   realtime: run the 3-vs-3 scene on this field instead of its own: box (the\n"
    "                 seed's 1.50 x 1.30 m box), vsss_3v3 or vsss_5v5 (official, with goals);\n"
    "                 box2d: this field instead of vsss_3v3\n"
    "  --quick        fewer configurations and single runs: a smoke test, not figures to quote\n"
    "  -h, --help     this help\n";

}  // namespace

int main(int argc, char** argv) {
    QCoreApplication app(argc, argv);  // Qt Core only for reading the scene file
    vssim::bench::Options options;
    options.sceneDir = VSSIM_SOURCE_DIR "/resources/scenes";
    options.sceneFile = options.sceneDir + "/kickoff_3v3.json";
    std::string outDir = "bench-results";
    using Bench = int (*)(const vssim::bench::Options&, std::ostream&, std::ostream&);
    const std::map<std::string, std::pair<Bench, const char*>> benches = {
        {"work-precision", {vssim::bench::workPrecision, "work_precision.csv"}},
        {"realtime", {vssim::bench::realtimeFactor, "realtime.csv"}},
        {"scale", {vssim::bench::scale, "scale.csv"}},
        {"stability", {vssim::bench::stability, "stability.csv"}},
        {"serve", {vssim::bench::serveLatency, "serve.csv"}},
        {"firasim", {vssim::bench::firasimLatency, "firasim.csv"}},
        {"match", {vssim::bench::matchBenchmark, "match.csv"}},
        {"camera", {vssim::bench::cameraRender, "camera.csv"}},
#if VSSIM_HAVE_BOX2D
        {"box2d", {vssim::bench::box2dBaseline, "box2d.csv"}},
#endif
    };
    std::vector<std::string> chosen;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            std::cout << kHelp;
            return 0;
        } else if (a == "--quick") {
            options.quick = true;
        } else if ((a == "--out" || a == "--scene") && i + 1 < argc) {
            (a == "--out" ? outDir : options.sceneFile) = argv[++i];
        } else if (a == "--field" && i + 1 < argc) {
            const std::string name = argv[++i];
            if (name == "box")
                options.field = vssim::FieldType::Box;
            else if (name == "vsss_3v3")
                options.field = vssim::FieldType::Vsss3v3;
            else if (name == "vsss_5v5")
                options.field = vssim::FieldType::Vsss5v5;
            else {
                std::cerr << "vssim_bench: --field: box, vsss_3v3 or vsss_5v5, not \"" << name << "\"\n";
                return 2;
            }
        } else if (a == "all") {
            for (const auto& [name, bench] : benches) chosen.push_back(name);
        } else if (benches.count(a)) {
            chosen.push_back(a);
        } else if (a == "box2d") {  // registered above only when built with Box2D
            std::cerr << "vssim_bench: box2d: this vssim_bench was built without Box2D; install Debian's "
                         "libbox2d-dev (./setup.sh does), configure again (cmake -S . -B build) and rebuild\n";
            return 2;
        } else {
            std::cerr << "vssim_bench: unknown argument \"" << a << "\" (or a missing value)\n\n" << kHelp;
            return 2;
        }
    }
    if (chosen.empty())
        for (const char* name :
             {"stability", "work-precision", "realtime", "scale", "serve", "firasim", "match", "camera", "box2d"})
            if (benches.count(name)) chosen.push_back(name);  // box2d only when built with Box2D
    if (!QDir().mkpath(QString::fromStdString(outDir))) {
        std::cerr << "vssim_bench: cannot create " << outDir << "\n";
        return 1;
    }
    for (const std::string& name : chosen) {
        const auto& [bench, file] = benches.at(name);
        const std::string path = outDir + "/" + file;
        std::ofstream out(path);
        if (!out) {
            std::cerr << "vssim_bench: cannot write " << path << "\n";
            return 1;
        }
        std::cerr << name << " -> " << path << "\n";
        try {
            if (const int status = bench(options, out, std::cerr); status != 0) return status;
        } catch (const std::exception& e) {
            std::cerr << "vssim_bench: " << name << ": " << e.what() << "\n";
            return 1;
        }
        if (!out.flush()) {
            std::cerr << "vssim_bench: failed to write " << path << "\n";
            return 1;
        }
    }
    return 0;
}
