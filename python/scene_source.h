// Where a Python World's scene comes from: a scene file, the name of a
// built-in scene ("kickoff_3v3"), or scene-file JSON (a dict, dumped by
// Python's json module). Errors are the scene loader's messages, which name
// the file and the key.
#pragma once

#include <optional>
#include <string>

#include "vssim/scene.h"

namespace vssim::python {

// A path or a built-in name (resolveScenePath), then loadSceneFile.
std::optional<Scene> sceneFromArgument(const std::string& argument, std::string* error);

// Scene-file JSON (docs/scenes.md), as parseScene reads it.
std::optional<Scene> sceneFromJson(const std::string& json, std::string* error);

}  // namespace vssim::python
