// libFuzzer target: a datagram on FIRASim's command port
// (runtime/firasim/packet_reader), read against the kick-off scene with
// every robot on the field, then with blue's robot 0 off it.
#include <QString>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "firasim/packet_reader.h"
#include "firasim/team_roster.h"
#include "io/scene_io.h"
#include "kickoff_scene.h"

using namespace vssim;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const Scene& scene = fuzz::kickoffScene();
    static const TeamRoster roster(scene);
    static const WorldState current = initialWorldState(scene);
    std::vector<char> onField(scene.robots.size(), 1);
    const char* bytes = reinterpret_cast<const char*>(data);
    const int n = static_cast<int>(size);
    (void)readFirasimPacket(bytes, n, scene, roster, current, onField);
    const int blue0 = roster.robotIndex(Team::Blue, 0);
    if (blue0 >= 0) onField[static_cast<std::size_t>(blue0)] = 0;
    (void)readFirasimPacket(bytes, n, scene, roster, current, onField);
    return 0;
}
