#include "bench_scenes.h"

#include <QFile>
#include <cmath>
#include <stdexcept>

#include "io/scene_io.h"

namespace vssim::bench {

double uniform(std::mt19937& rng, double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng()) / 4294967296.0);
}

void addRandomVoltages(Scene& scene, std::mt19937& rng, double duration, double period) {
    scene.commands.clear();
    for (int k = 0; k * period < duration - 1e-12; ++k)
        for (int i = 0; i < static_cast<int>(scene.robots.size()); ++i)
            scene.commands.push_back({k * period, i, {uniform(rng, -7.4, 7.4), uniform(rng, -7.4, 7.4)}});
}

Scene freeFlightScene(std::uint32_t seed, double duration, double period) {
    std::mt19937 rng(seed);
    Scene scene;
    scene.field = makeRectangularField(100.0, 100.0);
    scene.ball.x = 45.0;
    scene.ball.y = 45.0;
    for (int i = 0; i < 6; ++i) {
        RobotSpec r;
        r.name = "r" + std::to_string(i);
        r.initial.x = -25.0 + 10.0 * i;
        r.initial.y = (i % 2 ? 15.0 : -15.0);
        r.initial.theta = uniform(rng, -M_PI, M_PI);
        if (i % 2) {  // a real robot: its sides never match
            auto spread = [&rng](double value) { return value * uniform(rng, 0.9, 1.1); };
            r.params.mass = spread(r.params.mass);
            r.params.inertia = spread(r.params.inertia);
            r.params.wheel_base = spread(r.params.wheel_base);
            for (MotorParams* m : {&r.params.right, &r.params.left}) {
                m->wheel_radius = spread(m->wheel_radius);
                m->resistance = spread(m->resistance);
                m->k = spread(m->k);
                m->rotor_inertia = spread(m->rotor_inertia);
            }
        }
        scene.robots.push_back(r);
    }
    addRandomVoltages(scene, rng, duration, period);
    return scene;
}

Scene loadScene(const std::string& file) {
    QString error;
    std::optional<Scene> scene = loadSceneFile(QString::fromStdString(file), &error);
    if (!scene) throw std::runtime_error(error.toStdString());
    return *scene;
}

Scene kickoffWithRandomVoltages(const std::string& sceneFile, std::uint32_t seed, double duration, double period) {
    Scene scene = loadScene(sceneFile);
    std::mt19937 rng(seed);
    addRandomVoltages(scene, rng, duration, period);
    return scene;
}

Scene crowdScene(std::uint32_t seed, int robots, double duration) {
    std::mt19937 rng(seed);
    const double side = std::sqrt(1.95 * robots / 6.0);  // m
    Scene scene;
    scene.field = makeRectangularField(side, side);
    const double reach = 0.5 * side - 0.06;
    while (static_cast<int>(scene.robots.size()) < robots) {
        RobotSpec r;
        r.initial.x = uniform(rng, -reach, reach);
        r.initial.y = uniform(rng, -reach, reach);
        r.initial.theta = uniform(rng, -M_PI, M_PI);
        bool free = std::hypot(r.initial.x, r.initial.y) > 0.08;  // the ball sits at the centre
        for (const RobotSpec& o : scene.robots)
            free = free && std::hypot(r.initial.x - o.initial.x, r.initial.y - o.initial.y) > 0.11;
        if (!free) continue;
        r.name = "r" + std::to_string(scene.robots.size());
        scene.robots.push_back(r);
    }
    addRandomVoltages(scene, rng, duration, 0.03);
    return scene;
}

}  // namespace vssim::bench
