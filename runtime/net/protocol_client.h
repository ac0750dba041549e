// A small Qt client of docs/protocol.md, for the tests and the benchmarks
// (the examples in examples/ show how to write one without Qt). Messages are
// queued as they arrive; the wait functions run the event loop, so the
// server may live in the same thread (tests) or another process (benchmarks).
#pragma once

#include <QElapsedTimer>
#include <QJsonObject>
#include <QObject>
#include <QTcpSocket>
#include <deque>
#include <optional>

#include "wire/protocol.h"

namespace vssim {

class ProtocolClient : public QObject {
    Q_OBJECT
public:
    struct Received {
        protocol::Message message;
        std::int64_t arrivalNs = 0;  // monotonicNs() when it was read
    };

    explicit ProtocolClient(QObject* parent = nullptr);

    bool connectTo(quint16 port, const QString& host = QStringLiteral("127.0.0.1"), int timeoutMs = 5000);
    void send(protocol::MessageType type, const QByteArray& payload);
    void sendJson(protocol::MessageType type, const QJsonObject& json);
    void sendRaw(const QByteArray& bytes);
    // HELLO, then waits for WELCOME (nullopt: no WELCOME within the timeout, e.g. an ERROR came).
    std::optional<QJsonObject> hello(const QJsonObject& json, int timeoutMs = 5000);

    // The next message (of any type), waiting up to timeoutMs.
    std::optional<Received> next(int timeoutMs = 5000);
    // The next message already received, without waiting.
    std::optional<Received> poll();
    // The next message of `type`; messages of other types before it are dropped.
    std::optional<Received> nextOf(protocol::MessageType type, int timeoutMs = 5000);
    // Waits until the server closes the connection.
    bool waitForDisconnect(int timeoutMs = 5000);
    // Reading can be stopped to play a client that never reads.
    void setReading(bool reading);

    QTcpSocket& socket() { return socket_; }
    std::size_t queued() const { return inbox_.size(); }
    bool failed() const { return failed_; }

signals:
    void messageReceived();

private:
    void readAvailable();
    QTcpSocket socket_;
    protocol::MessageReader reader_{protocol::kMaxServerMessage};
    std::deque<Received> inbox_;
    bool reading_ = true;
    bool failed_ = false;  // the server sent something unreadable
};

// JSON payload of a message (empty object when it is not JSON).
QJsonObject jsonPayload(const protocol::Message& message);

}  // namespace vssim
