// The ball (model.md §3, eq. 9): a disc with linear viscous damping.
#pragma once

namespace vssim {

struct BallParams {
    double mass = 0.046;      // m_b, kg (golf ball)
    double radius = 0.02135;  // r_b, m
    double friction = 0.02;   // beta_b, N s/m
};

// Field frame. The speed v_b = |(vx, vy)| and heading theta_b = atan2(vy, vx)
// of eq. 9 are derived from the velocity vector.
struct BallState {
    double x = 0.0;   // centre, m
    double y = 0.0;   // m
    double vx = 0.0;  // m/s
    double vy = 0.0;  // m/s
};

}  // namespace vssim
