// The colours of the synthetic camera image, in OpenCV's BGR byte order
// (blue, green, red; 0..255). Part of the image protocol: vision clients
// threshold on these values.
#pragma once

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>

#include "vssim/scene.h"

namespace vssim {

struct Bgr {
    std::uint8_t b = 0, g = 0, r = 0;
};

constexpr Bgr kFloorColour{20, 20, 20};        // the floor inside the walls
constexpr Bgr kOutsideColour{70, 70, 70};      // everything outside the walls
constexpr Bgr kWallColour{200, 200, 200};      // the wall lines (camera_layout.h)
constexpr Bgr kMarkingColour{255, 255, 255};   // centre line and centre circle
constexpr Bgr kRobotBodyColour{0, 0, 0};       // the robot's top, around its patches
constexpr Bgr kYellowTeamColour{0, 255, 255};  // team patch of Team::Yellow
constexpr Bgr kBlueTeamColour{255, 0, 0};      // team patch of Team::Blue
constexpr Bgr kBallColour{0, 128, 255};        // orange

// Identity patch colour by the robot's index among the robots of its own
// team, in scene order; index 6 and up start again at the top.
constexpr std::array<Bgr, 6> kIdentityColours{{
    {0, 0, 255},      // 0 red
    {0, 255, 0},      // 1 green
    {255, 0, 255},    // 2 magenta
    {255, 255, 0},    // 3 cyan
    {255, 255, 255},  // 4 white
    {128, 0, 128},    // 5 purple
}};

constexpr Bgr teamColour(Team team) { return team == Team::Yellow ? kYellowTeamColour : kBlueTeamColour; }

constexpr Bgr identityColour(int indexInTeam) {
    return kIdentityColours[static_cast<std::size_t>(indexInTeam) % kIdentityColours.size()];
}

inline cv::Scalar toScalar(Bgr c) { return cv::Scalar(c.b, c.g, c.r); }
inline cv::Vec3b toVec3b(Bgr c) { return cv::Vec3b(c.b, c.g, c.r); }

}  // namespace vssim
