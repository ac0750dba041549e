// Benchmark 3: cost per robot per simulated second from 6 to 1000 robots at
// the 3-vs-3 density, five crowds of each size, with and without the broad
// phase (RK4, 1 ms: the contact tests at every step), and with the default
// settings (exact, long steps, contacts at their time of impact: the
// planner's own costs).
#include <cmath>
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
    // Several crowds of each size: one second of one crowd is mostly luck
    // (whether a pair happens to meet; at 6 robots one crowd costs three
    // times another), which is not what this benchmark is about. The first
    // crowd of each size is the one measured alone before (seed 1000 + n).
    const int crowds = options.quick ? 1 : 5;
    out << "robots,setting,broad_phase,field_side_m,simulated_s,run_time_s,us_per_robot_per_simulated_s,contacts,runs,"
           "crowds,us_per_robot_fewest,us_per_robot_most,us_per_robot_first_crowd\n"
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
            double runTime = 0.0;  // s, the crowds' medians summed
            double fewest = INFINITY, most = 0.0, first = 0.0;  // us per robot per simulated s
            std::int64_t contacts = 0;
            int runs = 0;
            double fieldSide = 0.0;  // m
            for (int k = 0; k < crowds; ++k) {
                Scene scene = crowdScene(static_cast<std::uint32_t>(1000 + n + 7919 * k), n, duration);
                scene.simulation.broad_phase = setting.broadPhase;
                scene.simulation.integrator = setting.integrator;
                fieldSide = scene.field.length;
                std::int64_t crowdContacts = 0;
                auto run = [&] {
                    Simulation sim(scene);
                    crowdContacts =
                        sim.advanceTo(Simulation::stepIndexAtOrAfter(duration, scene.simulation.dt)).contacts;
                };
                const Timing t =
                    timeMedian(run, options.quick ? 1 : 3, options.quick ? 0.0 : 0.3, options.quick ? 1 : 15);
                const double perRobot = t.median / (n * duration) * 1e6;
                if (k == 0) first = perRobot;
                fewest = std::min(fewest, perRobot);
                most = std::max(most, perRobot);
                runTime += t.median;
                contacts += crowdContacts;
                runs += t.runs;
            }
            const double perRobot = runTime / (crowds * n * duration) * 1e6;  // us per robot per simulated s
            out << n << ",\"" << setting.name << "\"," << (setting.broadPhase ? "on" : "off") << ',' << fieldSide << ','
                << duration << ',' << runTime << ',' << perRobot << ',' << contacts << ',' << runs << ',' << crowds
                << ',' << fewest << ',' << most << ',' << first << '\n';
            log << "  " << std::setw(5) << n << " robots, " << std::setw(28) << setting.name << ", broad phase "
                << (setting.broadPhase ? "on " : "off") << "  " << std::setw(9) << perRobot
                << " us per robot per simulated s (" << crowds << (crowds == 1 ? " crowd" : " crowds, each ") << fewest
                << " to " << most << "; " << contacts << " contacts)\n";
        }
    }
    return 0;
}

}  // namespace vssim::bench
