// Benchmark 7: whole matches (docs/performance.md, "Matches"). The default
// match of vssim match (the official 3 vs 3 field, three robots per team,
// the referee on), seeded as vssim match --seed does:
//   speed     full matches of two 300 s halves, built-in teams, real-time
//             factor (simulated time over run time) for RK4 at 1 ms and the
//             exact integrator, one match per seed;
//   strength  the built-in team against an idle one, each side in turn (one
//             300 s half per seed), and against itself (a full match per
//             seed): goals, and those scored straight from a kick-off;
//   cost      what the game layer (referee, built-in teams, placements, the
//             Match's loop) costs: each match is replayed with a plain
//             Simulation that gets the very voltages and placements the
//             Match gave it, tick by tick (same final state hash, checked),
//             and both are timed (CPU time, the fastest of a few runs); plus the referee's and the built-in team's
//             functions timed alone on states recorded from the match;
//   contacts  where the exact integrator's time goes in a match: its ticks
//             sorted by what the world looks like at their end (the ball
//             squeezed between a wall and a robot, other contacts, none),
//             each kind's share of the ticks, the contacts and the run
//             time, at the default tick and at the camera's 30 ms.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "bench_timing.h"
#include "benchmarks.h"
#include "io/scene_io.h"
#include "match_setup.h"
#include "vssim/game/referee.h"
#include "vssim/game/sparring_team.h"
#include "vssim/separation.h"
#include "vssim/state_hash.h"

namespace vssim::bench {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// This thread's CPU time, s: unlike the wall clock, it does not count the
// time the other programs of a shared machine take the core away.
double cpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::string hex(std::uint64_t h) {
    std::ostringstream s;
    s << std::hex << std::setw(16) << std::setfill('0') << h;
    return s.str();
}

Scene matchScene(TeamControl yellow, TeamControl blue, int halves, double halfDuration, Integrator integrator) {
    Scene scene = defaultMatchScene(yellow, blue);
    scene.game.rules.halves = halves;
    scene.game.rules.half_duration = halfDuration;
    scene.simulation.integrator = integrator;
    return scene;
}

struct Played {
    double runTime = 0.0;    // s, wall clock
    double cpuTime = 0.0;    // s, this thread's CPU time
    double simulated = 0.0;  // s
    std::int64_t steps = 0;
    int goals[2] = {0, 0};
    std::size_t calls = 0;
    int kickoffGoals[2] = {0, 0};  // by team: goals within kKickoffGoalTime of its own kick-off
    std::uint64_t hash = 0;
};

// A goal this soon after the scorer's own kick-off (s of game time) counts as
// scored from the kick-off.
constexpr double kKickoffGoalTime = 5.0;

Played play(const Scene& scene, std::uint64_t seed) {
    const auto start = Clock::now();
    const double cpuStart = cpuSeconds();
    Match match(scene, seed);
    if (!playToFullTime(match, matchTimeLimit(scene.game.rules)))
        throw std::runtime_error("a match did not finish (seed " + std::to_string(seed) + ")");
    Played p;
    p.runTime = secondsSince(start);
    p.cpuTime = cpuSeconds() - cpuStart;
    p.simulated = match.simulation().state().time;
    p.steps = match.simulation().state().step;
    p.goals[0] = match.game().goals[0];
    p.goals[1] = match.game().goals[1];
    p.calls = match.game().calls.size();
    const std::vector<RefereeCall>& calls = match.game().calls;
    for (std::size_t k = 1; k < calls.size(); ++k) {
        const RefereeCall& goal = calls[k];
        const RefereeCall& before = calls[k - 1];
        if (goal.call != Call::KickOff || goal.reason.rfind("goal by ", 0) != 0) continue;
        const Team scorer = otherTeam(goal.team);
        if (before.call == Call::KickOff && before.team == scorer && before.half == goal.half &&
            goal.clock - before.clock < kKickoffGoalTime)
            ++p.kickoffGoals[teamIndex(scorer)];
    }
    p.hash = hashState(match.simulation().state());
    return p;
}

const char* kHeader =
    "part,setting,seed,yellow,blue,halves,half_duration_s,simulated_s,steps,run_time_s,realtime_factor,us_per_step,"
    "cpu_time_s,cpu_realtime_factor,"
    "goals_yellow,goals_blue,calls,state_hash,contacts\n";

void row(std::ostream& out, const char* part, const std::string& setting, std::uint64_t seed, const Scene& scene,
         const Played& p) {
    out << part << ",\"" << setting << "\"," << seed << ',' << teamControlName(scene.game.yellow).toStdString() << ','
        << teamControlName(scene.game.blue).toStdString() << ',' << scene.game.rules.halves << ','
        << scene.game.rules.half_duration << ',' << p.simulated << ',' << p.steps << ',' << p.runTime << ','
        << p.simulated / p.runTime << ',' << 1e6 * p.runTime / static_cast<double>(p.steps) << ',' << p.cpuTime << ','
        << p.simulated / p.cpuTime << ',' << p.goals[0] << ',' << p.goals[1] << ',' << p.calls << ',' << hex(p.hash)
        << ",\n";
}

// A match as the Simulation saw it: the start, and at every tick the
// voltages set and, after a call, the placement.
struct Recording {
    std::vector<RobotState> robots;  // at the start, after the kick-off placement and the jitter
    BallState ball;
    std::int64_t tickSteps = 1;
    std::vector<Voltages> voltages;  // per tick, every robot
    struct Placed {
        std::size_t tick;
        std::vector<RobotState> robots;
        BallState ball;
    };
    std::vector<Placed> placements;
    // Every `sampleEvery` ticks: the world and the game as the referee and
    // the built-in teams saw them at that tick (before their decision).
    std::vector<WorldState> states;
    std::vector<GameState> games;
    std::int64_t endStep = 0;
    std::uint64_t hash = 0;
};

constexpr std::size_t kSampleEvery = 7;

// Plays the match recording what it did to the Simulation. (Recording
// costs a little: the timed runs are separate.)
Recording record(const Scene& scene, std::uint64_t seed) {
    Recording rec;
    Match match(scene, seed);
    rec.robots = match.simulation().state().robots;
    rec.ball = match.simulation().state().ball;
    rec.tickSteps = match.tickSteps();
    std::size_t tick = 0;
    while (match.game().phase != GamePhase::Finished) {
        const std::size_t callsBefore = match.game().calls.size();
        GameState before = match.game();
        before.calls.clear();
        match.advanceTo(static_cast<std::int64_t>(tick + 1) * rec.tickSteps);
        const WorldState& s = match.simulation().state();
        if (tick % kSampleEvery == 0 && before.phase == GamePhase::GameOn) {
            // The world the tick saw: the state before any placement of this
            // tick, so only ticks of play without a call are kept.
            if (match.game().calls.size() == callsBefore) {
                rec.states.push_back(s);
                rec.games.push_back(before);
            }
        }
        rec.voltages.insert(rec.voltages.end(), s.voltages.begin(), s.voltages.end());
        if (match.game().calls.size() != callsBefore) rec.placements.push_back({tick, s.robots, s.ball});
        ++tick;
        if (s.time > matchTimeLimit(scene.game.rules) || firstNonFiniteBody(s) >= 0)  // (non-finite: it stops advancing)
            throw std::runtime_error("a match did not finish");
    }
    rec.endStep = match.simulation().state().step;
    rec.hash = hashState(match.simulation().state());
    return rec;
}

// The same match on a plain Simulation: the recorded voltages and placements
// at the same ticks. Returns the final state's hash.
std::uint64_t replay(const Scene& scene, const Recording& rec) {
    Simulation sim(scene);
    const std::size_t n = rec.robots.size();
    for (std::size_t i = 0; i < n; ++i) sim.placeRobot(static_cast<int>(i), rec.robots[i]);
    sim.placeBall(rec.ball);
    for (std::size_t i = 0; i < n; ++i) sim.setVoltages(static_cast<int>(i), {});
    std::size_t nextPlacement = 0;
    const std::size_t ticks = rec.voltages.size() / std::max<std::size_t>(n, 1);
    for (std::size_t tick = 0; tick < ticks; ++tick) {
        sim.advanceTo(static_cast<std::int64_t>(tick + 1) * rec.tickSteps);
        if (nextPlacement < rec.placements.size() && rec.placements[nextPlacement].tick == tick) {
            const auto& p = rec.placements[nextPlacement++];
            for (std::size_t i = 0; i < n; ++i) sim.placeRobot(static_cast<int>(i), p.robots[i]);
            sim.placeBall(p.ball);
        }
        for (std::size_t i = 0; i < n; ++i) sim.setVoltages(static_cast<int>(i), rec.voltages[tick * n + i]);
    }
    if (sim.state().step != rec.endStep) throw std::runtime_error("the replay ended on another step");
    return hashState(sim.state());
}

void speed(const Options& options, std::ostream& out, std::ostream& log) {
    const int seeds = options.quick ? 1 : 5;
    const double half = options.quick ? 20.0 : 300.0;
    log << "  speed: " << seeds << " full matches (2 x " << half << " s), built-in teams:\n";
    for (Integrator integrator : {Integrator::Rk4, Integrator::Exact}) {
        const Scene scene = matchScene(TeamControl::Builtin, TeamControl::Builtin, 2, half, integrator);
        const std::string setting = integrator == Integrator::Rk4 ? "rk4 1 ms" : "exact, long steps";
        std::vector<double> factors, cpuFactors, perStep;
        for (int seed = 1; seed <= seeds; ++seed) {
            const Played p = play(scene, static_cast<std::uint64_t>(seed));
            row(out, "speed", setting, static_cast<std::uint64_t>(seed), scene, p);
            factors.push_back(p.simulated / p.runTime);
            cpuFactors.push_back(p.simulated / p.cpuTime);
            perStep.push_back(1e6 * p.runTime / static_cast<double>(p.steps));
        }
        log << "  " << std::setw(20) << setting << "  median " << std::setw(7) << std::fixed << std::setprecision(0)
            << median(factors) << "x real time (" << std::defaultfloat << std::setprecision(4)
            << *std::min_element(factors.begin(), factors.end()) << " to "
            << *std::max_element(factors.begin(), factors.end()) << "; " << median(perStep)
            << " us per step of dt), by CPU time " << std::setprecision(4) << median(cpuFactors) << "x\n";
    }
}

void strength(const Options& options, std::ostream& out, std::ostream& log) {
    const double half = options.quick ? 20.0 : 300.0;
    const int againstIdle = options.quick ? 1 : 5;
    const int selfSeeds = options.quick ? 2 : 20;
    log << "  strength: one half of " << half << " s each:\n";
    for (Team builtin : {Team::Yellow, Team::Blue}) {
        const Scene scene =
            matchScene(builtin == Team::Yellow ? TeamControl::Builtin : TeamControl::Idle,
                       builtin == Team::Yellow ? TeamControl::Idle : TeamControl::Builtin, 1, half, Integrator::Rk4);
        std::vector<double> goals;
        std::ostringstream each;
        for (int seed = 1; seed <= againstIdle; ++seed) {
            const Played p = play(scene, static_cast<std::uint64_t>(seed));
            row(out, "strength", "built-in vs idle", static_cast<std::uint64_t>(seed), scene, p);
            goals.push_back(p.goals[teamIndex(builtin)]);
            each << (seed > 1 ? " " : "") << p.goals[teamIndex(builtin)] << ':' << p.goals[1 - teamIndex(builtin)];
        }
        log << "    built-in " << teamLabel(builtin) << " vs idle: goals per half " << each.str() << " (median "
            << median(goals) << ", least " << *std::min_element(goals.begin(), goals.end()) << ")\n";
    }
    // Whole matches: each team kicks off one half (one half alone would give
    // yellow, who kicks off the first, the advantage of the first kick-off).
    const Scene scene = matchScene(TeamControl::Builtin, TeamControl::Builtin, 2, half, Integrator::Rk4);
    std::vector<double> differences;
    int yellow = 0, blue = 0, yellowWins = 0, blueWins = 0, kickoffGoals[2] = {0, 0};
    for (int seed = 1; seed <= selfSeeds; ++seed) {
        const Played p = play(scene, static_cast<std::uint64_t>(seed));
        row(out, "strength", "built-in vs built-in", static_cast<std::uint64_t>(seed), scene, p);
        yellow += p.goals[0], blue += p.goals[1];
        yellowWins += p.goals[0] > p.goals[1], blueWins += p.goals[1] > p.goals[0];
        kickoffGoals[0] += p.kickoffGoals[0], kickoffGoals[1] += p.kickoffGoals[1];
        differences.push_back(p.goals[0] - p.goals[1]);
    }
    double mean = 0.0, var = 0.0;
    for (double d : differences) mean += d / differences.size();
    for (double d : differences) var += (d - mean) * (d - mean) / std::max<std::size_t>(1, differences.size() - 1);
    log << "    built-in vs built-in, " << selfSeeds << " matches of 2 x " << half << " s: yellow " << yellow
        << " goals (" << kickoffGoals[0] << " within " << kKickoffGoalTime << " s of its own kick-off), blue " << blue
        << " (" << kickoffGoals[1] << "); wins " << yellowWins << " / " << blueWins << " (draws "
        << selfSeeds - yellowWins - blueWins << "); mean difference (yellow - blue) " << std::setprecision(3) << mean
        << " +- " << std::sqrt(var / differences.size()) << " (standard error)\n";
}

void cost(const Options& options, std::ostream& out, std::ostream& log) {
    const int seeds = options.quick ? 1 : 3;
    const int repeats = options.quick ? 1 : 5;
    const double half = options.quick ? 20.0 : 300.0;
    const Scene scene = matchScene(TeamControl::Builtin, TeamControl::Builtin, 2, half, Integrator::Rk4);
    log << "  cost of the game layer (full matches, RK4 1 ms, CPU time, fastest of " << repeats << " runs each):\n";
    std::vector<double> shares;
    for (int seed = 1; seed <= seeds; ++seed) {
        const Recording rec = record(scene, static_cast<std::uint64_t>(seed));
        if (replay(scene, rec) != rec.hash || play(scene, static_cast<std::uint64_t>(seed)).hash != rec.hash)
            throw std::runtime_error("the replay of seed " + std::to_string(seed) + " differs from the match");
        std::vector<double> matchWall, matchCpu, replayWall, replayCpu;
        Played last;
        for (int r = 0; r < repeats; ++r) {  // interleaved, so both see the same machine
            last = play(scene, static_cast<std::uint64_t>(seed));
            matchWall.push_back(last.runTime);
            matchCpu.push_back(last.cpuTime);
            const auto start = Clock::now();
            const double cpuStart = cpuSeconds();
            replay(scene, rec);
            replayCpu.push_back(cpuSeconds() - cpuStart);
            replayWall.push_back(secondsSince(start));
        }
        // This thread's CPU time, the fastest of the runs: on a shared
        // machine the wall clock also counts the other programs' turns (the
        // wall-clock difference moved by +-25 % between runs).
        auto fastest = [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); };
        const double tm = fastest(matchCpu), tr = fastest(replayCpu);
        Played matched = last, replayed = last;
        matched.runTime = fastest(matchWall), matched.cpuTime = tm;
        replayed.runTime = fastest(replayWall), replayed.cpuTime = tr;
        row(out, "cost", "match", static_cast<std::uint64_t>(seed), scene, matched);
        row(out, "cost", "replay: plain Simulation, same voltages and placements", static_cast<std::uint64_t>(seed),
            scene, replayed);

        // The referee's and the built-in teams' functions alone, on the
        // recorded ticks (their inputs as the match gave them), CPU time.
        const Simulation sim(scene);
        const WorldModel& model = sim.model();
        const std::vector<Team> teams = robotTeams(scene);
        const double elapsed = static_cast<double>(rec.tickSteps) * sim.dt();
        std::vector<GameState> games = rec.games;
        std::vector<Voltages> voltages(teams.size());
        double refereeTime = 1e9, teamTime = 1e9;
        for (int r = 0; r < repeats; ++r) {
            games = rec.games;
            double start = cpuSeconds();
            for (std::size_t k = 0; k < rec.states.size(); ++k)
                refereeTick(scene.game.rules, model, rec.states[k], teams, elapsed, games[k]);
            refereeTime = std::min(refereeTime, cpuSeconds() - start);
            start = cpuSeconds();
            for (std::size_t k = 0; k < rec.states.size(); ++k)
                for (Team team : {Team::Yellow, Team::Blue})
                    sparringVoltages(model, rec.states[k], teams, scene.game.rules, rec.games[k], team, voltages);
            teamTime = std::min(teamTime, cpuSeconds() - start);
        }
        const double samples = static_cast<double>(rec.states.size());
        const double stepsPerTick = static_cast<double>(rec.tickSteps);
        const double matchPerTick = tm / static_cast<double>(last.steps) * stepsPerTick;  // s
        const double refereePerTick = refereeTime / samples, teamPerTick = teamTime / samples;
        const double share = (tm - tr) / tm;
        shares.push_back(share);
        // Per tick: us_per_step and cpu_time_s (a tick's), the other columns empty.
        auto perTick = [&](const char* what, double seconds) {
            out << "cost,\"" << what << "\"," << seed << ",,,,,,,,," << 1e6 * seconds / stepsPerTick << ',' << seconds
                << ",,,,,,\n";
        };
        perTick("referee alone, per tick", refereePerTick);
        perTick("built-in teams alone (both), per tick", teamPerTick);
        log << std::defaultfloat << std::setprecision(3) << "    seed " << seed << ": match " << tm << " s, replay "
            << tr << " s for " << last.simulated << " s simulated (" << 1e6 * tm / last.steps << " vs "
            << 1e6 * tr / last.steps << " us per step): the game layer is " << 100.0 * share
            << " % of the match's run time; alone, per tick of " << stepsPerTick << " steps: referee "
            << 1e6 * refereePerTick << " us, both built-in teams " << 1e6 * teamPerTick << " us ("
            << 100.0 * (refereePerTick + teamPerTick) / matchPerTick << " % of a tick's run time)\n";
    }
    log << "    median share of the game layer: " << std::setprecision(3) << 100.0 * median(shares) << " %\n";
}

// The ball within this distance (m) of a wall and of a robot at a tick's end
// counts as squeezed between them. (In the paper's elastic model a robot
// pushing the ball into a wall keeps it bouncing between the two, gaps of
// a fraction of a millimetre. In eight halves, 1 mm and a contact of the
// ball with both within the tick agreed on 8,353 of the 9,125 and 9,153
// ticks each found; 0.1 mm finds a quarter as many.)
constexpr double kSqueezeGap = 1e-3;

bool ballSqueezed(const WorldModel& model, const WorldState& state) {
    const Eigen::Vector2d ball(state.ball.x, state.ball.y);
    bool nearWall = false, nearRobot = false;
    for (const Wall& wall : model.field.walls)
        nearWall = nearWall || ballWallSeparation(ball, model.ball.radius, wall).distance <= kSqueezeGap;
    for (std::size_t i = 0; i < state.robots.size() && nearWall && !nearRobot; ++i)
        nearRobot = !state.offField[i] &&
                    ballRobotSeparation(ball, model.ball.radius, state.robots[i], model.sides[i]).distance <= kSqueezeGap;
    return nearWall && nearRobot;
}

// What a kind of tick amounted to over a match. Contacts are the engine's
// count (AdvanceReport::contacts): every contact found, at its instant or on
// the grid, where each pass of a step that finds one again counts it again.
struct TickShare {
    std::int64_t ticks = 0, steps = 0, contacts = 0;
    double runTime = 0.0;  // s, wall clock within advanceTo

    void add(const TickShare& o) { ticks += o.ticks, steps += o.steps, contacts += o.contacts, runTime += o.runTime; }
    // Real-time factor of these ticks on their own (NaN: none, or too quick to time).
    double factor(double dt) const { return runTime > 0.0 ? static_cast<double>(steps) * dt / runTime : NAN; }
};

// a / b as a percentage, 0 when b is 0.
double percent(double a, double b) { return b > 0.0 ? 100.0 * a / b : 0.0; }

void contacts(const Options& options, std::ostream& out, std::ostream& log) {
    const int seeds = options.quick ? 1 : 5;
    const double half = options.quick ? 20.0 : 300.0;
    enum Kind { Squeezed, OtherContacts, NoContact, Kinds };
    const char* names[Kinds] = {"ball squeezed between a wall and a robot", "other contacts", "no contact"};
    log << "  contacts: where the exact integrator's time goes, " << seeds << " full matches (2 x " << half
        << " s) per tick, built-in teams; a tick's kind from the world at its end (the ball within "
        << 1e3 * kSqueezeGap << " mm of a wall and a robot: squeezed):\n";
    for (double tick : {GameRules{}.tick, 0.03}) {
        Scene scene = matchScene(TeamControl::Builtin, TeamControl::Builtin, 2, half, Integrator::Exact);
        scene.game.rules.tick = tick;
        std::array<TickShare, Kinds> all{};
        for (int seed = 1; seed <= seeds; ++seed) {
            std::array<TickShare, Kinds> mine{};
            Match match(scene, static_cast<std::uint64_t>(seed));
            const std::int64_t tickSteps = match.tickSteps();
            const double limit = matchTimeLimit(scene.game.rules);
            while (match.game().phase != GamePhase::Finished) {
                const std::int64_t from = match.simulation().state().step;
                const auto start = Clock::now();
                const AdvanceReport r = match.advanceTo((from / tickSteps + 1) * tickSteps);
                const double took = secondsSince(start);
                const WorldState& s = match.simulation().state();
                // (A world gone non-finite stops advancing: fail, not spin.)
                if (s.time > limit || s.step == from || firstNonFiniteBody(s) >= 0)
                    throw std::runtime_error("a match did not finish (seed " + std::to_string(seed) + ")");
                const Kind kind = ballSqueezed(match.simulation().model(), s) ? Squeezed
                                  : r.contacts > 0                             ? OtherContacts
                                                                               : NoContact;
                TickShare& t = mine[kind];
                ++t.ticks, t.steps += s.step - from, t.contacts += r.contacts, t.runTime += took;
            }
            const double dt = match.simulation().dt();
            for (int k = 0; k < Kinds; ++k) {
                const TickShare& t = mine[k];
                all[k].add(t);
                out << "contacts,\"tick " << tick << " s: " << names[k] << "\"," << seed << ','
                    << teamControlName(scene.game.yellow).toStdString() << ','
                    << teamControlName(scene.game.blue).toStdString() << ',' << scene.game.rules.halves << ',' << half
                    << ',' << static_cast<double>(t.steps) * dt << ',' << t.steps << ',' << t.runTime << ',';
                if (t.steps > 0 && t.runTime > 0.0)  // (a kind with no ticks: those two columns empty)
                    out << t.factor(dt) << ',' << 1e6 * t.runTime / static_cast<double>(t.steps);
                else
                    out << ',';
                out << ",,,,,,," << t.contacts << '\n';
            }
        }
        TickShare total;
        for (const TickShare& t : all) total.add(t);
        const double dt = scene.simulation.dt;
        const double simulated = static_cast<double>(total.steps) * dt;
        log << std::defaultfloat << std::setprecision(3) << "    tick " << 1e3 * tick << " ms: " << std::fixed
            << std::setprecision(0) << total.factor(dt) << "x real time, "
            << static_cast<double>(total.contacts) / simulated << " contacts per simulated second\n";
        for (int k = 0; k < Kinds; ++k) {
            const TickShare& t = all[k];
            log << "      " << std::setw(42) << std::left << names[k] << std::right << std::fixed << std::setprecision(1)
                << std::setw(5) << percent(static_cast<double>(t.ticks), static_cast<double>(total.ticks))
                << " % of ticks, " << std::setw(5)
                << percent(static_cast<double>(t.contacts), static_cast<double>(total.contacts)) << " % of contacts, "
                << std::setw(5) << percent(t.runTime, total.runTime) << " % of run time (" << std::setprecision(0)
                << t.factor(dt) << "x real time on their own)\n";
        }
        // What the squeezes cost the match: its factor were their ticks as
        // cheap per simulated second as the ticks without a contact.
        const double freeRate = all[NoContact].factor(dt);
        if (std::isfinite(freeRate) && all[Squeezed].ticks > 0) {
            const double squeezedAsFree = static_cast<double>(all[Squeezed].steps) * dt / freeRate;
            log << "      were the squeezed ticks as cheap as those without a contact: " << std::setprecision(0)
                << simulated / (total.runTime - all[Squeezed].runTime + squeezedAsFree) << "x real time\n";
        }
    }
}

}  // namespace

int matchBenchmark(const Options& options, std::ostream& out, std::ostream& log) {
    // The log is shared by every benchmark: its number format is left as found.
    std::ios savedFormat(nullptr);
    savedFormat.copyfmt(log);
    out << kHeader << std::setprecision(6);
    speed(options, out, log);
    strength(options, out, log);
    cost(options, out, log);
    contacts(options, out, log);
    log.copyfmt(savedFormat);
    return 0;
}

}  // namespace vssim::bench
