// Runs the built vssim binary from a test and collects what it did.
#pragma once

#include <QByteArray>
#include <QProcess>
#include <QProcessEnvironment>
#include <QStringList>
#include <functional>

namespace vssim::test {

struct Result {
    int exitCode = -1;  // -1: crashed or timed out
    QByteArray out;     // standard output
    QByteArray err;     // standard error
};

// Runs VSSIM_BINARY with `args`, waiting at most two minutes. `setUp`, when
// given, prepares the process before it starts (its standard output, a child
// modifier).
inline Result runVssim(const QStringList& args, const std::function<void(QProcess&)>& setUp = {}) {
    QProcess p;
    if (setUp) setUp(p);
    // Never a display: `vssim` alone would open the desktop app.
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"}) env.remove(name);
    p.setProcessEnvironment(env);
    p.start(VSSIM_BINARY, args);
    Result r;
    if (!p.waitForFinished(120000)) {
        p.kill();
        r.err = "timed out";
        return r;
    }
    r.exitCode = p.exitStatus() == QProcess::NormalExit ? p.exitCode() : -1;
    r.out = p.readAllStandardOutput();
    r.err = p.readAllStandardError();
    return r;
}

}  // namespace vssim::test
