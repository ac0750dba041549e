#include "gui_command.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QCoreApplication>
#include <QHostAddress>
#include <QRegularExpression>
#include <QSurfaceFormat>
#include <QTextStream>
#include <cstdlib>

#include "display.h"
#include "vssim/camera/camera_renderer.h"
#include "io/scene_io.h"
#include "main_window.h"
#include "net/network_address.h"
#include "remote_window.h"
#include "wire/protocol.h"

namespace vssim {

int guiCommand(int argc, char** argv) {
    // The command line first, with a plain QCoreApplication: --help and bad
    // options work without a display.
    ServerSettings server;
    QString connectTarget, sceneName;
    {
        QCoreApplication core(argc, argv);
        QStringList args = QCoreApplication::arguments();
        if (args.size() >= 2 && args[1] == "gui") args.removeAt(1);
        QCommandLineParser parser;
        parser.setApplicationDescription(
            "The vssim desktop app: the field, dragging robots, driving by hand, live plots;\n"
            "it also serves TCP clients like vssim serve (docs/protocol.md). Guide: docs/app.md.");
        parser.addHelpOption();
        parser.addPositionalArgument("scene", "Scene file or built-in scene name (default: kickoff_3v3).", "[SCENE]");
        const QCommandLineOption port(
            "port", QStringLiteral("TCP port for clients (default %1; 0: any free port).").arg(protocol::kDefaultPort),
            "N");
        const QCommandLineOption listen("listen", "Address to listen on (default 127.0.0.1).", "ADDR");
        const QCommandLineOption connectTo("connect", "Watch a running vssim serve instead (as an observer).",
                                           "HOST:PORT");
        const QCommandLineOption readOnly("read-only-observers",
                                          "Observers of the app's server may only watch and ask for stats "
                                          "(docs/protocol.md, read_only).");
        parser.addOptions({port, listen, connectTo, readOnly});
        QTextStream err(stderr);
        if (!parser.parse(args)) {
            err << "vssim gui: " << parser.errorText() << "\n";
            return 2;
        }
        if (parser.isSet("help")) {
            QString text = parser.helpText();
            text.replace(QRegularExpression("^Usage: \\S+"), "Usage: vssim gui");  // not the binary's path
            QTextStream(stdout) << text << "\n";
            return 0;
        }
        if (parser.isSet(port)) {
            const std::optional<quint16> value = parsePort(parser.value(port));
            if (!value) {
                err << "vssim gui: --port: expected 0 to 65535, got \"" << parser.value(port) << "\"\n";
                return 2;
            }
            server.port = *value;
        }
        if (parser.isSet(listen) && !server.address.setAddress(parser.value(listen))) {
            err << "vssim gui: --listen: \"" << parser.value(listen) << "\" is not an IP address\n";
            return 2;
        }
        server.readOnlyObservers = parser.isSet(readOnly);
        connectTarget = parser.value(connectTo);
        sceneName = parser.positionalArguments().value(0, "kickoff_3v3");
        if (!displayAvailable()) {
            err << "vssim gui: no display: set DISPLAY (X11) or WAYLAND_DISPLAY, or run it under xvfb-run; "
                   "vssim serve runs headless\n";
            return 1;
        }
    }

    QApplication app(argc, argv);
    QApplication::setApplicationName("vssim");
    QApplication::setOrganizationName("vssim");
    QApplication::setApplicationVersion(VSSIM_VERSION);
    QTextStream err(stderr);
    if (!connectTarget.isEmpty()) {
        const std::optional<HostPort> target = parseHostPort(connectTarget);
        if (!target) {
            err << "vssim gui: --connect: expected HOST:PORT, e.g. 127.0.0.1:" << protocol::kDefaultPort << ", got \""
                << connectTarget << "\"\n";
            return 2;
        }
        auto* watcher = new RemoteWatcher;
        QString error;
        if (!watcher->connectTo(target->host, target->port, &error)) {
            err << "vssim gui: " << error << "\n";
            delete watcher;
            return 1;
        }
        RemoteWindow window(watcher);
        window.show();
        return QApplication::exec();
    }
    const QString path = resolveScenePath(sceneName);
    QString error;
    const std::optional<Scene> scene = path.isEmpty() ? std::nullopt : loadSceneFile(path, &error);
    if (!scene) {
        err << "vssim gui: " << (path.isEmpty() ? sceneNotFoundMessage(sceneName) : error) << "\n";
        return 2;
    }
    if (const std::string problem = cameraProblem(*scene); !problem.empty()) {
        err << "vssim gui: " << path << ": " << QString::fromStdString(problem) << "\n";
        return 2;
    }
    MainWindow window(*scene, path, server);
    window.show();
    return QApplication::exec();
}

}  // namespace vssim
