// Benchmark 4: each integrator's stability limit in step size, for the
// default robot and for stiff extreme parameters, found by bisection and set
// beside the linear theory: explicit Euler is stable for h < 2/|lambda|max,
// classical RK4 for h < 2.785/|lambda|max (the real-axis end of its
// stability region), and the exact integrator for every h.
#include <cmath>
#include <iomanip>

#include "bench_scenes.h"
#include "bench_timing.h"
#include "benchmarks.h"
#include "vssim/integrator.h"
#include "vssim/robot_model.h"

namespace vssim::bench {

namespace {

// Stable: from rest under constant voltages, 2000 steps stay bounded and
// end at the steady state (within 1e-6 relative, or the run is too short to
// tell, which only happens for tiny steps, far below the limits).
bool stable(const RobotModel& m, Integrator method, double h) {
    const Voltages e{7.4, 3.0};
    const Eigen::Vector2d target = steadyStateVelocity(m, e);
    RobotState s;
    for (int k = 0; k < 2000; ++k) {
        integrateRobot(m, s, e, h, method);
        if (!(std::abs(s.v) < 1e3 * std::abs(target(0)) + 1.0)) return false;
    }
    return std::abs(s.v - target(0)) <= 1e-6 * std::abs(target(0)) &&
           std::abs(s.omega - target(1)) <= 1e-6 * std::abs(target(1)) + 1e-9;
}

// Largest stable step by bisection in log(h) between 1 us and 100 s.
double stabilityLimit(const RobotModel& m, Integrator method) {
    double lo = 1e-6, hi = 100.0;
    if (stable(m, method, hi)) return INFINITY;
    for (int k = 0; k < 60; ++k) {
        const double mid = std::sqrt(lo * hi);
        (stable(m, method, mid) ? lo : hi) = mid;
    }
    return lo;
}

}  // namespace

int stability(const Options& options, std::ostream& out, std::ostream& log) {
    struct Robot {
        const char* name;
        RobotParams params;
    };
    // Stiff but valid: resources/scenes/stiff_robot.json, a light robot on
    // strong, low-resistance motors with tiny rotor inertia.
    const Scene stiff = loadScene(options.sceneDir + "/stiff_robot.json");
    const Robot robots[] = {{"default", RobotParams{}}, {"stiff", stiff.robots.at(0).params}};
    out << "robot,fastest_rate_per_s,integrator,theory_limit_s,measured_limit_s\n" << std::setprecision(6);
    for (const Robot& r : robots) {
        const RobotModel m = makeRobotModel(r.params);
        log << "  " << r.name << " robot: fastest mode |lambda| = " << m.fastestRate << " 1/s (time constant "
            << 1e3 / m.fastestRate << " ms)\n";
        const struct {
            const char* name;
            Integrator method;
            double theory;
        } rows[] = {{"euler", Integrator::Euler, stableStepLimit(Integrator::Euler, m.fastestRate)},
                    {"rk4", Integrator::Rk4, stableStepLimit(Integrator::Rk4, m.fastestRate)},
                    {"exact", Integrator::Exact, stableStepLimit(Integrator::Exact, m.fastestRate)}};
        for (const auto& row : rows) {
            const double measured = stabilityLimit(m, row.method);
            out << r.name << ',' << m.fastestRate << ',' << row.name << ',' << row.theory << ',' << measured << '\n';
            log << "    " << std::setw(6) << row.name << "  theory h < " << std::setw(10) << row.theory
                << " s   measured " << std::setw(10) << measured << " s\n";
        }
    }
    return 0;
}

}  // namespace vssim::bench
