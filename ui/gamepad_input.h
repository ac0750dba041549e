// Gamepad input through SDL2's GameController API (any controller SDL maps:
// Xbox, PlayStation, Switch Pro, ...). Polls at 100 Hz with a QTimer on the
// thread that owns it, so it needs no SDL window or video subsystem.
#pragma once

#include <QObject>
#include <QString>
#include <QTimer>

struct _SDL_GameController;

namespace vssim {

class GamepadInput : public QObject {
    Q_OBJECT
public:
    // Initialises SDL's game-controller subsystem (only that: no video, no
    // audio, no SDL signal handlers, events even when the window is not
    // focused). If that fails, available() is false and errorString() says
    // why; every other call is then a harmless no-op.
    explicit GamepadInput(QObject* parent = nullptr);
    // Closes the controller and shuts the subsystem down.
    ~GamepadInput() override;

    GamepadInput(const GamepadInput&) = delete;
    GamepadInput& operator=(const GamepadInput&) = delete;

    bool available() const { return available_; }
    QString errorString() const { return error_; }

    // Whether a controller is open, and its name (empty when none).
    bool connected() const { return controller_ != nullptr; }
    QString name() const { return name_; }

    // Poll period, ms (100 Hz).
    static constexpr int kPollIntervalMs = 10;

public slots:
    // Opens the first controller already plugged in (if any) and starts
    // polling: hot-plug, and the sticks. Does nothing if !available().
    void start();
    // Stops polling (the controller stays open; axes are not reported).
    void stop();

signals:
    // Stick positions, each in [-1, 1] (dimensionless): x right positive,
    // y UP positive (SDL's y axis, which points down, is inverted). Emitted
    // when any of them changes, and all zeros when the controller goes away.
    void axesChanged(double leftX, double leftY, double rightX, double rightY);
    // A controller was opened (true, its name) or the open one was
    // unplugged (false, its name) with no other one to replace it.
    void connectedChanged(bool connected, const QString& name);

private:
    void poll();
    void openFirst();            // opens the first game controller, if any
    bool open(int deviceIndex);  // SDL device index
    void close();                // closes the open one (no signal)
    void readAxes();

    bool available_ = false;
    QString error_;
    _SDL_GameController* controller_ = nullptr;
    int instanceId_ = -1;  // SDL_JoystickID of the open controller
    QString name_;
    QTimer timer_;
    double axes_[4] = {0.0, 0.0, 0.0, 0.0};  // last emitted: lx, ly, rx, ry
};

}  // namespace vssim
