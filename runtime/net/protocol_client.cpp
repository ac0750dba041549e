#include "net/protocol_client.h"

#include <QEventLoop>
#include <QTimer>

#include "realtime/monotonic_clock.h"

namespace vssim {

ProtocolClient::ProtocolClient(QObject* parent) : QObject(parent) {
    connect(&socket_, &QTcpSocket::readyRead, this, &ProtocolClient::readAvailable);
}

bool ProtocolClient::connectTo(quint16 port, const QString& host, int timeoutMs) {
    // Again after a disconnection (a watcher reconnecting): nothing of the old connection is kept.
    socket_.abort();
    reader_ = protocol::MessageReader{protocol::kMaxServerMessage};
    inbox_.clear();
    failed_ = false;
    socket_.connectToHost(host, port);
    QElapsedTimer timer;
    timer.start();
    QEventLoop loop;
    QTimer poll;
    connect(&socket_, &QTcpSocket::connected, &loop, &QEventLoop::quit);
    connect(&socket_, &QTcpSocket::errorOccurred, &loop, &QEventLoop::quit);
    QTimer::singleShot(timeoutMs, &loop, &QEventLoop::quit);
    if (socket_.state() != QAbstractSocket::ConnectedState) loop.exec();
    if (socket_.state() != QAbstractSocket::ConnectedState) return false;
    socket_.setSocketOption(QAbstractSocket::LowDelayOption, 1);  // no Nagle delay on small messages
    return true;
}

void ProtocolClient::send(protocol::MessageType type, const QByteArray& payload) {
    sendRaw(protocol::encodeMessage(type, payload));
}

void ProtocolClient::sendJson(protocol::MessageType type, const QJsonObject& json) {
    sendRaw(protocol::encodeJsonMessage(type, json));
}

void ProtocolClient::sendRaw(const QByteArray& bytes) {
    socket_.write(bytes);
    socket_.flush();
}

std::optional<QJsonObject> ProtocolClient::hello(const QJsonObject& json, int timeoutMs) {
    sendJson(protocol::MessageType::Hello, json);
    const std::optional<Received> r = next(timeoutMs);
    if (!r || r->message.type != static_cast<std::uint8_t>(protocol::MessageType::Welcome)) {
        if (r) inbox_.push_front(*r);  // leave the ERROR for the caller
        return std::nullopt;
    }
    return jsonPayload(r->message);
}

void ProtocolClient::setReading(bool reading) {
    reading_ = reading;
    // Also stop QTcpSocket itself from reading the kernel's buffer, so that
    // the server sees a client that does not read.
    socket_.setReadBufferSize(reading ? 0 : 1);
    if (reading) readAvailable();
}

void ProtocolClient::readAvailable() {
    if (!reading_) return;
    const std::int64_t now = monotonicNs();
    reader_.append(socket_.readAll());
    protocol::Message message;
    bool any = false;
    for (;;) {
        const auto status = reader_.next(&message);
        if (status == protocol::MessageReader::Status::NeedMore) break;
        if (status != protocol::MessageReader::Status::Message) {
            failed_ = true;
            socket_.abort();
            break;
        }
        inbox_.push_back({message, now});
        any = true;
    }
    if (any) emit messageReceived();
}

std::optional<ProtocolClient::Received> ProtocolClient::next(int timeoutMs) {
    if (inbox_.empty()) {
        QEventLoop loop;
        connect(this, &ProtocolClient::messageReceived, &loop, &QEventLoop::quit);
        connect(&socket_, &QTcpSocket::disconnected, &loop, &QEventLoop::quit);
        QTimer::singleShot(timeoutMs, &loop, &QEventLoop::quit);
        if (socket_.state() == QAbstractSocket::ConnectedState) loop.exec();
        readAvailable();
    }
    if (inbox_.empty()) return std::nullopt;
    Received r = std::move(inbox_.front());
    inbox_.pop_front();
    return r;
}

std::optional<ProtocolClient::Received> ProtocolClient::poll() {
    if (inbox_.empty()) return std::nullopt;
    Received r = std::move(inbox_.front());
    inbox_.pop_front();
    return r;
}

std::optional<ProtocolClient::Received> ProtocolClient::nextOf(protocol::MessageType type, int timeoutMs) {
    QElapsedTimer timer;
    timer.start();
    while (timer.elapsed() <= timeoutMs) {
        std::optional<Received> r = next(static_cast<int>(std::max<qint64>(1, timeoutMs - timer.elapsed())));
        if (!r) return std::nullopt;
        if (r->message.type == static_cast<std::uint8_t>(type)) return r;
    }
    return std::nullopt;
}

bool ProtocolClient::waitForDisconnect(int timeoutMs) {
    if (socket_.state() == QAbstractSocket::UnconnectedState) return true;
    QEventLoop loop;
    connect(&socket_, &QTcpSocket::disconnected, &loop, &QEventLoop::quit);
    QTimer::singleShot(timeoutMs, &loop, &QEventLoop::quit);
    loop.exec();
    readAvailable();
    return socket_.state() == QAbstractSocket::UnconnectedState;
}

QJsonObject jsonPayload(const protocol::Message& message) {
    QString error;
    return protocol::parseJsonObject(message.payload, &error).value_or(QJsonObject());
}

}  // namespace vssim
