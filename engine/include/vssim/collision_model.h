// Which collision response the world uses (model.md §6).
#pragma once

namespace vssim {

enum class CollisionModel {
    Paper,    // §6a: sphere-equivalent 1-D elastic exchange (eq. 12), the seed's
    Impulse,  // §6b: energy-consistent impulse with restitution, uses the robot's M
};

}  // namespace vssim
