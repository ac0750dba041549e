// vssim.World: py_world.h for Python, with its inputs and state as numpy
// arrays (docs/python.md).
#include "world_binding.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstring>
#include <stdexcept>

#include "io/scene_io.h"
#include "py_world.h"
#include "scene_binding.h"
#include "scene_source.h"
#include "vssim/game/game_state.h"

namespace py = pybind11;

namespace vssim::python {

namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::unique_ptr<World> makeWorld(const py::object& scene, const py::object& seed) {
    return std::make_unique<World>(loadScene(scene), seedArgument(seed));
}

// Anything numpy turns into float64 with shape (robots, 2): [right, left] per robot.
std::vector<std::pair<double, double>> pairsPerRobot(const World& world, const py::object& values, const char* what) {
    DoubleArray a = DoubleArray::ensure(values);
    if (!a) throw py::type_error(std::string(what) + ": expected an array of numbers of shape (n_robots, 2)");
    const py::ssize_t n = world.robotCount();
    if (a.ndim() != 2 || a.shape(0) != n || a.shape(1) != 2) {
        std::string shape = "(";
        for (py::ssize_t d = 0; d < a.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(a.shape(d));
        shape += a.ndim() == 1 ? ",)" : ")";
        throw std::invalid_argument(std::string(what) + ": expected shape (" + std::to_string(n) +
                                    ", 2), [right, left] per robot, got " + shape);
    }
    std::vector<std::pair<double, double>> out(n);
    auto r = a.unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) out[i] = {r(i, 0), r(i, 1)};
    return out;
}

// A robot index from Python (any 64-bit integer): IndexError for one the
// scene does not have, before it is narrowed to int.
int robotIndex(const World& world, std::int64_t robot) {
    if (robot < 0 || robot >= world.robotCount())
        throw std::out_of_range("robot " + std::to_string(robot) + " does not exist: the scene has " +
                                std::to_string(world.robotCount()) + " robots");
    return static_cast<int>(robot);
}

py::array_t<double> matrix(py::ssize_t rows, py::ssize_t cols) { return py::array_t<double>({rows, cols}); }

py::object teamOrNone(const RefereeCall& call) {
    // Only a kick-off, a penalty kick and a goal kick are for a team (as gameStateJson).
    if (call.call == Call::None || call.call == Call::FreeBall) return py::none();
    return py::str(teamLabel(call.team));
}

py::dict callDict(const RefereeCall& call) {
    py::dict d;
    d["call"] = callName(call.call);
    d["team"] = teamOrNone(call);
    d["quadrant"] = call.quadrant;
    d["half"] = call.half;
    d["clock"] = call.clock;
    d["time"] = call.time;
    d["reason"] = call.reason;
    return d;
}

// The keys and names of the protocol's game object (wire/game_message.cpp, gameStateJson).
py::dict gameDict(const GameState& game, bool referee) {
    py::dict d;
    d["referee"] = referee;
    d["phase"] = gamePhaseName(game.phase);
    d["call"] = callName(game.last.call);
    d["team"] = teamOrNone(game.last);
    d["quadrant"] = game.last.quadrant;
    d["half"] = game.half;
    d["clock"] = game.clock;
    d["stop_left"] = game.stopLeft;
    py::dict goals;
    goals["yellow"] = game.goals[teamIndex(Team::Yellow)];
    goals["blue"] = game.goals[teamIndex(Team::Blue)];
    d["goals"] = goals;
    d["reason"] = game.last.reason;
    d["call_time"] = game.last.time;
    d["call_clock"] = game.last.clock;
    return d;
}

py::array_t<double> robotsArray(const WorldSnapshot& s) {
    const auto n = static_cast<py::ssize_t>(s.robots.size());
    py::array_t<double> a = matrix(n, 5);
    auto w = a.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
        const RobotState& r = s.robots[i];
        w(i, 0) = r.x, w(i, 1) = r.y, w(i, 2) = r.theta, w(i, 3) = r.v, w(i, 4) = r.omega;
    }
    return a;
}

template <typename F>
py::array_t<double> pairsArray(const WorldSnapshot& s, F pick) {
    const auto n = static_cast<py::ssize_t>(s.robots.size());
    py::array_t<double> a = matrix(n, 2);
    auto w = a.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
        const auto [right, left] = pick(s, i);
        w(i, 0) = right, w(i, 1) = left;
    }
    return a;
}

py::array_t<double> wheelSpeedsArray(const WorldSnapshot& s) {
    return pairsArray(s, [](const WorldSnapshot& s, py::ssize_t i) {
        return std::pair{s.outputs[i].wheel_speed_right, s.outputs[i].wheel_speed_left};
    });
}
py::array_t<double> currentsArray(const WorldSnapshot& s) {
    return pairsArray(s, [](const WorldSnapshot& s, py::ssize_t i) {
        return std::pair{s.outputs[i].current_right, s.outputs[i].current_left};
    });
}
py::array_t<double> voltagesArray(const WorldSnapshot& s) {
    return pairsArray(
        s, [](const WorldSnapshot& s, py::ssize_t i) { return std::pair{s.voltages[i].right, s.voltages[i].left}; });
}
py::array_t<double> ballArray(const WorldSnapshot& s) {
    py::array_t<double> a(4);
    auto w = a.mutable_unchecked<1>();
    w(0) = s.ball.x, w(1) = s.ball.y, w(2) = s.ball.vx, w(3) = s.ball.vy;
    return a;
}

}  // namespace

void bindWorld(py::module_& m) {
    py::class_<World>(m, "World", R"doc(
One scene run in-process: the world, the referee and the built-in teams
(vssim's Match), stepped from Python with the GIL released.

World(scene, seed=0): scene is a scene file's path, a built-in scene name
("kickoff_3v3", see builtin_scenes()) or a dict in the scene-file format
(docs/scenes.md). A bad scene raises ValueError with the loader's message,
which names the key. seed other than 0 jitters the referee's placements.
Units: SI (m, s, rad, V, A); the field frame's origin is the field centre.
)doc")
        .def(py::init(&makeWorld), py::arg("scene"), py::arg("seed") = 0)
        .def(
            "set_voltages",
            [](World& w, std::int64_t robot, double right, double left) { w.setVoltages(robotIndex(w, robot), Voltages{right, left}); },
            py::arg("robot"), py::arg("right"), py::arg("left"),
            "One robot's motor voltages, V (clamped to its max_voltage), through the game's rules.")
        .def(
            "set_voltages",
            [](World& w, const py::object& e) {
                std::vector<Voltages> v;
                for (const auto& [right, left] : pairsPerRobot(w, e, "voltages")) v.push_back({right, left});
                w.setVoltages(v);
            },
            py::arg("voltages"),
            "Every robot's motor voltages: shape (n_robots, 2), [right, left] V. A remote team's robots take them "
            "while the game is on (0 V while it is stopped); a built-in or idle team's robots ignore them.")
        .def(
            "set_wheel_speeds",
            [](World& w, std::int64_t robot, double right, double left) { w.setWheelSpeeds(robotIndex(w, robot), WheelSpeeds{right, left}); },
            py::arg("robot"), py::arg("right"), py::arg("left"),
            "One robot's wheel-speed targets, rad/s, for its on-board speed loop.")
        .def(
            "set_wheel_speeds",
            [](World& w, const py::object& speeds) {
                std::vector<WheelSpeeds> v;
                for (const auto& [right, left] : pairsPerRobot(w, speeds, "wheel speeds")) v.push_back({right, left});
                w.setWheelSpeeds(v);
            },
            py::arg("wheel_speeds"),
            "Every robot's wheel-speed targets: shape (n_robots, 2), [right, left] rad/s, through the speed loops.")
        .def(
            "step",
            [](World& w, double seconds) {
                py::gil_scoped_release release;
                return w.step(seconds);
            },
            py::arg("seconds"),
            "Advances by seconds (rounded up to whole steps of dt, at least one) and returns the new time, s. "
            "The GIL is released meanwhile.")
        .def(
            "place_robot",
            [](World& w, std::int64_t robot, double x, double y, double theta, double v, double omega) {
                w.placeRobot(robotIndex(w, robot), RobotState{x, y, theta, v, omega});
            },
            py::arg("robot"), py::arg("x"), py::arg("y"), py::arg("theta"), py::arg("v") = 0.0,
            py::arg("omega") = 0.0, "Moves a robot (m, m, rad; m/s, rad/s); ValueError unless wholly inside the field.")
        .def(
            "place_ball", [](World& w, double x, double y, double vx, double vy) { w.placeBall(BallState{x, y, vx, vy}); },
            py::arg("x"), py::arg("y"), py::arg("vx") = 0.0, py::arg("vy") = 0.0,
            "Moves the ball (m; m/s); ValueError unless wholly inside the field.")
        .def("reset", &World::reset, "Back to the scene's start.")
        .def("close", &World::close, "Frees the world; any later use raises RuntimeError.")
        .def_property_readonly("closed", &World::closed)
        .def("__enter__", [](py::object self) { return self; })
        .def("__exit__", [](World& w, py::args) { w.close(); })
        .def(
            "camera_image",
            [](const World& w) {
                const cv::Mat frame = w.cameraImage();
                py::array_t<std::uint8_t> a({static_cast<py::ssize_t>(frame.rows), static_cast<py::ssize_t>(frame.cols),
                                             static_cast<py::ssize_t>(3)});
                for (int r = 0; r < frame.rows; ++r)
                    std::memcpy(a.mutable_data(r, 0, 0), frame.ptr(r), static_cast<std::size_t>(frame.cols) * 3);
                return a;
            },
            "The synthetic overhead camera's image of the current state: (H, W, 3) uint8, channels in BGR order "
            "(as OpenCV's cv2 expects; [..., ::-1] gives RGB).")
        // The scene (constant).
        .def_property_readonly("n_robots", &World::robotCount)
        .def_property_readonly("dt", &World::dt, "The step, s.")
        .def_property_readonly("seed", &World::seed)
        .def_property_readonly("robot_names",
                               [](const World& w) {
                                   std::vector<std::string> names;
                                   for (const RobotSpec& r : w.scene().robots) names.push_back(r.name);
                                   return names;
                               })
        .def_property_readonly("robot_teams",
                               [](const World& w) {
                                   std::vector<std::string> teams;
                                   for (const RobotSpec& r : w.scene().robots) teams.push_back(teamLabel(r.team));
                                   return teams;
                               })
        .def("scene_json", [](const World& w) { return sceneToJson(w.scene()).toStdString(); },
             "The complete scene as scene-file JSON, every parameter spelled out.")
        // The state, copied out.
        .def_property_readonly("robots", [](const World& w) { return robotsArray(w.snapshot()); },
                               "(n, 5): x, y (m), theta (rad), v (m/s), omega (rad/s) per robot.")
        .def_property_readonly("wheel_speeds", [](const World& w) { return wheelSpeedsArray(w.snapshot()); },
                               "(n, 2): right, left wheel speeds, rad/s.")
        .def_property_readonly("currents", [](const World& w) { return currentsArray(w.snapshot()); },
                               "(n, 2): right, left armature currents, A.")
        .def_property_readonly("voltages", [](const World& w) { return voltagesArray(w.snapshot()); },
                               "(n, 2): right, left voltages applied now (clamped), V.")
        .def_property_readonly("on_field",
                               [](const World& w) {
                                   const WorldSnapshot s = w.snapshot();
                                   std::vector<bool> on(s.onField.begin(), s.onField.end());
                                   return on;
                               })
        .def_property_readonly("ball", [](const World& w) { return ballArray(w.snapshot()); },
                               "(4,): x, y (m), vx, vy (m/s).")
        .def_property_readonly("time", [](const World& w) { return w.snapshot().time; }, "Simulated time, s.")
        .def_property_readonly("step_count", [](const World& w) { return w.snapshot().step; }, "Steps of dt taken.")
        .def(
            "state",
            [](const World& w) {
                const WorldSnapshot s = w.snapshot();
                py::dict d;
                d["time"] = s.time;
                d["step_count"] = s.step;
                d["robots"] = robotsArray(s);
                d["wheel_speeds"] = wheelSpeedsArray(s);
                d["currents"] = currentsArray(s);
                d["voltages"] = voltagesArray(s);
                d["ball"] = ballArray(s);
                return d;
            },
            "Everything above at one instant, as a dict of the same names.")
        // The game.
        .def_property_readonly(
            "score",
            [](const World& w) {
                const GameState g = w.snapshot().game;
                return py::make_tuple(g.goals[teamIndex(Team::Yellow)], g.goals[teamIndex(Team::Blue)]);
            },
            "(yellow, blue) goals.")
        .def_property_readonly("phase", [](const World& w) { return std::string(gamePhaseName(w.snapshot().game.phase)); },
                               "\"game_on\", \"stop\", \"halt\" or \"finished\".")
        .def_property_readonly("half", [](const World& w) { return w.snapshot().game.half; })
        .def_property_readonly("last_call", [](const World& w) { return callDict(w.snapshot().game.last); },
                               "The call being played (or the last one): call, team, quadrant, half, clock, time, reason.")
        .def_property_readonly(
            "calls",
            [](const World& w) {
                py::list calls;
                for (const RefereeCall& c : w.snapshot().game.calls) calls.append(callDict(c));
                return calls;
            },
            "Every call of the match so far (kick-offs, free balls, penalties, goal kicks), in order.")
        .def_property_readonly(
            "game", [](const World& w) { return gameDict(w.snapshot().game, w.scene().game.rules.referee); },
            "The game as the protocol's STATE `game` object (docs/protocol.md), plus `referee`.");

    m.def("builtin_scenes", [] {
        std::vector<std::string> names;
        for (const QString& name : builtinSceneNames()) names.push_back(name.toStdString());
        return names;
    }, "The names of the built-in example scenes.");
}

}  // namespace vssim::python
