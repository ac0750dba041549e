// A scene played as a game: the world (Simulation), the referee, the
// placements and the built-in teams, on one clock of simulated time
// (docs/game.md). Qt-free and deterministic like the engine: the same scene,
// the same inputs at the same steps, the same calls of advanceTo() give
// bit-identical results, and calls cut at game ticks (as vssim match and
// the realtime loop do) change nothing.
//
// Every tick (rules.tick, in whole steps of dt) the referee looks at the
// world and the built-in teams decide their voltages. While the game is
// stopped (Stop, Halt, Finished) every robot is held at 0 V. With the
// referee off and no built-in team a Match is the plain Simulation.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vssim/game/game_state.h"
#include "vssim/game/placement.h"
#include "vssim/world.h"

namespace vssim {

class Match {
public:
    // `seed` varies the game: with a seed other than 0 every robot the
    // referee places is moved by up to kPlacementJitter and turned by up to
    // kHeadingJitter from its spot (splitmix64 from the seed; a placement
    // the jitter would make illegal is used as it is). Seed 0: no jitter.
    static constexpr double kPlacementJitter = 0.005;  // m
    static constexpr double kHeadingJitter = 0.05;     // rad
    explicit Match(const Scene& scene, std::uint64_t seed = 0);

    const Scene& scene() const { return sim_.scene(); }
    const Simulation& simulation() const { return sim_; }
    // Simulation::lendTableCache, for BatchWorld.
    void lendTableCache(ExactTableCache* cache) { sim_.lendTableCache(cache); }
    const GameState& game() const { return game_; }
    const std::vector<Team>& teams() const { return teams_; }
    // Steps of dt per game tick.
    std::int64_t tickSteps() const { return tickSteps_; }
    // Whether ticks matter (a referee or a built-in team): false means
    // advanceTo is exactly Simulation::advanceTo (for a finite world).
    bool ticking() const { return ticking_; }
    TeamControl control(Team team) const { return team == Team::Yellow ? yellow_ : blue_; }
    void setControl(Team team, TeamControl control);

    // Advances to step `target`, with the referee and the built-in teams at
    // every tick boundary on the way (including `target` if it is one).
    // A world whose state is not finite (firstNonFiniteBody) is frozen: it
    // does not advance (stepping NaN on is meaningless, and very slow); a
    // ticking world stops at the first tick after it went non-finite.
    AdvanceReport advanceTo(std::int64_t target);

    // A remote team's voltages for one robot (V): applied now while the game
    // is on, remembered and applied when it goes on again otherwise; ignored
    // for robots of a built-in or idle team.
    void setVoltages(int robot, const Voltages& e);
    // The same with wheel-speed targets (rad/s) for the robot's speed loop
    // (speed_controller.h); a remote team's robots may switch between the two.
    void setWheelSpeeds(int robot, const WheelSpeeds& w);
    void drive(int robot, const DriveCommand& command);
    // Takes a robot off the field or brings it back (Simulation::setOnField).
    void setOnField(int robot, bool onField);
    // A person driving a robot by hand (V): these voltages replace its
    // team's, built-in, remote or idle, while the game is on, and 0 V while
    // it is stopped, like everybody's; nullopt gives the robot back to its
    // team (a remote team's last voltages now, a built-in team's at the next
    // tick).
    void overrideVoltages(int robot, const std::optional<Voltages>& e);
    // The same with wheel-speed targets through the robot's speed loop, or voltages.
    void overrideDrive(int robot, const std::optional<DriveCommand>& command);
    // Moves a body now (a person dragging it, a client placing it).
    void placeRobot(int robot, const RobotState& pose);
    void placeBall(const BallState& ball);

    // A call by hand (the desktop app, a client): the game stops and the
    // referee places the bodies. Refused (false) with the referee off.
    bool call(Call call, Team team, int quadrant);
    // HALT: everything held at 0 V, the clock stopped, until resume().
    void halt();
    // Back to GAME_ON from Halt or Stop (no placement).
    void resume();
    // A team's own placement during Stop (robot index -> pose): applied if
    // it is legal for the current call; otherwise the referee's stays and
    // the reason is returned.
    std::string placeTeam(Team team, const std::vector<std::pair<int, RobotState>>& poses);

private:
    Simulation sim_;
    std::vector<Team> teams_;
    std::vector<std::string> names_;
    GameRules rules_;
    TeamControl yellow_, blue_;
    GameState game_;
    bool ticking_ = false;
    std::int64_t tickSteps_ = 1;
    std::vector<DriveCommand> remote_;               // the remote teams' last commands (V or rad/s)
    std::vector<std::optional<DriveCommand>> override_;  // a person's command per robot (V or rad/s)
    std::vector<Voltages> wanted_;                   // scratch: the built-in teams' voltages
    std::uint64_t random_;                           // splitmix64 state
    bool jitter_;                                    // a seed other than 0 was given

    void tick();           // the referee, then the voltages, at a tick boundary
    void applyVoltages();  // what every robot gets now
    void place(const Placement& placement);
    // The referee's placement for a call, jittered by the seed.
    void placeFor(const RefereeCall& call);
    double uniform();  // in [-1, 1), from the seed
    bool playing() const { return game_.phase == GamePhase::GameOn; }
};

}  // namespace vssim
