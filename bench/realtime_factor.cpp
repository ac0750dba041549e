// Benchmark 2: real-time factor of the 3-vs-3 scene headless (no camera),
// 60 s of the shipped kick-off, advanced frame by frame (30 ms) as a server
// would: as shipped (a few commands), and with random voltages every 30 ms
// (a controller changing every voltage every frame: the hard case for long
// steps). With each integrator; the default, the exact integrator with long
// steps, is also the one that keeps the position error under 1 um
// (benchmark 1).
#include <iomanip>
#include <stdexcept>

#include "bench_scenes.h"
#include "bench_timing.h"
#include "benchmarks.h"
#include "io/scene_io.h"
#include "vssim/world.h"

namespace vssim::bench {

int realtimeFactor(const Options& options, std::ostream& out, std::ostream& log) {
    const double duration = options.quick ? 5.0 : 60.0;  // s
    const Scene shipped = loadScene(options.sceneFile);
    const struct {
        const char* name;
        Scene scene;
    } scenarios[] = {
        {"kickoff as shipped", shipped},
        {"kickoff, random voltages every 30 ms", kickoffWithRandomVoltages(options.sceneFile, 7, duration, 0.03)}};
    struct Setting {
        const char* name;
        Integrator integrator;
        bool longSteps;
        bool timeOfImpact = true;
    };
    // The scene's own integrator is overridden; "(default)" marks what a
    // scene without one gets (SimulationSettings).
    const Setting settings[] = {{"rk4", Integrator::Rk4, false},
                                {"euler", Integrator::Euler, false},
                                {"exact, fixed steps", Integrator::Exact, false},
                                {"exact, long steps, contacts on the grid", Integrator::Exact, true, false},
                                {"exact, long steps (default)", Integrator::Exact, true}};
    out << "scenario,setting,dt_s,simulated_s,run_time_s,realtime_factor,step_calls,long_steps,contacts,impacts,runs\n"
        << std::setprecision(6);
    for (const auto& scenario : scenarios) {
        log << "  " << scenario.name << ":\n";
        for (const Setting& s : settings) {
            Scene scene = scenario.scene;
            if (options.field) scene.field = makeField(officialDimensions(*options.field));
            scene.simulation.integrator = s.integrator;
            scene.simulation.long_steps = s.longSteps;
            scene.simulation.time_of_impact = s.timeOfImpact;
            const std::int64_t end = Simulation::stepIndexAtOrAfter(duration, scene.simulation.dt);
            AdvanceReport totals;
            auto run = [&] {
                Simulation sim(scene);
                totals = {};
                const std::int64_t perFrame = Simulation::stepIndexAtOrAfter(0.03, scene.simulation.dt);
                for (std::int64_t k = perFrame; k < end + perFrame;
                     k += perFrame) {  // frame by frame, as a server would
                    const AdvanceReport r = sim.advanceTo(std::min(k, end));
                    totals.stepCalls += r.stepCalls;
                    totals.longSteps += r.longSteps;
                    totals.contacts += r.contacts;
                    totals.impacts += r.impacts;
                }
            };
            const Timing t = timeMedian(run, options.quick ? 1 : 5, options.quick ? 0.0 : 1.0, options.quick ? 1 : 21);
            out << '"' << scenario.name << "\",\"" << s.name << "\"," << scene.simulation.dt << ',' << duration << ','
                << t.median << ',' << duration / t.median << ',' << totals.stepCalls << ',' << totals.longSteps << ','
                << totals.contacts << ',' << totals.impacts << ',' << t.runs << '\n';
            log << "  " << std::setw(27) << s.name << "  " << std::setw(9) << duration / t.median << "x real time  ("
                << t.median * 1e3 << " ms for " << duration << " s; " << totals.stepCalls << " steps of dt, "
                << totals.longSteps << " long steps, " << totals.contacts << " contacts, " << totals.impacts
                << " at their instant)\n";
        }
    }
    return 0;
}

}  // namespace vssim::bench
