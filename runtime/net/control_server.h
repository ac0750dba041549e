// The TCP side of docs/protocol.md: accepts clients, checks what they send,
// posts requests to the engine thread stamped with their arrival time, and
// writes the engine's frames, states and replies back. Lives in the thread
// that owns it (the main thread); never blocks on a client. A camera stream
// is never late: in real time a client gets a new frame only once the socket
// has taken the previous one (the newest waits, older ones are dropped), and
// its socket's send buffer is kept small; in lockstep, where the client sets
// the pace, frames queue up to lockstepBacklogBytes. REPLY and ERROR
// messages are never dropped and keep their order with the frames: behind a
// frame that waits, they wait too. What waits unsent is bounded: a client
// that lets more than maxUnsentBytes pile up, or the one with the most
// unsent when all together hold more than maxTotalUnsentBytes, is
// disconnected; above half of that, frames wait for every client whose
// socket has not taken the previous one, lockstep or not. ERROR replies are
// rationed (kMaxErrorsPerWindow): a client that sends nothing but mistakes
// and never reads would otherwise turn each 6-byte message into a 100-byte
// reply kept for it.
//
// Clients are served fairly: each gets a turn of at most kMaxMessagesPerTurn
// messages (kMaxBytesPerTurn bytes) when its socket has data, and the rest
// waits for its next turn, queued behind the other clients' turns and the
// engine's frames; what the server has not read yet stays in the kernel
// (beyond kReadAheadBytes), so TCP slows a sender the server cannot keep up
// with. A turn's VOLTAGES reach the engine as one request, the newest per
// robot.
//
// Each client has its own camera link (docs/protocol.md, FRAME, Delivery):
// the scene's camera with its HELLO's `camera` over it. Its frames (with
// their STATE, noisy as its camera makes it: wire/state_message.h) wait in
// its FrameDelivery until simulated time reaches their delivery time, which
// is checked at each camera instant, REPLY and REFEREE; only then do they
// meet the flow control above; at most maxUnsentBytes wait in the link (the
// oldest go beyond). With the ideal camera they go at once, as they always did.
#pragma once

#include <QHostAddress>
#include <QObject>
#include <QTcpServer>
#include <functional>
#include <map>
#include <memory>

#include "vssim/camera/camera_renderer.h"
#include "net/client_requests.h"
#include "realtime/engine_thread.h"
#include "realtime/sample_stats.h"
#include "wire/protocol.h"

class QTcpSocket;
class QTimer;

namespace vssim {

struct ServerSettings {
    QHostAddress address = QHostAddress::LocalHost;
    quint16 port = protocol::kDefaultPort;   // 0: any free port
    int helloTimeoutMs = 5000;               // a client must say HELLO within this
    qint64 lockstepBacklogBytes = 1 << 20;   // lockstep: unsent bytes above which new frames wait (newest kept)
    // Real time: the kernel's send buffer for subscribers (SO_SNDBUF; Linux doubles it). It must hold two of
    // loopback's 64 KiB segments: with room for one, each waits for the reader's delayed ACK (40 ms), 1.6 MB/s.
    int realtimeSendBufferBytes = 64 << 10;
    qint64 maxUnsentBytes = 8 << 20;         // one client's unsent bytes above which it is disconnected
    qint64 maxTotalUnsentBytes = 64 << 20;   // all clients' together: above, the one with the most is disconnected
    int maxClients = 64;
    // Observers may only watch and ask for `stats`: commands that change the
    // game (pause, step, reset, placing bodies, speed) get ERROR read_only.
    // For matches, where only the teams (or the person at the app) decide.
    bool readOnlyObservers = false;
    // Simulated seconds of `step` one client may have waiting for the engine
    // (more gets `busy`): the engine does a step at once, and an hour of
    // simulated time costs it seconds, during which no one else is served.
    double maxQueuedStepSeconds = kMaxStepDuration;
};

// One connected client, for a connections panel.
struct ClientInfo {
    int id = 0;
    QString peer;  // address:port
    bool greeted = false;
    QString role;  // yellow, blue, observer
    QString name;
    QString images;  // e.g. "patches/png", or "none"
    bool state = false;
    std::int64_t commands = 0, framesSent = 0, framesDropped = 0;
    qint64 unsentBytes = 0;          // written for it and not yet taken by the kernel, plus what waits (its camera link's too)
    qint64 unreadBytes = 0;          // received from it and not handled yet (the rest waits in the kernel)
    std::int64_t errorsNotSent = 0;  // ERROR replies withheld: more than kMaxErrorsPerWindow
    double connectedSeconds = 0.0;
};

// A log line is cut here (its client-given parts are cut to 40 or 64 characters long before).
constexpr int kMaxLogLineCharacters = 1000;
// Requests one client may have waiting for the engine (a flood gets `busy`).
constexpr int kMaxQueuedPerClient = 500;
// One client's turn: this many messages or bytes at most (at least one message),
// so that a few microseconds per message keep a turn well under a millisecond.
constexpr int kMaxMessagesPerTurn = 64;
constexpr qint64 kMaxBytesPerTurn = 64 << 10;
// Bytes Qt reads ahead from one client's socket; more waits in the kernel.
constexpr qint64 kReadAheadBytes = 64 << 10;
// ERROR replies one client gets in a window (fixed, from its first error):
// plenty to debug with, and beyond them one ERROR too_many_errors says that
// the rest of the window's are not sent (their messages are still refused).
constexpr int kMaxErrorsPerWindow = 100;
constexpr std::int64_t kErrorWindowNs = 10'000'000'000;
// A client dropped after a fatal error with more unsent than this is not
// reading: it is closed at once instead of being given 2 s to take its ERROR.
constexpr qint64 kGraceBytes = 1 << 20;

class ControlServer : public QObject {
    Q_OBJECT
public:
    ControlServer(const Scene& scene, EngineThread& engine, const ServerSettings& settings, QObject* parent = nullptr);
    ~ControlServer() override;

    bool listen(QString* error);
    quint16 port() const { return server_.serverPort(); }
    QHostAddress address() const { return server_.serverAddress(); }
    int clientCount() const { return static_cast<int>(clients_.size()); }
    std::vector<ClientInfo> clients() const;
    // Another scene (the desktop app opened one): every client is told
    // (ERROR scene_changed, fatal) and disconnected, since its WELCOME no
    // longer holds. The engine gets the scene separately (LoadScene).
    void setScene(const Scene& scene);
    // New integrator, dt or collision settings (clients stay; later WELCOMEs say so).
    void setSimulationSettings(const SimulationSettings& settings) { scene_.simulation = settings; }

signals:
    // One line for the log: connections, greetings, errors, disconnections.
    void logLine(const QString& line);

private:
    struct Client;

    void accept();
    void makeRoomFor(Client& newcomer);  // above maxClients: the oldest without HELLO goes, or the newcomer
    void serveTurn(Client& client);
    void flushVoltages(Client& client, std::int64_t arrivalNs);
    void handle(Client& client, const protocol::Message& message, std::int64_t arrivalNs);
    void handleVoltages(Client& client, const protocol::Message& message);
    void handleWheelSpeeds(Client& client, const protocol::Message& message);
    void keepNewest(Client& client, int robot, const DriveCommand& drive);  // into the turn's request
    void greet(Client& client, const QJsonObject& json);
    void sendError(Client& client, const RequestError& error, bool fatal, const QJsonValue& id = QJsonValue());
    bool errorAllowed(Client& client);  // within its ERROR ration (says so once when not)
    void writeError(Client& client, const RequestError& error, bool fatal, const QJsonValue& id);
    void send(Client& client, const QByteArray& bytes);  // in order, behind a frame that waits
    static bool waiting(const Client& client);           // a frame (or STATE) waits for its socket
    bool fits(Client& client, qint64 bytes);             // within the memory limits (false: it was dropped)
    bool makeRoom(Client& writer, qint64 bytes);         // false: the writer itself had to go
    qint64 unsent(const Client& client) const;           // what the memory limits count

    qint64 totalUnsent() const;
    void sendNewest(Client& client, QByteArray frame, QByteArray state, std::int64_t instantNs);
    bool holdsFrames(Client& client);  // whether a new frame must wait for this client's socket
    bool lockstep() const;
    void flushPending(Client& client);
    // Hands the client the frames its camera link has delivered by simulated time `now` (s).
    void deliverDue(Client& client, double now);
    // Closes a client's connection: after its unsent bytes (a last ERROR) are
    // written, or `now`, discarding them (it is not reading).
    void drop(Client& client, const QString& why, bool now = false);
    void forget(int id);
    void stopRobots(Client& client);                   // 0 V to a team client's robots, once
    bool post(Client& client, EngineRequest request);  // false: its quota or the queue is full
    void drainEngine();
    void updateSubscriptions();
    QJsonObject welcome(const Client& client) const;
    QJsonObject gameJson() const;  // WELCOME's "game": the settings and the state
    void log(const Client& client, const QString& text);

    Scene scene_;
    EngineThread& engine_;
    ServerSettings settings_;
    CameraRenderer background_;  // for the background images sent on HELLO
    QTcpServer server_;
    std::map<int, std::unique_ptr<Client>> clients_;
    QJsonObject lastReferee_;  // the last REFEREE sent (empty before the first)
    SampleStats imageAgeMs_;   // from the camera instant to its FRAME's hand-over to the socket, ms
    int nextId_ = 1;
    std::map<ClientRole, std::int64_t> greetedByRole_;  // clients greeted per role since the scene: their draw streams
};

}  // namespace vssim
