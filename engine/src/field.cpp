#include "vssim/field.h"

#include <cmath>

#include "vssim/geometry.h"

namespace vssim {

Field makeRectangularField(double length, double width) {
    Field field;
    field.length = length;
    field.width = width;
    const double hx = 0.5 * length;
    const double hy = 0.5 * width;
    using V = Eigen::Vector2d;
    field.walls = {
        {V(-hx, -hy), V(hx, -hy), V(0.0, 1.0)},  // bottom
        {V(hx, -hy), V(hx, hy), V(-1.0, 0.0)},   // right
        {V(hx, hy), V(-hx, hy), V(0.0, -1.0)},   // top
        {V(-hx, hy), V(-hx, -hy), V(1.0, 0.0)},  // left
    };
    return field;
}

static bool centreWithin(const Field& field, double halfX, double halfY, double x, double y) {
    return std::abs(x) <= 0.5 * field.length - halfX && std::abs(y) <= 0.5 * field.width - halfY;
}

bool robotInsideField(const Field& field, double side, double x, double y, double theta) {
    const double reach = robotHalfExtent(side, theta);
    return centreWithin(field, reach, reach, x, y);
}

bool discInsideField(const Field& field, double r, double x, double y) { return centreWithin(field, r, r, x, y); }

}  // namespace vssim
