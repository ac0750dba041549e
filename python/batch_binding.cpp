#include "batch_binding.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>

#include "io/scene_io.h"
#include "placement_check.h"
#include "py_batch_world.h"
#include "scene_binding.h"

namespace py = pybind11;

namespace vssim::python {

namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// Anything numpy turns into float64 of shape (worlds, robots, 2): [right, left].
DoubleArray perRobot(const BatchWorld& batch, const py::object& values, const char* what) {
    DoubleArray a = DoubleArray::ensure(values);
    if (!a) throw py::type_error(std::string(what) + ": expected an array of numbers of shape (n_worlds, n_robots, 2)");
    if (a.ndim() != 3 || a.shape(0) != batch.size() || a.shape(1) != batch.robots() || a.shape(2) != 2) {
        std::string shape = "(";
        for (py::ssize_t d = 0; d < a.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(a.shape(d));
        shape += a.ndim() == 1 ? ",)" : ")";
        throw std::invalid_argument(std::string(what) + ": expected shape (" + std::to_string(batch.size()) + ", " +
                                    std::to_string(batch.robots()) + ", 2), [right, left] per robot, got " + shape);
    }
    return a;
}

int worldIndex(const BatchWorld& batch, std::int64_t world) {
    if (world < 0 || world >= batch.size())
        throw std::out_of_range("world " + std::to_string(world) + " does not exist: the batch has " +
                                std::to_string(batch.size()) + " worlds");
    return static_cast<int>(world);
}

}  // namespace

void bindBatchWorld(py::module_& m) {
    py::class_<BatchWorld>(m, "BatchWorld", R"(n independent copies of one scene, stepped together in C++ on a pool
of threads (threads=0: every core), each with its own inputs. World i is
bit-identical to vssim.World(scene, seed=0 if seed == 0 else seed + i)
given the same inputs, whatever the thread count. Safe to call from
several Python threads: each call waits for the one running.)")
        .def(py::init([](std::int64_t n, const py::object& scene, int threads, const py::object& seed) {
                 if (n < 1 || n > (1 << 24))
                     throw std::invalid_argument("n: expected 1 to 16777216 worlds, got " + std::to_string(n));
                 const std::uint64_t s = seedArgument(seed);
                 return std::make_unique<BatchWorld>(loadScene(scene), static_cast<int>(n), threads, s);
             }),
             py::arg("n"), py::arg("scene"), py::arg("threads") = 0, py::arg("seed") = 0)
        .def_property_readonly("n_worlds", &BatchWorld::size)
        .def_property_readonly("n_robots", &BatchWorld::robots)
        .def_property_readonly("threads", &BatchWorld::threads)
        .def_property_readonly("dt", &BatchWorld::dt,
                               "The step every world takes, s.")
        .def_property_readonly(
            "step_counts",
            [](const BatchWorld& b) {
                py::array_t<std::int64_t> a(static_cast<py::ssize_t>(b.size()));
                b.copySteps(a.mutable_data());
                return a;
            },
            "(n_worlds,) int64: steps of dt each world has taken (its time is step_counts * dt).")
        .def("scene_json", [](const BatchWorld& b) { return sceneToJson(b.scene()).toStdString(); },
             "The complete scene every world plays, as scene-file JSON, every parameter spelled out.")
        .def(
            "set_voltages",
            [](BatchWorld& b, const py::object& values) {
                const DoubleArray a = perRobot(b, values, "set_voltages");
                b.setVoltagesAll(a.data());
            },
            py::arg("voltages"), "Every robot's armature voltages, V: shape (n_worlds, n_robots, 2), [right, left].")
        .def(
            "set_wheel_speeds",
            [](BatchWorld& b, const py::object& values) {
                const DoubleArray a = perRobot(b, values, "set_wheel_speeds");
                b.setWheelSpeedsAll(a.data());
            },
            py::arg("wheel_speeds"),
            "Every robot's wheel-speed targets, rad/s, through its speed loop: shape (n_worlds, n_robots, 2).")
        .def(
            "step",
            [](BatchWorld& b, double seconds) {
                py::gil_scoped_release release;
                return b.step(seconds);
            },
            py::arg("seconds"),
            "Advances every world by seconds (rounded up to whole steps, and game ticks), in parallel, the GIL "
            "released; returns the steps taken.")
        .def(
            "place_robot",
            [](BatchWorld& b, std::int64_t world, std::int64_t robot, double x, double y, double theta, double v,
               double omega) {
                const int w = worldIndex(b, world);
                if (robot < 0 || robot >= b.robots())
                    throw std::out_of_range("robot " + std::to_string(robot) + " does not exist: the scene has " +
                                            std::to_string(b.robots()) + " robots");
                const RobotState pose{x, y, theta, v, omega};
                checkRobotPlacement(b.scene(), static_cast<int>(robot), pose,
                                    "world " + std::to_string(w) + ", robot " + std::to_string(robot));
                b.placeRobot(w, static_cast<int>(robot), pose);
            },
            py::arg("world"), py::arg("robot"), py::arg("x"), py::arg("y"), py::arg("theta"), py::arg("v") = 0.0,
            py::arg("omega") = 0.0,
            "Moves robot `robot` of world `world` at once: x, y (m), theta (rad), v (m/s), omega (rad/s); wholly "
            "inside the field, or ValueError.")
        .def(
            "place_ball",
            [](BatchWorld& b, std::int64_t world, double x, double y, double vx, double vy) {
                const int w = worldIndex(b, world);
                const BallState ball{x, y, vx, vy};
                checkBallPlacement(b.scene(), ball, "world " + std::to_string(w) + ", the ball");
                b.placeBall(w, ball);
            },
            py::arg("world"), py::arg("x"), py::arg("y"), py::arg("vx") = 0.0, py::arg("vy") = 0.0,
            "Moves the ball of world `world` at once: x, y (m), vx, vy (m/s); inside the field, or ValueError.")
        .def("reset", [](BatchWorld& b, std::int64_t world) { b.reset(worldIndex(b, world)); }, py::arg("world"))
        .def("reset_all", [](BatchWorld& b) {
            py::gil_scoped_release release;
            b.resetAll();
        })
        .def_property_readonly(
            "robots",
            [](const BatchWorld& b) {
                py::array_t<double> a({static_cast<py::ssize_t>(b.size()), static_cast<py::ssize_t>(b.robots()),
                                       static_cast<py::ssize_t>(5)});
                b.copyRobots(a.mutable_data());
                return a;
            },
            "(n_worlds, n_robots, 5): x, y (m), theta (rad), v (m/s), omega (rad/s).")
        .def_property_readonly(
            "wheel_speeds",
            [](const BatchWorld& b) {
                py::array_t<double> a({static_cast<py::ssize_t>(b.size()), static_cast<py::ssize_t>(b.robots()),
                                       static_cast<py::ssize_t>(2)});
                b.copyWheelSpeeds(a.mutable_data());
                return a;
            },
            "(n_worlds, n_robots, 2): wheel speeds, right, left (rad/s).")
        .def_property_readonly(
            "balls",
            [](const BatchWorld& b) {
                py::array_t<double> a({static_cast<py::ssize_t>(b.size()), static_cast<py::ssize_t>(4)});
                b.copyBalls(a.mutable_data());
                return a;
            },
            "(n_worlds, 4): x, y (m), vx, vy (m/s).")
        .def_property_readonly(
            "scores",
            [](const BatchWorld& b) {
                py::array_t<int> a({static_cast<py::ssize_t>(b.size()), static_cast<py::ssize_t>(2)});
                b.copyScores(a.mutable_data());
                return a;
            },
            "(n_worlds, 2): goals of yellow, blue.")
        .def_property_readonly(
            "times",
            [](const BatchWorld& b) {
                py::array_t<double> a(static_cast<py::ssize_t>(b.size()));
                b.copyTimes(a.mutable_data());
                return a;
            },
            "(n_worlds,): simulated time of each world, s.");
}

}  // namespace vssim::python
