// libFuzzer target: a datagram on VSSReferee's placement port, as the
// bridge reads it (runtime/firasim/vssref_bridge.cpp: a VSSRef_Placement
// with a world frame, then runtime/firasim/vssref_command's vssRefPlacement
// against the kick-off scene). A refusal always says why.
#include <QString>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "firasim/team_roster.h"
#include "firasim/vssref_command.h"
#include "io/scene_io.h"
#include "kickoff_scene.h"

using namespace vssim;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const Scene& scene = fuzz::kickoffScene();
    static const TeamRoster roster(scene);
    VSSRef::team_to_ref::VSSRef_Placement message;
    if (!message.ParseFromArray(data, static_cast<int>(size)) || !message.has_world()) return 0;
    QString why;
    if (!vssRefPlacement(message, scene, roster, &why) && why.isEmpty()) std::abort();
    return 0;
}
