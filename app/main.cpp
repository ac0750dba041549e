// vssim: the command-line entry point. Subcommands dispatch to their own files.
// The headless commands (run, match, stress, demo, --help, --version) run
// here, in a program that loads Qt Core and nothing of the GUI, the camera or
// the network; `gui` and `serve` (and no command, with a display) are run by
// vssim-full, started in this process's place (full_program.h).
#include <fcntl.h>
#include <unistd.h>
#include <QCoreApplication>
#include <QTextStream>
#include <string>

#include "display.h"
#include "full_program.h"
#include "match_command.h"
#include "run_command.h"
#include "stress_command.h"

namespace {

QString mainHelp() {
    return QStringLiteral(
               "vssim %1 - simulator of IEEE Very Small Size Soccer robots (DC motors, ball, collisions)\n"
               "\n"
               "Usage:\n"
               "  vssim                 open the desktop app on the 3-vs-3 kick-off (without a display: the demo)\n"
               "  vssim gui [SCENE]     open the desktop app on a scene (vssim gui --help)\n"
               "  vssim demo            play the built-in 3-vs-3 kick-off headless for 10 s and print a summary\n"
               "  vssim run SCENE ...   run a scene headless and write CSV (vssim run --help)\n"
               "  vssim serve SCENE ... serve a scene over TCP (real time, faster or lockstep): voltages in, images out\n"
               "                        (vssim serve --help; protocol: docs/protocol.md)\n"
               "  vssim match [SCENE]   play a whole match headless: referee, built-in teams; prints the score\n"
               "                        and the referee's calls (vssim match --help; docs/game.md)\n"
               "  vssim stress ...      numerical-stability stress test on random scenes (vssim stress --help)\n"
               "  vssim --help          this help\n"
               "  vssim --version       the version\n"
               "\n"
               "Scenes are JSON files (docs/scenes.md); the model is described in docs/model.md.\n")
        .arg(VSSIM_VERSION);
}

// A standard descriptor closed by the caller (`vssim run ... >&-`) would be
// handed out again by the next open(): the CSV would go to whatever Qt opened
// first, or error messages into the --out file. Each closed one is held by
// /dev/null opened read-only instead, so nothing else gets it and a write
// to it fails ("Bad file descriptor"), which vssim run reports.
void holdClosedStandardDescriptors() {
    for (int fd : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO}) {
        if (::fcntl(fd, F_GETFD) != -1) continue;
        const int held = ::open("/dev/null", O_RDONLY);
        if (held >= 0 && held != fd) {  // lower descriptors are open, so this is fd unless open() failed
            ::dup2(held, fd);
            ::close(held);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    holdClosedStandardDescriptors();
    const std::string first = argc >= 2 ? argv[1] : "";
    if (first == "gui" || first == "serve" || (argc < 2 && vssim::displayAvailable()))
        return vssim::runFullProgram(argv);  // `vssim gui` says so itself when there is no display
    QCoreApplication app(argc, argv);
    QCoreApplication::setApplicationName("vssim");
    QCoreApplication::setApplicationVersion(VSSIM_VERSION);
    const QStringList args = QCoreApplication::arguments();
    if (args.size() < 2) {
        QTextStream(stderr) << "vssim: no display, so no desktop app: running the headless demo instead "
                               "(vssim gui needs X11 or Wayland; vssim --help lists the rest)\n";
        return vssim::demoCommand();
    }
    if (args[1] == "demo") {
        if (args.size() > 2) {
            const bool help = args[2] == "-h" || args[2] == "--help";
            (help ? QTextStream(stdout) : QTextStream(stderr))
                << (help ? "" : QStringLiteral("vssim demo: unexpected argument \"%1\"\n").arg(args[2]))
                << "Usage: vssim demo\n  Plays the built-in 3-vs-3 kick-off headless for 10 s and prints where "
                   "everything ended up.\n";
            return help ? 0 : 2;
        }
        return vssim::demoCommand();
    }
    const QString command = args[1];
    if (command == "run") return vssim::runCommand(args.mid(1));
    if (command == "match") return vssim::matchCommand(args.mid(1));
    if (command == "stress") return vssim::stressCommand(args.mid(1));
    if (command == "-h" || command == "--help" || command == "help") {
        QTextStream(stdout) << mainHelp();
        return 0;
    }
    if (command == "-v" || command == "--version") {
        QTextStream(stdout) << "vssim " << VSSIM_VERSION << "\n";
        return 0;
    }
    QTextStream(stderr) << "vssim: unknown command \"" << command << "\"\n\n" << mainHelp();
    return 2;
}
