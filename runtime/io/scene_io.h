// Scene files (JSON, format version 1; docs/scenes.md): reading with errors
// that name the key path, and writing back with every value explicit.
#pragma once

#include <QByteArray>
#include <QJsonObject>
#include <QString>
#include <QStringList>
#include <optional>

#include "io/scene_limits.h"
#include "vssim/scene.h"

namespace vssim {

// Parses a scene. On failure returns nullopt and sets *error to a message
// that names where, e.g. "robots[2].params.right.resistance: expected a number".
std::optional<Scene> parseScene(const QByteArray& json, QString* error);

// Reads and parses a file (or a Qt resource path); errors start with the path.
std::optional<Scene> loadSceneFile(const QString& path, QString* error);

// The complete scene as JSON: every parameter of every robot spelled out,
// numbers in their shortest round-trip form, so parseScene(sceneToJson(s))
// reproduces s exactly.
QByteArray sceneToJson(const Scene& scene);

// A field as a scene file's `field` object (its type and every dimension it
// takes), as sceneToJson writes it and WELCOME carries it; and back, with the
// scene reader's checks and messages (a `field` without `type` is a box).
QJsonObject fieldToJson(const Field& field);
std::optional<Field> fieldFromJson(const QJsonObject& field, QString* error);

// The names used in scene files and on the command line.
QString integratorName(Integrator integrator);
std::optional<Integrator> integratorFromName(const QString& name);
QString collisionModelName(CollisionModel model);
std::optional<CollisionModel> collisionModelFromName(const QString& name);
QString teamName(Team team);  // "yellow", "blue"
std::optional<Team> teamFromName(const QString& name);
QString teamControlName(TeamControl control);  // "builtin", "remote", "idle"
std::optional<TeamControl> teamControlFromName(const QString& name);
QString fieldTypeName(FieldType type);
std::optional<FieldType> fieldTypeFromName(const QString& name);

// The keys of a scene file's `field` object besides `type`, in the order they
// are written, with the dimension each one sets (docs/scenes.md, `field`).
struct FieldDimensionKey {
    const char* key;                     // "goal_width", ...
    double FieldDimensions::*dimension;  // &FieldDimensions::goal_width, ...
    AllowedRange range;                  // what the reader accepts on its own (scene_limits.h)
    bool box;                            // whether a box (no goals, no corners) takes it
};
extern const FieldDimensionKey kFieldDimensionKeys[11];

// The box a scene file with neither `field.type` nor `field.centre_radius`
// describes: length x width, the centre circle 0.20 m when it fits in the
// box (its radius under half the shorter side), none otherwise.
FieldDimensions boxDimensions(double length, double width);

// A field's floor area inside its walls (the goals included, the corner
// triangles left out), m².
double floorArea(const Field& field);

// Resolves a scene argument: an existing file, or the name of a built-in
// example scene ("kickoff_3v3" or "kickoff_3v3.json", compiled in as a Qt
// resource). Returns an empty string when neither exists.
QString resolveScenePath(const QString& argument);

// Why resolveScenePath(argument) found nothing, as "ARGUMENT: what it is":
// a directory, a FIFO, a device or a socket is named as such (a scene is read
// from a regular file), anything else is "no such file or built-in scene"
// with the built-in names.
QString sceneNotFoundMessage(const QString& argument);

// The game section's checks, shared with the command line (vssim serve
// --referee): whether a field has goals (a referee needs them), and why a
// game tick does not suit a step dt (it must be a whole number of steps,
// at least one), or an empty string.
bool fieldHasGoals(const Field& field);
QString refereeFieldProblem();
QString gameTickProblem(double tick, double dt);
// The game rules as a scene file's `game` object writes them (without the
// teams' controls), as WELCOME carries them.
QJsonObject gameRulesToJson(const GameRules& rules);

// The camera as a scene file's `camera` object writes it: every key, no
// preset (docs/scenes.md, `camera`); WELCOME carries it too.
QJsonObject cameraSettingsToJson(const CameraSettings& camera);
// A `camera` object (a scene file's, or a HELLO's) applied over `base`: its
// `preset` first ("ideal" or "realistic" replaces everything), then each key,
// with the scene reader's checks; errors name the key under `path`
// ("camera.noise: ...").
std::optional<CameraSettings> cameraSettingsFromJson(const QJsonObject& camera, const CameraSettings& base,
                                                     const QString& path, QString* error);
// "ideal" or "realistic" when the settings are exactly that preset, "custom" otherwise.
QString cameraPresetName(const CameraSettings& camera);
QString cameraProjectionName(CameraProjection projection);  // "orthographic", "pinhole"

// Whether the scene file at `path` names its left team (game.left_team):
// then a command line's own default (FIRASim's layout with --firasim) does
// not replace it. False for a file that cannot be read or parsed.
bool sceneNamesLeftTeam(const QString& path);

// Names of the built-in example scenes, sorted.
QStringList builtinSceneNames();

}  // namespace vssim
