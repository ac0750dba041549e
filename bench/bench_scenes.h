// The scenes the benchmarks run. Random choices use std::mt19937 with a fixed
// mapping to doubles, so every machine builds the same scenes.
#pragma once

#include <cstdint>
#include <random>
#include <string>

#include "vssim/scene.h"

namespace vssim::bench {

// Uniform in [lo, hi) from the generator's raw 32-bit output (the standard
// distributions may differ between library implementations).
double uniform(std::mt19937& rng, double lo, double hi);

// Six robots (half with +-10 % parameter spread, left and right apart) far
// from each other and from any wall on a 100 m field, the ball at rest far
// away: no contact can happen in 10 s, so the error measured is the
// integrator's alone. Random voltages in +-7.4 V every `period` seconds.
Scene freeFlightScene(std::uint32_t seed, double duration, double period);

// A scene file; throws std::runtime_error with the file's error message.
Scene loadScene(const std::string& file);

// The shipped 3-vs-3 kick-off scene (resources/scenes/kickoff_3v3.json),
// its commands replaced by random voltages every `period` seconds, as a
// controller would send them.
Scene kickoffWithRandomVoltages(const std::string& sceneFile, std::uint32_t seed, double duration, double period);

// n robots at random, non-overlapping places on a square field whose area
// grows with n at the 3-vs-3 density (1.95 m^2 for 6 robots), the ball
// among them, random voltages every 30 ms.
Scene crowdScene(std::uint32_t seed, int robots, double duration);

// Adds random voltages in +-7.4 V for every robot every `period` s.
void addRandomVoltages(Scene& scene, std::mt19937& rng, double duration, double period);

}  // namespace vssim::bench
