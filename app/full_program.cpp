#include "full_program.h"

#include <limits.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace vssim {

namespace {

constexpr const char* kFullName = "vssim-full";

std::string ownDirectory() {
    char path[PATH_MAX];
    const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
    if (n <= 0) return {};
    path[n] = '\0';
    std::string s(path);
    const std::size_t slash = s.rfind('/');
    return slash == std::string::npos ? std::string(".") : s.substr(0, slash);
}

bool executable(const std::string& path) { return ::access(path.c_str(), X_OK) == 0; }

}  // namespace

std::string fullProgramPath(std::string* lookedAt) {
    const std::string dir = ownDirectory();
    const std::string candidates[] = {dir + "/" + kFullName, dir + "/../libexec/vssim/" + kFullName};
    if (lookedAt) lookedAt->clear();
    for (const std::string& c : candidates) {
        if (executable(c)) return c;
        if (lookedAt) *lookedAt += (lookedAt->empty() ? "" : ", ") + c;
    }
    return {};
}

int runFullProgram(char** argv) {
    std::string looked;
    const std::string path = fullProgramPath(&looked);
    if (path.empty()) {
        std::fprintf(stderr,
                     "vssim: this command needs %s, the part of vssim with the desktop app and the server, "
                     "which is missing (looked at %s): reinstall vssim, or build the whole project\n",
                     kFullName, looked.c_str());
        return 127;
    }
    ::execv(path.c_str(), argv);
    std::fprintf(stderr, "vssim: cannot start %s: %s\n", path.c_str(), std::strerror(errno));
    return 127;
}

}  // namespace vssim
