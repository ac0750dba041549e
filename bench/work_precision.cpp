// Benchmark 1, work against precision: for each integrator and step, the
// largest position error over a 10 s free-flight scene with random voltages
// every 30 ms, against a reference, and the run time.
//
// The reference is the exact integrator with fixed steps of 0.25 ms (120
// panels per voltage interval, a step none of the measured runs uses),
// itself checked against RK4 at 10 us; their largest difference is printed
// with the results.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <vector>

#include "bench_scenes.h"
#include "bench_timing.h"
#include "benchmarks.h"
#include "io/scene_io.h"
#include "vssim/world.h"

namespace vssim::bench {

namespace {

constexpr double kDuration = 10.0;  // s
constexpr double kPeriod = 0.03;    // s between voltage changes (and samples)

struct Config {
    Integrator integrator;
    bool longSteps;
    double dt;  // s
};

// Robot positions at every 30 ms sample, flattened.
std::vector<double> samplePositions(const Scene& base, const Config& c, std::int64_t* contacts) {
    Scene scene = base;
    scene.simulation.integrator = c.integrator;
    scene.simulation.long_steps = c.longSteps;
    scene.simulation.dt = c.dt;
    Simulation sim(scene);
    const std::int64_t stepsPerSample = std::llround(kPeriod / c.dt);
    const int samples = static_cast<int>(std::lround(kDuration / kPeriod));
    std::vector<double> positions;
    positions.reserve(samples * scene.robots.size() * 2);
    for (int k = 1; k <= samples; ++k) {
        const AdvanceReport r = sim.advanceTo(k * stepsPerSample);
        if (contacts) *contacts += r.contacts;
        for (const RobotState& robot : sim.state().robots) {
            positions.push_back(robot.x);
            positions.push_back(robot.y);
        }
    }
    return positions;
}

double maxDistance(const std::vector<double>& a, const std::vector<double>& b) {
    double worst = 0.0;
    for (std::size_t k = 0; k + 1 < a.size(); k += 2)
        worst = std::max(worst, std::hypot(a[k] - b[k], a[k + 1] - b[k + 1]));
    return worst;
}

std::string label(const Config& c) {
    if (c.integrator == Integrator::Exact) return c.longSteps ? "exact" : "exact-fixed";
    return c.integrator == Integrator::Euler ? "euler" : "rk4";
}

// Whether `c` is what a scene gets by default (the exact integrator with long
// steps at 1 ms), for the printed summary; plot.py marks it in the figure.
bool isDefault(const Config& c) {
    const SimulationSettings defaults;
    return c.integrator == defaults.integrator && c.longSteps == defaults.long_steps && c.dt == defaults.dt;
}

}  // namespace

int workPrecision(const Options& options, std::ostream& out, std::ostream& log) {
    const Scene scene = freeFlightScene(2003, kDuration, kPeriod);
    std::int64_t contacts = 0;
    const std::vector<double> reference = samplePositions(scene, {Integrator::Exact, false, 2.5e-4}, &contacts);
    const std::vector<double> fineRk4 = samplePositions(scene, {Integrator::Rk4, false, 1e-5}, &contacts);
    if (contacts != 0) {
        log << "work-precision: the free-flight scene had " << contacts << " contacts; it must have none\n";
        return 1;
    }
    log << std::setprecision(3)
        << "work-precision: reference = exact, 0.25 ms steps; its largest distance to RK4 at 10 us is "
        << maxDistance(reference, fineRk4) << " m\n";

    std::vector<double> steps = {1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 3e-3, 5e-3, 6e-3, 1e-2, 1.5e-2, 3e-2};
    if (options.quick) steps = {1e-3, 1e-2, 3e-2};
    out << "integrator,dt_s,max_position_error_m,run_time_s,realtime_factor,runs\n" << std::setprecision(6);
    for (const Integrator integrator : {Integrator::Euler, Integrator::Rk4, Integrator::Exact}) {
        for (const bool longSteps : {false, true}) {
            if (longSteps && integrator != Integrator::Exact) continue;
            for (const double dt : steps) {
                const Config c{integrator, longSteps, dt};
                const double error = maxDistance(samplePositions(scene, c, nullptr), reference);
                const Timing t = timeMedian([&] { samplePositions(scene, c, nullptr); }, options.quick ? 1 : 3,
                                            options.quick ? 0.0 : 0.5, options.quick ? 1 : 15);
                out << label(c) << ',' << dt << ',' << error << ',' << t.median << ',' << kDuration / t.median << ','
                    << t.runs << '\n';
                log << "  " << std::setw(11) << label(c) << "  dt " << std::setw(7) << dt * 1e3 << " ms  error "
                    << std::setw(10) << error << " m  " << std::setw(9) << t.median * 1e3 << " ms per 10 s  ("
                    << std::setw(8) << kDuration / t.median << "x real time)" << (isDefault(c) ? "  (default)" : "")
                    << '\n';
            }
        }
    }
    return 0;
}

}  // namespace vssim::bench
