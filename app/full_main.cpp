// vssim-full: the commands of `vssim` that need the desktop app or the
// server's stacks (Qt Widgets and OpenGL, SDL2, OpenCV, Qt Network,
// protobuf): `vssim gui` and `vssim serve`. `vssim` itself starts it for
// them with the same arguments (full_program.h); run by hand it takes the
// same command line as `vssim` does for those two commands.
#include <QCoreApplication>
#include <QTextStream>
#include <string>

#include "display.h"
#include "gui_command.h"
#include "serve_command.h"

int main(int argc, char** argv) {
    const std::string command = argc >= 2 ? argv[1] : "";
    if (command == "gui" || (command.empty() && vssim::displayAvailable())) return vssim::guiCommand(argc, argv);
    QCoreApplication app(argc, argv);
    QCoreApplication::setApplicationName("vssim");
    QCoreApplication::setApplicationVersion(VSSIM_VERSION);
    if (command == "serve") return vssim::serveCommand(QCoreApplication::arguments().mid(1));
    QTextStream(stderr) << "vssim-full: expected the command gui or serve (this program runs them for vssim; "
                           "vssim --help lists every command)\n";
    return 2;
}
