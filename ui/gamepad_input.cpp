#include "gamepad_input.h"

#include <SDL.h>

#include <algorithm>

namespace vssim {

namespace {

// SDL axis value (-32768..32767) to [-1, 1].
double normalisedAxis(Sint16 raw) { return std::clamp(static_cast<double>(raw) / 32767.0, -1.0, 1.0); }

}  // namespace

GamepadInput::GamepadInput(QObject* parent) : QObject(parent) {
    // Qt handles SIGINT/SIGTERM itself; SDL must not install handlers. The
    // app window has focus, not SDL (which has none), so accept background
    // events.
    SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");
    SDL_SetHint(SDL_HINT_JOYSTICK_ALLOW_BACKGROUND_EVENTS, "1");
    // Reference-counted by SDL: several GamepadInputs (or other SDL users)
    // may coexist; the destructor undoes exactly this.
    if (SDL_InitSubSystem(SDL_INIT_GAMECONTROLLER) == 0) {
        available_ = true;
    } else {
        error_ = QStringLiteral("SDL game controller subsystem unavailable: %1").arg(QString::fromUtf8(SDL_GetError()));
    }
    timer_.setInterval(kPollIntervalMs);
    timer_.setTimerType(Qt::PreciseTimer);
    connect(&timer_, &QTimer::timeout, this, &GamepadInput::poll);
}

GamepadInput::~GamepadInput() {
    timer_.stop();
    if (!available_) return;
    close();
    SDL_QuitSubSystem(SDL_INIT_GAMECONTROLLER);
    if (SDL_WasInit(SDL_INIT_EVERYTHING) == 0) SDL_Quit();  // nothing else uses SDL
}

void GamepadInput::start() {
    if (!available_) return;
    if (!controller_) openFirst();
    timer_.start();
}

void GamepadInput::stop() { timer_.stop(); }

void GamepadInput::openFirst() {
    const int count = SDL_NumJoysticks();
    for (int i = 0; i < count; ++i)
        if (SDL_IsGameController(i) && open(i)) return;
}

bool GamepadInput::open(int deviceIndex) {
    SDL_GameController* controller = SDL_GameControllerOpen(deviceIndex);
    if (!controller) return false;
    controller_ = controller;
    instanceId_ = SDL_JoystickInstanceID(SDL_GameControllerGetJoystick(controller));
    const char* name = SDL_GameControllerName(controller);
    name_ = name ? QString::fromUtf8(name) : QStringLiteral("Game controller");
    emit connectedChanged(true, name_);
    readAxes();
    return true;
}

void GamepadInput::close() {
    if (controller_) SDL_GameControllerClose(controller_);
    controller_ = nullptr;
    instanceId_ = -1;
    name_.clear();
}

void GamepadInput::poll() {
    if (!available_) return;
    SDL_Event event;
    while (SDL_PollEvent(&event)) {
        switch (event.type) {
            case SDL_CONTROLLERDEVICEADDED:  // cdevice.which: device index
                if (!controller_) open(event.cdevice.which);
                break;
            case SDL_CONTROLLERDEVICEREMOVED:  // cdevice.which: instance id
                if (controller_ && event.cdevice.which == instanceId_) {
                    const QString lost = name_;
                    close();
                    if (axes_[0] != 0.0 || axes_[1] != 0.0 || axes_[2] != 0.0 || axes_[3] != 0.0) {
                        std::fill(std::begin(axes_), std::end(axes_), 0.0);
                        emit axesChanged(0.0, 0.0, 0.0, 0.0);  // let go: stop the robot
                    }
                    openFirst();  // another one still plugged in takes over
                    if (!controller_) emit connectedChanged(false, lost);
                }
                break;
            default:  // axis/button events: the axes are read below
                break;
        }
    }
    readAxes();
}

void GamepadInput::readAxes() {
    if (!controller_) return;
    const double now[4] = {
        normalisedAxis(SDL_GameControllerGetAxis(controller_, SDL_CONTROLLER_AXIS_LEFTX)),
        -normalisedAxis(SDL_GameControllerGetAxis(controller_, SDL_CONTROLLER_AXIS_LEFTY)),
        normalisedAxis(SDL_GameControllerGetAxis(controller_, SDL_CONTROLLER_AXIS_RIGHTX)),
        -normalisedAxis(SDL_GameControllerGetAxis(controller_, SDL_CONTROLLER_AXIS_RIGHTY)),
    };
    if (std::equal(std::begin(now), std::end(now), std::begin(axes_))) return;
    std::copy(std::begin(now), std::end(now), std::begin(axes_));
    emit axesChanged(now[0], now[1], now[2], now[3]);
}

}  // namespace vssim
