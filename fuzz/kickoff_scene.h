// The scene the fuzz targets read their inputs against: the built-in 3-vs-3
// kick-off, loaded once (a target aborts if it cannot be: the harness itself
// is broken then, not the reader under test).
#pragma once

#include <QString>
#include <cstdlib>
#include <optional>

#include "io/scene_io.h"

namespace vssim::fuzz {

inline const Scene& kickoffScene() {
    static const Scene scene = [] {
        QString error;
        std::optional<Scene> s = loadSceneFile(QStringLiteral(":/scenes/kickoff_3v3.json"), &error);
        if (!s) std::abort();
        return *s;
    }();
    return scene;
}

}  // namespace vssim::fuzz
