// Benchmark 3: cost per robot per simulated second from 6 to 1000 robots at
// the 3-vs-3 density, five crowds of each size, with and without the broad
// phase (RK4, 1 ms: the contact tests at every step), and with the default
// settings (exact, long steps, contacts at their time of impact: the
// planner's own costs).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <vector>

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
           "crowds,us_per_robot_fewest,us_per_robot_most,us_per_robot_first_crowd,rounds\n"
        << std::setprecision(6);
    struct Setting {
        const char* name;
        Integrator integrator;
        bool broadPhase;
    };
    const Setting settings[] = {{"rk4", Integrator::Rk4, true},
                                {"rk4", Integrator::Rk4, false},
                                {"exact, long steps (default)", Integrator::Exact, true}};
    // Interleaved rounds: each round times every size and setting once
    // (each crowd run for 0.1 s, 1 to 15 times, its median), the sizes
    // smallest first in odd rounds and largest first in even ones, and
    // each crowd's figure is the median of its rounds. This host's speed
    // drifts by a third within minutes; timed one size after another, a slow
    // spell at the end made the largest crowd look dearer per robot than it
    // is, which is the very ratio this benchmark is for. A round takes about
    // a minute, so the default row's largest over smallest cost per robot is
    // also given per round.
    const int rounds = options.quick ? 1 : 3;
    constexpr std::size_t kSettings = sizeof settings / sizeof settings[0];
    std::vector<std::vector<Scene>> scenes(sizes.size());  // per size, per crowd
    for (std::size_t s = 0; s < sizes.size(); ++s)
        for (int k = 0; k < crowds; ++k)
            scenes[s].push_back(crowdScene(static_cast<std::uint32_t>(1000 + sizes[s] + 7919 * k), sizes[s], duration));
    // seconds[s][setting][crowd]: one median per round; runs and contacts summed.
    std::vector<std::vector<std::vector<std::vector<double>>>> seconds(
        sizes.size(),
        std::vector<std::vector<std::vector<double>>>(kSettings, std::vector<std::vector<double>>(crowds)));
    std::vector<std::vector<std::int64_t>> contacts(sizes.size(), std::vector<std::int64_t>(kSettings, 0));
    std::vector<std::vector<int>> runs(sizes.size(), std::vector<int>(kSettings, 0));
    std::vector<double> roundSpread;  // the default row's largest / smallest cost per robot, per round
    for (int round = 0; round < rounds; ++round) {
        std::vector<double> defaultRow(sizes.size());  // us per robot per simulated s, per size, this round
        for (std::size_t order = 0; order < sizes.size(); ++order) {
            const std::size_t s = round % 2 == 0 ? order : sizes.size() - 1 - order;
            const int n = sizes[s];
            for (std::size_t j = 0; j < kSettings; ++j) {
                double sum = 0.0;  // s, this round's crowd medians
                for (int k = 0; k < crowds; ++k) {
                    Scene& scene = scenes[s][k];
                    scene.simulation.broad_phase = settings[j].broadPhase;
                    scene.simulation.integrator = settings[j].integrator;
                    std::int64_t crowdContacts = 0;
                    auto run = [&] {
                        Simulation sim(scene);
                        crowdContacts =
                            sim.advanceTo(Simulation::stepIndexAtOrAfter(duration, scene.simulation.dt)).contacts;
                    };
                    const Timing t = timeMedian(run, 1, options.quick ? 0.0 : 0.1, options.quick ? 1 : 15);
                    seconds[s][j][k].push_back(t.median);
                    sum += t.median;
                    if (round == 0) contacts[s][j] += crowdContacts;
                    runs[s][j] += t.runs;
                }
                if (settings[j].integrator == Integrator::Exact) defaultRow[s] = sum / (crowds * n * duration) * 1e6;
            }
        }
        const auto [low, high] = std::minmax_element(defaultRow.begin(), defaultRow.end());
        roundSpread.push_back(*high / *low);
        log << "  round " << round + 1 << " of " << rounds << ": default, us per robot per simulated s:";
        for (std::size_t s = 0; s < sizes.size(); ++s) log << ' ' << sizes[s] << ": " << defaultRow[s];
        log << " (largest / smallest " << roundSpread.back() << ")\n";
    }
    std::vector<double> defaultMedians;  // the default row's figures, us per robot per simulated s
    for (std::size_t s = 0; s < sizes.size(); ++s) {
        const int n = sizes[s];
        for (std::size_t j = 0; j < kSettings; ++j) {
            const Setting& setting = settings[j];
            double runTime = 0.0;                               // s: each crowd's median over the rounds, summed
            double fewest = INFINITY, most = 0.0, first = 0.0;  // us per robot per simulated s
            for (int k = 0; k < crowds; ++k) {
                const double crowdTime = median(seconds[s][j][k]);  // s
                const double perRobot = crowdTime / (n * duration) * 1e6;
                if (k == 0) first = perRobot;
                fewest = std::min(fewest, perRobot);
                most = std::max(most, perRobot);
                runTime += crowdTime;
            }
            const double perRobot = runTime / (crowds * n * duration) * 1e6;  // us per robot per simulated s
            if (setting.integrator == Integrator::Exact) defaultMedians.push_back(perRobot);
            out << n << ",\"" << setting.name << "\"," << (setting.broadPhase ? "on" : "off") << ','
                << scenes[s][0].field.length << ',' << duration << ',' << runTime << ',' << perRobot << ','
                << contacts[s][j] << ',' << runs[s][j] << ',' << crowds << ',' << fewest << ',' << most << ',' << first
                << ',' << rounds << '\n';
            log << "  " << std::setw(5) << n << " robots, " << std::setw(28) << setting.name << ", broad phase "
                << (setting.broadPhase ? "on " : "off") << "  " << std::setw(9) << perRobot
                << " us per robot per simulated s (";
            if (crowds == 1)
                log << "1 crowd";
            else
                log << crowds << " crowds, each " << fewest << " to " << most;
            log << "; " << contacts[s][j] << " contacts)\n";
        }
    }
    const auto [low, high] = std::minmax_element(defaultMedians.begin(), defaultMedians.end());
    log << "  default: largest / smallest cost per robot " << *high / *low << " (the figures above); per round ";
    for (std::size_t r = 0; r < roundSpread.size(); ++r) log << (r ? ", " : "") << roundSpread[r];
    log << " (their median " << median(roundSpread) << ")\n";
    return 0;
}

}  // namespace vssim::bench
