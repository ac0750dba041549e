// Benchmark 3: cost per robot per simulated second from 6 to 1000 robots at
// the 3-vs-3 density, with and without the broad phase (RK4, 1 ms: the
// contact tests at every step), and with the default settings (exact, long
// steps, contacts at their time of impact: the planner's own costs).
#include <iomanip>

#include "bench_scenes.h"
#include "bench_timing.h"
#include "benchmarks.h"
#include "vssim/world.h"

namespace vssim::bench {

int scale(const Options& options, std::ostream& out, std::ostream& log) {
    const double duration = options.quick ? 0.1 : 1.0;  // s
    std::vector<int> sizes = {6, 24, 96, 384, 1000};
    if (options.quick) sizes = {6, 96};
    out << "robots,setting,broad_phase,field_side_m,simulated_s,run_time_s,us_per_robot_per_simulated_s,contacts,runs\n"
        << std::setprecision(6);
    struct Setting {
        const char* name;
        Integrator integrator;
        bool broadPhase;
    };
    const Setting settings[] = {{"rk4", Integrator::Rk4, true},
                                {"rk4", Integrator::Rk4, false},
                                {"exact, long steps (default)", Integrator::Exact, true}};
    for (const int n : sizes) {
        for (const Setting& setting : settings) {
            Scene scene = crowdScene(1000 + n, n, duration);
            scene.simulation.broad_phase = setting.broadPhase;
            scene.simulation.integrator = setting.integrator;
            std::int64_t contacts = 0;
            auto run = [&] {
                Simulation sim(scene);
                contacts = sim.advanceTo(Simulation::stepIndexAtOrAfter(duration, scene.simulation.dt)).contacts;
            };
            const Timing t = timeMedian(run, options.quick ? 1 : 3, options.quick ? 0.0 : 1.0, options.quick ? 1 : 15);
            const double perRobot = t.median / (n * duration) * 1e6;  // us per robot per simulated s
            out << n << ",\"" << setting.name << "\"," << (setting.broadPhase ? "on" : "off") << ','
                << scene.field.length << ',' << duration << ',' << t.median << ',' << perRobot << ',' << contacts << ','
                << t.runs << '\n';
            log << "  " << std::setw(5) << n << " robots, " << std::setw(28) << setting.name << ", broad phase "
                << (setting.broadPhase ? "on " : "off") << "  " << std::setw(9) << perRobot
                << " us per robot per simulated s  (" << contacts << " contacts)\n";
        }
    }
    return 0;
}

}  // namespace vssim::bench
