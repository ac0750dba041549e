#include "vssim/game/pitch.h"

#include <cmath>

namespace vssim {

int goalScoredIn(const Field& field, const BallState& ball, double radius) {
    const FieldDimensions& d = field.dimensions;
    if (!(d.goal_width > 0.0)) return 0;
    if (!(std::abs(ball.y) < 0.5 * d.goal_width)) return 0;
    if (ball.x > 0.5 * d.length + radius) return 1;
    if (ball.x < -0.5 * d.length - radius) return -1;
    return 0;
}

bool inGoalArea(const Field& field, int side, const Eigen::Vector2d& p) {
    const FieldDimensions& d = field.dimensions;
    if (!(d.goal_area_depth > 0.0 && d.goal_area_width > 0.0)) return false;
    const double hx = 0.5 * d.length;
    const double front = hx - d.goal_area_depth, back = hx + d.goal_depth;  // |x| range
    const double x = side * p.x();
    return x >= front && x <= back && std::abs(p.y()) <= 0.5 * d.goal_area_width;
}

Eigen::Vector2d goalCentre(const Field& field, int side) { return {side * 0.5 * field.dimensions.length, 0.0}; }

Eigen::Vector2d penaltyMark(const Field& field, int side) {
    return {side * (0.5 * field.dimensions.length - field.dimensions.penalty_mark), 0.0};
}

Eigen::Vector2d freeBallMark(const Field& field, int quadrant) {
    const double sx = (quadrant == 1 || quadrant == 4) ? 1.0 : -1.0;
    const double sy = (quadrant == 1 || quadrant == 2) ? 1.0 : -1.0;
    const FieldDimensions& d = field.dimensions;
    return {sx * (0.5 * d.length - d.free_ball_x), sy * d.free_ball_y};
}

}  // namespace vssim
