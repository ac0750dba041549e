// Which bodies certainly cannot touch anything within a horizon: the basis
// of the long-step planner (Simulation::advanceTo, long_step_planner.cpp) and
// of the sub-step choice for Euler and RK4 (stepWorld).
#pragma once

#include <utility>
#include <vector>

#include "vssim/broad_phase.h"
#include "vssim/world_model.h"

namespace vssim {

// Which bodies certainly cannot touch another body or a wall within a
// horizon, from their travel bounds (robotTravelBound for the exact
// integrator; for Euler and RK4 a cruder one, see free_bodies.cpp; the ball's
// straight free flight) and discs that hold each body at any heading.
struct FreeBodies {
    std::vector<char> robots;                // 1: robot i is free for the horizon
    bool ball = false;                       // the ball is free
    bool all = false;                        // every body is free
    std::vector<double> robotTravel;         // farthest any point of robot i can go within the horizon, m
    double ballTravel = 0.0;                 // m
    std::vector<std::pair<int, int>> pairs;  // work buffers
    BroadPhaseScratch broadPhase;
    ModeProgressCache progress;
};
void findFreeBodies(const WorldModel& model, const WorldState& state, double horizon, FreeBodies& out);

// How far robot i's centre can go within `horizon` (s) as the scene's
// integrator computes it, m; infinity when nothing is promised
// (free_bodies.cpp). The modes' progress over the horizon comes from `progress`.
double robotTravelForIntegrator(const WorldModel& model, const WorldState& state, std::size_t i, double horizon,
                                ModeProgressCache& progress);
// How far the ball can go within `horizon` (s) in free flight, m.
double ballTravelForIntegrator(const WorldModel& model, const WorldState& state, double horizon);

}  // namespace vssim
