// A scene's game: the rules an automatic referee applies and who controls
// each team (shared vsss-game.md, "Rules"; docs/scenes.md, "game"). Plain
// data, kept with the scene so that every way of running one (vssim run,
// serve, match, the desktop app) plays the same game; the physics ignores it.
// The referee and the built-in team are in the game library (game/).
#pragma once

namespace vssim {

enum class Team { Yellow, Blue };

// Who drives a team's robots.
enum class TeamControl {
    Idle,     // nobody: 0 V (the robots stand still unless pushed)
    Builtin,  // vssim's sparring team (game/sparring_team.h)
    Remote,   // a client over the network (TCP protocol), or a person at the keyboard or gamepad
};

struct GameRules {
    bool referee = false;              // off: no score, no clock, no fouls (physics scenes)
    int halves = 2;                    // halves in a match
    double half_duration = 300.0;      // game time per half, s (the clock stops while the game is stopped)
    double stop_duration = 4.0;        // STOP -> GAME_ON after a call, s: the teams' time to place their robots
    double stuck_ball_speed = 0.10;    // below this the ball counts as stuck, m/s
    double stuck_ball_time = 5.0;      // stuck this long -> free ball (or a penalty in a goal area), s
    double crowded_area_time = 3.0;    // two defenders / two attackers in a goal area this long -> foul, s
    double free_ball_distance = 0.20;  // the two robots at a free ball stand this far from it along x, m
    double tick = 0.01;                // the referee's and the built-in team's period, s (whole steps of dt)
    // The team that defends the goal at x < 0 (the left end, seen from above
    // with x to the right) and attacks the one at x > 0, for the whole match;
    // the other team the other way round. vssim's own default is yellow;
    // FIRASim's layout (and so `--firasim`'s default) is blue.
    Team left_team = Team::Yellow;
};

struct GameSettings {
    GameRules rules;
    TeamControl yellow = TeamControl::Remote;
    TeamControl blue = TeamControl::Remote;
};

}  // namespace vssim
