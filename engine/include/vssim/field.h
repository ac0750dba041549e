// The playing field: a set of one-sided wall segments (model.md §4).
//
// Walls are segments, not four numbers, so that the official IEEE VSSS field
// (goals, corner triangles) can be described with the same model later. Each
// wall has an inward normal: the side the bodies are on. A body is "in the
// field" when it lies on the inner side of every wall within the field's
// bounding box.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace vssim {

struct Wall {
    Eigen::Vector2d a;       // first end, m (field frame)
    Eigen::Vector2d b;       // second end, m
    Eigen::Vector2d normal;  // unit normal pointing into the field
};

struct Field {
    double length = 1.50;     // extent along x, m
    double width = 1.30;      // extent along y, m
    std::vector<Wall> walls;  // one-sided wall segments
};

// The seed's field: a closed rectangle length x width centred on the origin,
// with four walls whose normals point inwards.
Field makeRectangularField(double length, double width);

// Whether a square robot of side `side` (m) centred at (x, y) with heading
// theta (rad), or a disc of radius r, lies inside the field's
// length x width rectangle (touching a wall counts as inside). False for NaN.
bool robotInsideField(const Field& field, double side, double x, double y, double theta);
bool discInsideField(const Field& field, double r, double x, double y);

}  // namespace vssim
