// The checks on a body placed from Python (World.place_robot,
// BatchWorld.place_robot, ...), the same as a TCP client's PLACE_ROBOT /
// PLACE_BALL: finite, within the scene files' speed limits, wholly inside the
// field (inside a goal is inside).
#pragma once

#include <string>

#include "vssim/scene.h"

namespace vssim::python {

// Throw std::invalid_argument with a message starting with `where` ("robot 2",
// "world 5, robot 2", "the ball", "world 5, the ball").
void checkRobotPlacement(const Scene& scene, int robot, const RobotState& pose, const std::string& where);
void checkBallPlacement(const Scene& scene, const BallState& ball, const std::string& where);

}  // namespace vssim::python
