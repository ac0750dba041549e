#include "vssim/field.h"

namespace vssim {

Field makeRectangularField(double length, double width) {
    Field field;
    field.length = length;
    field.width = width;
    const double hx = 0.5 * length;
    const double hy = 0.5 * width;
    using V = Eigen::Vector2d;
    field.walls = {
        {V(-hx, -hy), V(hx, -hy), V(0.0, 1.0)},   // bottom
        {V(hx, -hy), V(hx, hy), V(-1.0, 0.0)},    // right
        {V(hx, hy), V(-hx, hy), V(0.0, -1.0)},    // top
        {V(-hx, hy), V(-hx, -hy), V(1.0, 0.0)},   // left
    };
    return field;
}

}  // namespace vssim
