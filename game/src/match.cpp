#include "vssim/game/match.h"

#include <algorithm>
#include <cmath>

#include "vssim/game/referee.h"
#include "vssim/game/sparring_team.h"
#include "vssim/split_mix.h"

namespace vssim {

Match::Match(const Scene& scene, std::uint64_t seed)
    : sim_(scene),
      teams_(robotTeams(scene)),
      rules_(scene.game.rules),
      yellow_(scene.game.yellow),
      blue_(scene.game.blue),
      game_(initialGameState(scene.game.rules, scene.robots.size())),
      random_(seed),
      jitter_(seed != 0) {
    for (const RobotSpec& r : scene.robots) names_.push_back(r.name);
    remote_.assign(scene.robots.size(), {});
    override_.assign(scene.robots.size(), std::nullopt);
    tickSteps_ = std::max<std::int64_t>(1, std::llround(rules_.tick / sim_.dt()));
    ticking_ = rules_.referee || yellow_ != TeamControl::Remote || blue_ != TeamControl::Remote;
    if (rules_.referee) placeFor(game_.last);
    if (ticking_) applyVoltages();
}

void Match::setControl(Team team, TeamControl control) {
    (team == Team::Yellow ? yellow_ : blue_) = control;
    ticking_ = rules_.referee || yellow_ != TeamControl::Remote || blue_ != TeamControl::Remote;
    applyVoltages();
}

AdvanceReport Match::advanceTo(std::int64_t target) {
    if (firstNonFiniteBody(sim_.state()) >= 0) return {};  // frozen until reset
    if (!ticking_) return sim_.advanceTo(target);
    AdvanceReport total;
    while (sim_.state().step < target) {
        const std::int64_t step = sim_.state().step;
        const std::int64_t nextTick = (step / tickSteps_ + 1) * tickSteps_;
        const AdvanceReport r = sim_.advanceTo(std::min(target, nextTick));
        total.steps += r.steps;
        total.stepCalls += r.stepCalls;
        total.longSteps += r.longSteps;
        total.replans += r.replans;
        total.contacts += r.contacts;
        if (sim_.state().step % tickSteps_ == 0) tick();
        if (firstNonFiniteBody(sim_.state()) >= 0) break;  // the caller checks and stops
    }
    return total;
}

void Match::tick() {
    const double elapsed = static_cast<double>(tickSteps_) * sim_.dt();
    if (const auto call = refereeTick(rules_, sim_.model(), sim_.state(), teams_, elapsed, game_)) placeFor(*call);
    applyVoltages();
}

double Match::uniform() {
    // splitmix64 (vssim/split_mix.h) over a counter stepped by its constant: a fixed sequence per seed.
    const std::uint64_t z = splitMix64(random_);
    random_ += 0x9e3779b97f4a7c15ull;
    return static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;
}

void Match::placeFor(const RefereeCall& call) {
    const Placement spots = automaticPlacement(sim_.model(), sim_.state(), teams_, game_, rules_, call);
    if (!jitter_) {
        place(spots);
        return;
    }
    Placement jittered = spots;
    jittered.offField = sim_.state().offField;
    for (RobotState& r : jittered.robots) {
        r.x += kPlacementJitter * uniform();
        r.y += kPlacementJitter * uniform();
        r.theta += kHeadingJitter * uniform();
    }
    for (Team team : {Team::Yellow, Team::Blue})
        if (!checkTeamPlacement(sim_.model(), teams_, names_, rules_, call, team, jittered).empty()) {
            place(spots);
            return;
        }
    place(jittered);
}

void Match::applyVoltages() {
    const std::size_t n = teams_.size();
    wanted_.assign(n, {});
    if (playing()) {
        for (Team team : {Team::Yellow, Team::Blue}) {
            const TeamControl c = control(team);
            if (c == TeamControl::Builtin) sparringVoltages(sim_.model(), sim_.state(), teams_, rules_, game_, team, wanted_);
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        const int robot = static_cast<int>(i);
        if (override_[i] && playing())
            sim_.drive(robot, *override_[i]);
        else if (override_[i])
            sim_.setVoltages(robot, {});
        else if (playing() && control(teams_[i]) == TeamControl::Remote)
            sim_.drive(robot, remote_[i]);  // a speed loop already on keeps its state
        else
            sim_.setVoltages(robot, wanted_[i]);
    }
}

void Match::overrideVoltages(int robot, const std::optional<Voltages>& e) {
    overrideDrive(robot, e ? std::optional(DriveCommand::ofVoltages(*e)) : std::nullopt);
}

void Match::overrideDrive(int robot, const std::optional<DriveCommand>& e) {
    if (robot < 0 || robot >= static_cast<int>(teams_.size())) return;
    if (!e && !override_[robot]) return;  // not overridden: nothing changes
    override_[robot] = e;
    DriveCommand now;  // 0 V: stopped, or a built-in or idle team's until its next tick
    if (e)
        now = !ticking_ || playing() ? *e : DriveCommand{};
    else if (!ticking_ || (playing() && control(teams_[robot]) == TeamControl::Remote))
        now = remote_[robot];
    sim_.drive(robot, now);
}

void Match::setVoltages(int robot, const Voltages& e) { drive(robot, DriveCommand::ofVoltages(e)); }

void Match::setWheelSpeeds(int robot, const WheelSpeeds& w) { drive(robot, DriveCommand::ofWheelSpeeds(w)); }

void Match::drive(int robot, const DriveCommand& command) {
    if (robot < 0 || robot >= static_cast<int>(teams_.size())) return;
    remote_[robot] = command;
    if (override_[robot]) return;  // a person has it
    if (!ticking_ || (playing() && control(teams_[robot]) == TeamControl::Remote)) sim_.drive(robot, command);
}

void Match::setOnField(int robot, bool onField) {
    if (robot < 0 || robot >= static_cast<int>(teams_.size())) return;
    if (onField == sim_.onField(robot)) return;
    sim_.setOnField(robot, onField);
    if (!onField) return;
    // Back: what drives it now (a built-in team's robot waits for the next tick at 0 V).
    if (override_[robot])
        sim_.drive(robot, !ticking_ || playing() ? *override_[robot] : DriveCommand{});
    else if (!ticking_ || (playing() && control(teams_[robot]) == TeamControl::Remote))
        sim_.drive(robot, remote_[robot]);
}

void Match::placeRobot(int robot, const RobotState& pose) { sim_.placeRobot(robot, pose); }
void Match::placeBall(const BallState& ball) { sim_.placeBall(ball); }

void Match::place(const Placement& placement) {
    for (std::size_t i = 0; i < placement.robots.size(); ++i) sim_.placeRobot(static_cast<int>(i), placement.robots[i]);
    sim_.placeBall(placement.ball);
}

bool Match::call(Call call, Team team, int quadrant) {
    if (!rules_.referee || call == Call::None) return false;
    if (call == Call::FreeBall && (quadrant < 1 || quadrant > 4)) return false;
    const RefereeCall c =
        makeCall(rules_, game_, call, team, call == Call::FreeBall ? quadrant : 0, sim_.state().time, "by hand");
    placeFor(c);
    applyVoltages();
    return true;
}

void Match::halt() {
    if (!rules_.referee || game_.phase == GamePhase::Finished) return;
    game_.phase = GamePhase::Halt;
    applyVoltages();
}

void Match::resume() {
    if (!rules_.referee || game_.phase == GamePhase::Finished) return;
    game_.phase = GamePhase::GameOn;
    game_.stopLeft = 0.0;
    applyVoltages();
}

std::string Match::placeTeam(Team team, const std::vector<std::pair<int, RobotState>>& poses) {
    if (!rules_.referee) return "the referee is off";
    if (game_.phase != GamePhase::Stop) return "placements are taken only while the game is stopped";
    Placement proposed;
    proposed.robots = sim_.state().robots;
    proposed.ball = sim_.state().ball;
    proposed.offField = sim_.state().offField;
    for (const auto& [robot, pose] : poses) {
        if (robot < 0 || robot >= static_cast<int>(teams_.size()))
            return "robot " + std::to_string(robot) + " does not exist";
        if (teams_[robot] != team)
            return names_[robot] + " (robot " + std::to_string(robot) + ") is not a " + teamLabel(team) + " robot";
        RobotState at = pose;
        at.v = 0.0, at.omega = 0.0;
        proposed.robots[robot] = at;
    }
    const std::string why = checkTeamPlacement(sim_.model(), teams_, names_, rules_, game_.last, team, proposed);
    if (!why.empty()) return why;
    for (const auto& [robot, pose] : poses) sim_.placeRobot(robot, proposed.robots[robot]);
    return {};
}

}  // namespace vssim
