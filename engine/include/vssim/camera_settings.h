// How a scene's overhead camera sees and delivers the world (docs/protocol.md,
// "The camera"; docs/scenes.md, `camera`). Plain data kept with the scene, as
// the game's rules are, so that every way of running one (vssim serve, the
// desktop app, the Python world) shows the same camera; the physics ignores
// it. The camera itself is its own library (camera/).
//
// Three stages, each off in the ideal camera (the default, today's image):
// - image formation, one per scene (every client sees the same image):
//   projection and lens, light and colour, sensor noise, motion blur;
// - delivery, per client (a client's HELLO may override them): latency,
//   jitter and dropped frames;
// - the ground truth's noise, per client: STATE and FIRASim vision positions.
// Every random draw comes from `seed` and the frame number, so lockstep runs
// repeat exactly.
#pragma once

#include <cstdint>

namespace vssim {

enum class CameraProjection {
    Orthographic,  // the ideal top view: u = centre_u + scale x, v = centre_v - scale y
    Pinhole,       // a camera `height` above the field centre looking straight down, with lens distortion
};

struct CameraSettings {
    // --- Image formation (per scene) ---
    CameraProjection projection = CameraProjection::Orthographic;
    double height = 2.0;        // m, the camera's optical centre above the field's centre (pinhole only)
    double focal_length = 0.0;  // px; 0 = the ideal camera's scale (px/m) times height: the floor as wide as today
    // Lens distortion in OpenCV's model (pinhole only; cv::projectPoints' order): radial k1, k2, k3 and
    // tangential p1, p2, on normalised image coordinates.
    double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;
    // Light: brightness falls by `vignetting` (a fraction) from the image centre to its corners, as r²;
    // a linear illumination gradient multiplies it by 1 + gradient_x at the right edge (1 - gradient_x at
    // the left) and 1 + gradient_y at the bottom edge.
    double vignetting = 0.0;
    double gradient_x = 0.0, gradient_y = 0.0;
    // Colour: per-channel gains (a colour cast and overall gain), applied before the noise.
    double gain_b = 1.0, gain_g = 1.0, gain_r = 1.0;
    double noise = 0.0;  // Gaussian sensor noise, standard deviation in grey levels (0..255) per pixel and channel
    // Motion blur: the image averages the scene over the `exposure` before each camera instant, at
    // `blur_samples` evenly spaced instants (0 s: no blur).
    double exposure = 0.0;  // s
    int blur_samples = 8;

    // --- Delivery (per client) ---
    double latency = 0.0;  // s of simulated time between a camera instant and the delivery of its FRAME and STATE
    double jitter = 0.0;   // s: each frame is further delayed by a uniform draw in [0, jitter]
    double drop = 0.0;     // probability that a frame (FRAME and STATE) is never delivered

    // --- Ground-truth noise (per client: STATE, FIRASim vision) ---
    double position_noise = 0.0;  // m, standard deviation of Gaussian noise on x and y (robots and ball)
    double heading_noise = 0.0;   // rad, standard deviation of Gaussian noise on a robot's heading
    double vanish = 0.0;          // probability that a body is missing from a frame's positions

    std::uint64_t seed = 1;  // of every random draw above

    bool operator==(const CameraSettings& o) const {
        return projection == o.projection && height == o.height && focal_length == o.focal_length && k1 == o.k1 &&
               k2 == o.k2 && p1 == o.p1 && p2 == o.p2 && k3 == o.k3 && vignetting == o.vignetting &&
               gradient_x == o.gradient_x && gradient_y == o.gradient_y && gain_b == o.gain_b &&
               gain_g == o.gain_g && gain_r == o.gain_r && noise == o.noise && exposure == o.exposure &&
               blur_samples == o.blur_samples && latency == o.latency && jitter == o.jitter && drop == o.drop &&
               position_noise == o.position_noise && heading_noise == o.heading_noise && vanish == o.vanish &&
               seed == o.seed;
    }
    bool operator!=(const CameraSettings& o) const { return !(*this == o); }
};

// Today's camera: orthographic, flat colours, no noise, no delay.
inline CameraSettings idealCamera() { return CameraSettings{}; }

// Values typical of a VSSS field's camera (docs/protocol.md, "The realistic
// preset", gives where each comes from): a webcam about 2 m above the field
// with a slightly wide lens, uneven indoor light, a 1/100 s exposure, a
// USB webcam's latency, and a vision system's millimetre-scale noise.
inline CameraSettings realisticCamera() {
    CameraSettings c;
    c.projection = CameraProjection::Pinhole;
    c.height = 2.0;
    c.focal_length = 0.0;
    c.k1 = -0.15, c.k2 = 0.03, c.p1 = 0.0005, c.p2 = -0.0005, c.k3 = 0.0;
    c.vignetting = 0.30;
    c.gradient_x = 0.10, c.gradient_y = -0.05;
    c.gain_b = 0.92, c.gain_g = 1.00, c.gain_r = 1.08;
    c.noise = 3.0;
    c.exposure = 0.010;
    c.blur_samples = 6;
    c.latency = 0.050;
    c.jitter = 0.010;
    c.drop = 0.01;
    c.position_noise = 0.002;
    c.heading_noise = 0.02;
    c.vanish = 0.01;
    c.seed = 1;
    return c;
}

}  // namespace vssim
