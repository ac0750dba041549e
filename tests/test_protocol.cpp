// The wire protocol (docs/protocol.md): framing, VOLTAGES and FRAME layouts,
// and the checks on HELLO, VOLTAGES and CONTROL. Expected bytes are spelled
// out by hand from the document (big-endian, IEEE 754 bit patterns), never
// produced by the encoders under test.
#include <QtTest>

#include <QJsonArray>
#include <QJsonDocument>
#include <cmath>
#include <initializer_list>
#include <limits>

#include "net/client_requests.h"
#include "net/network_address.h"
#include "wire/protocol.h"

using namespace vssim;
using namespace vssim::protocol;

namespace {

QByteArray bytes(std::initializer_list<int> list) {
    QByteArray out;
    for (int b : list) out.append(static_cast<char>(b));
    return out;
}

void pushU32(QByteArray& out, std::uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) out.append(static_cast<char>((v >> shift) & 0xFF));
}

// A message framed by hand: u32 length (type + payload), u8 type, payload.
QByteArray frameMessage(int type, const QByteArray& payload) {
    QByteArray out;
    pushU32(out, static_cast<std::uint32_t>(payload.size() + 1));
    out.append(static_cast<char>(type));
    return out + payload;
}

QJsonObject obj(const char* json) {
    const QJsonDocument doc = QJsonDocument::fromJson(json);
    if (!doc.isObject()) qFatal("test JSON is not an object: %s", json);
    return doc.object();
}

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// VOLTAGES for robot 2, right 1.5 V (0x3FF8000000000000), left -3.25 V (0xC00A000000000000).
const QByteArray kVoltagesRobot2 =
    bytes({0x01, 0x02, 0x3F, 0xF8, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xC0, 0x0A, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00});

// FRAME: frame 0x01020304, time 2.5 s (0x4004000000000000), kind patches, encoding jpeg,
// two patches: (258, 3, 4, 5) with 3 bytes 9 8 7, and an empty one at (640, 480).
const QByteArray kFramePayload =
    bytes({0x01, 0x02, 0x03, 0x04, 0x40, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00,
           0x02, 0x01, 0x02, 0x00, 0x03, 0x00, 0x04, 0x00, 0x05, 0x00, 0x00, 0x00, 0x03, 0x09, 0x08,
           0x07, 0x02, 0x80, 0x01, 0xE0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00});

// Two yellow then two blue robots on the standard 1.5 x 1.3 m field.
Scene fourRobotScene() {
    Scene scene;
    for (auto [name, team] : {std::pair{"yellow0", Team::Yellow}, std::pair{"yellow1", Team::Yellow},
                              std::pair{"blue0", Team::Blue}, std::pair{"blue1", Team::Blue}}) {
        RobotSpec r;
        r.name = name;
        r.team = team;
        scene.robots.push_back(r);
    }
    return scene;
}

std::vector<Message> drain(MessageReader& reader) {
    std::vector<Message> out;
    Message m;
    MessageReader::Status s;
    while ((s = reader.next(&m)) == MessageReader::Status::Message) out.push_back(m);
    if (s != MessageReader::Status::NeedMore) qFatal("reader stopped with status %d", int(s));
    return out;
}

// Three messages: an empty payload, a short one, a longer one.
QByteArray threeMessages() {
    return frameMessage(0x03, {}) + frameMessage(0x81, "abc") + frameMessage(0x02, QByteArray(300, 'x'));
}

}  // namespace

class TestProtocol : public QObject {
    Q_OBJECT
private slots:
    void encodeMessageLayout();
    void readerSplitsAStreamHoweverItArrives();
    void readerMessageSplitAcrossAppends();
    void readerOversizeEmptyAndExactMax();
    void readerLongStream();
    void voltagesHandBuiltBytes();
    void voltagesBadSizes_data();
    void voltagesBadSizes();
    void frameHandBuiltBytes();
    void frameRoundTrip();
    void frameTruncatedAtEveryLength();
    void frameBadPatchLengthTrailingBytesKindEncoding();
    void parseJsonObjectErrors();
    void helloDefaultsRolesAndImages();
    void helloErrors_data();
    void helloErrors();
    void helloNameIsSanitised();
    void checkVoltagesTeamsAndValues();
    void controlCommands();
    void controlPlaceRobotBoundary();
    void controlErrors_data();
    void controlErrors();
    void controlNonFiniteNumbers();
    void gameControlCommands();
    void placementChecks();
    void placementErrors_data();
    void placementErrors();
    void reviewFindings();
    void messagesCarryNoControlCharacters();
    void printableTextCatchesEveryLineBreaker();
    void portsAndAddresses();
};

void TestProtocol::encodeMessageLayout() {
    QCOMPARE(encodeMessage(MessageType::Voltages, "abc"), bytes({0, 0, 0, 4, 0x02, 'a', 'b', 'c'}));
    QCOMPARE(encodeMessage(MessageType::Error, {}), bytes({0, 0, 0, 1, 0x85}));
    const QByteArray big = encodeMessage(MessageType::Frame, QByteArray(0x10203, 'z'));
    QCOMPARE(big.left(5), bytes({0x00, 0x01, 0x02, 0x04, 0x82}));  // 0x10203 + 1, big-endian
    QCOMPARE(big.size(), 5 + 0x10203);

    const QJsonObject o{{"command", "step"}, {"duration", 0.03}, {"id", QJsonArray{1, "x"}}};
    const QByteArray m = encodeJsonMessage(MessageType::Control, o);
    QVERIFY(m.size() > 5);
    QByteArray header;
    pushU32(header, static_cast<std::uint32_t>(m.size() - 4));
    header.append(char(0x03));
    QCOMPARE(m.left(5), header);
    QCOMPARE(QJsonDocument::fromJson(m.mid(5)).object(), o);
    QVERIFY(!m.endsWith('\0'));
}

void TestProtocol::readerSplitsAStreamHoweverItArrives() {
    // Fed in one buffer, then one byte at a time: the same three messages.
    const QByteArray stream = threeMessages();
    for (int chunk : {int(stream.size()), 1}) {
        MessageReader reader(kMaxClientMessage);
        std::vector<Message> got;
        for (qsizetype at = 0; at < stream.size(); at += chunk) {
            reader.append(stream.mid(at, chunk));
            for (const Message& m : drain(reader)) got.push_back(m);
        }
        QCOMPARE(got.size(), std::size_t(3));
        QCOMPARE(int(got[0].type), 0x03);
        QVERIFY(got[0].payload.isEmpty());
        QCOMPARE(int(got[1].type), 0x81);
        QCOMPARE(got[1].payload, QByteArray("abc"));
        QCOMPARE(int(got[2].type), 0x02);
        QCOMPARE(got[2].payload, QByteArray(300, 'x'));
        QCOMPARE(reader.buffered(), std::size_t(0));
    }
}

void TestProtocol::readerMessageSplitAcrossAppends() {
    const QByteArray m = frameMessage(0x01, "{\"protocol\":1}");
    for (int cut : {1, 3, 4, 5, 9, int(m.size()) - 1}) {
        MessageReader reader(kMaxClientMessage);
        Message out;
        std::uint32_t length = 0;
        reader.append(m.left(cut));
        QCOMPARE(reader.next(&out, &length), MessageReader::Status::NeedMore);
        QCOMPARE(reader.buffered(), std::size_t(cut));
        reader.append(m.mid(cut));
        QCOMPARE(reader.next(&out, &length), MessageReader::Status::Message);
        QCOMPARE(length, std::uint32_t(m.size() - 4));
        QCOMPARE(int(out.type), 0x01);
        QCOMPARE(out.payload, QByteArray("{\"protocol\":1}"));
    }
}

void TestProtocol::readerOversizeEmptyAndExactMax() {
    Message out;
    std::uint32_t length = 0;
    {  // One byte over: refused from the length field alone, before any payload arrives.
        MessageReader reader(16);
        reader.append(bytes({0, 0, 0, 17}));
        QCOMPARE(reader.next(&out, &length), MessageReader::Status::Oversize);
        QCOMPARE(length, std::uint32_t(17));
    }
    {
        MessageReader reader(kMaxClientMessage);
        reader.append(bytes({0xFF, 0xFF, 0xFF, 0xFF, 0x01}));
        QCOMPARE(reader.next(&out, &length), MessageReader::Status::Oversize);
        QCOMPARE(length, std::uint32_t(0xFFFFFFFF));
    }
    {
        MessageReader reader(kMaxClientMessage);
        reader.append(bytes({0, 0, 0, 0, 0x01}));
        QCOMPARE(reader.next(&out, &length), MessageReader::Status::Empty);
        QCOMPARE(length, std::uint32_t(0));
    }
    {  // Exactly the maximum (the protocol's 65,536) is accepted.
        MessageReader reader(kMaxClientMessage);
        QCOMPARE(kMaxClientMessage, std::uint32_t(65536));
        reader.append(bytes({0x00, 0x01, 0x00, 0x00, 0x02}) + QByteArray(65535, 'v'));
        QCOMPARE(reader.next(&out, &length), MessageReader::Status::Message);
        QCOMPARE(length, std::uint32_t(65536));
        QCOMPARE(out.payload.size(), 65535);
        QCOMPARE(reader.buffered(), std::size_t(0));
    }
}

void TestProtocol::readerLongStream() {
    // 10,000 messages of 4 to 40 payload bytes, each starting with its number: far more
    // than the reader keeps before it drops consumed bytes.
    QByteArray stream;
    const int n = 10000;
    for (int i = 0; i < n; ++i) {
        QByteArray payload;
        pushU32(payload, static_cast<std::uint32_t>(i));
        payload += QByteArray(i % 37, char('a' + i % 26));
        stream += frameMessage(i % 256, payload);
    }
    for (int chunk : {int(stream.size()), 777, 1}) {
        MessageReader reader(kMaxClientMessage);
        int next = 0;
        for (qsizetype at = 0; at < stream.size(); at += chunk) {
            reader.append(stream.mid(at, chunk));
            for (const Message& m : drain(reader)) {
                QCOMPARE(int(m.type), next % 256);
                QCOMPARE(m.payload.size(), 4 + next % 37);
                QCOMPARE(qFromBigEndian<quint32>(m.payload.constData()), quint32(next));
                QCOMPARE(m.payload.back(), next % 37 ? char('a' + next % 26) : char(next & 0xFF));
                ++next;
            }
        }
        QCOMPARE(next, n);
        QCOMPARE(reader.buffered(), std::size_t(0));
    }
}

void TestProtocol::voltagesHandBuiltBytes() {
    QString error;
    auto one = decodeVoltages(kVoltagesRobot2, &error);
    QVERIFY2(one, qPrintable(error));
    QCOMPARE(one->size(), std::size_t(1));
    QCOMPARE((*one)[0].first, 2);
    QCOMPARE((*one)[0].second.right, 1.5);
    QCOMPARE((*one)[0].second.left, -3.25);
    QCOMPARE(encodeVoltages({{2, {1.5, -3.25}}}), kVoltagesRobot2);

    // NaN (0x7FF8...), +inf (0x7FF0...), -inf (0xFFF0...) pass: decode checks the layout only.
    const QByteArray special = bytes({0x02, 0x00, 0x7F, 0xF8, 0, 0, 0, 0, 0, 0,    0x7F, 0xF0, 0, 0, 0, 0, 0, 0,
                                      0xFF, 0xFF, 0xF0, 0,    0, 0, 0, 0, 0, 0x80, 0,    0,    0, 0, 0, 0, 0});
    auto two = decodeVoltages(special, &error);
    QVERIFY2(two, qPrintable(error));
    QCOMPARE(two->size(), std::size_t(2));
    QCOMPARE((*two)[0].first, 0);
    QVERIFY(std::isnan((*two)[0].second.right));
    QCOMPARE((*two)[0].second.left, kInf);
    QCOMPARE((*two)[1].first, 255);
    QCOMPARE((*two)[1].second.right, -kInf);
    QCOMPARE((*two)[1].second.left, 0.0);
    QVERIFY(std::signbit((*two)[1].second.left));  // -0.0 kept bit for bit

    // The largest count, 255.
    const QByteArray full = bytes({0xFF}) + QByteArray(17 * 255, '\0');
    auto many = decodeVoltages(full, &error);
    QVERIFY2(many, qPrintable(error));
    QCOMPARE(many->size(), std::size_t(255));
}

void TestProtocol::voltagesBadSizes_data() {
    QTest::addColumn<QByteArray>("payload");
    QTest::addColumn<QStringList>("mentions");
    QTest::newRow("no bytes") << QByteArray() << QStringList{"empty"};
    QTest::newRow("count 0") << bytes({0x00}) << QStringList{"count is 0"};
    QTest::newRow("count 0, entry") << kVoltagesRobot2.mid(1).prepend('\0') << QStringList{"count is 0"};
    QTest::newRow("count 2, 17 bytes") << bytes({0x02}) + QByteArray(16, '\0') << QStringList{"2 entries", "35", "17"};
    QTest::newRow("one extra byte") << kVoltagesRobot2 + bytes({0x00}) << QStringList{"1 entries", "18", "19"};
    QTest::newRow("one short") << kVoltagesRobot2.chopped(1) << QStringList{"18", "17"};
}

void TestProtocol::voltagesBadSizes() {
    QFETCH(QByteArray, payload);
    QFETCH(QStringList, mentions);
    QString error;
    QVERIFY(!decodeVoltages(payload, &error));
    for (const QString& m : mentions) QVERIFY2(error.contains(m), qPrintable(error));
}

void TestProtocol::frameHandBuiltBytes() {
    FrameHeader h;
    std::vector<FramePatch> patches;
    QString error;
    QVERIFY2(decodeFrame(kFramePayload, &h, &patches, &error), qPrintable(error));
    QCOMPARE(h.frame, std::uint32_t(0x01020304));
    QCOMPARE(h.time, 2.5);
    QCOMPARE(h.kind, FrameKind::Patches);
    QCOMPARE(h.encoding, ImageEncoding::Jpeg);
    QCOMPARE(patches.size(), std::size_t(2));
    QCOMPARE(patches[0].x, 258);
    QCOMPARE(patches[0].y, 3);
    QCOMPARE(patches[0].w, 4);
    QCOMPARE(patches[0].h, 5);
    QCOMPARE(patches[0].data, (std::vector<std::uint8_t>{9, 8, 7}));
    QCOMPARE(patches[1].x, 640);
    QCOMPARE(patches[1].y, 480);
    QCOMPARE(patches[1].w, 0);
    QVERIFY(patches[1].data.empty());
    QCOMPARE(encodeFrame(h, patches), kFramePayload);

    // Kind at offset 12, encoding at 13 (documented codes), count at 14.
    const QByteArray bg = encodeFrame({7, 0.0, FrameKind::Background, ImageEncoding::Png}, {});
    QCOMPARE(bg, bytes({0, 0, 0, 7, 0, 0, 0, 0, 0, 0, 0, 0, 2, 1, 0, 0}));
    const QByteArray full = encodeFrame({0, 0.0, FrameKind::Full, ImageEncoding::Raw}, {});
    QCOMPARE(int(full[12]), 1);
    QCOMPARE(int(full[13]), 0);
    QCOMPARE(int(encodingCode(ImageEncoding::Raw)), 0);
    QCOMPARE(int(encodingCode(ImageEncoding::Png)), 1);
    QCOMPARE(int(encodingCode(ImageEncoding::Jpeg)), 2);
}

void TestProtocol::frameRoundTrip() {
    std::vector<FramePatch> patches(4);
    patches[0] = {0, 0, 2, 1, {1, 2, 3, 4, 5, 6}};
    patches[1] = {0, 0, 0, 0, {}};  // a body outside the image
    patches[2] = {65535, 639, 1, 1, std::vector<std::uint8_t>(1000, 0xAB)};
    patches[3] = {12, 34, 56, 78, {0x00, 0xFF}};
    const FrameHeader h{0xFFFFFFFFu, 1.0 / 3.0, FrameKind::Full, ImageEncoding::Raw};
    const QByteArray payload = encodeFrame(h, patches);
    QCOMPARE(payload.size(), 16 + 4 * 12 + 6 + 0 + 1000 + 2);
    FrameHeader back;
    std::vector<FramePatch> got{FramePatch{}};  // stale contents are replaced
    QString error;
    QVERIFY2(decodeFrame(payload, &back, &got, &error), qPrintable(error));
    QCOMPARE(back.frame, h.frame);
    QCOMPARE(back.time, h.time);
    QCOMPARE(back.kind, h.kind);
    QCOMPARE(back.encoding, h.encoding);
    QCOMPARE(got.size(), patches.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        QCOMPARE(got[i].x, patches[i].x);
        QCOMPARE(got[i].y, patches[i].y);
        QCOMPARE(got[i].w, patches[i].w);
        QCOMPARE(got[i].h, patches[i].h);
        QCOMPARE(got[i].data, patches[i].data);
    }
}

void TestProtocol::frameTruncatedAtEveryLength() {
    for (int cut = 0; cut < kFramePayload.size(); ++cut) {
        FrameHeader h;
        std::vector<FramePatch> patches;
        QString error;
        QVERIFY2(!decodeFrame(kFramePayload.left(cut), &h, &patches, &error), qPrintable(QString::number(cut)));
        QVERIFY2(!error.isEmpty(), qPrintable(QString::number(cut)));
    }
}

void TestProtocol::frameBadPatchLengthTrailingBytesKindEncoding() {
    FrameHeader h;
    std::vector<FramePatch> patches;
    QString error;
    // The first patch declares 4 bytes; 3 follow and nothing else.
    QByteArray overlong = kFramePayload.left(31);
    overlong[14] = 0;
    overlong[15] = 1;
    overlong[27] = 4;
    QVERIFY(!decodeFrame(overlong, &h, &patches, &error));
    QVERIFY2(error.contains("declares 4 bytes, 3 left"), qPrintable(error));
    QByteArray huge = overlong;  // 0xFFFFFFFF bytes: no overflow, no allocation
    huge[24] = huge[25] = huge[26] = huge[27] = char(0xFF);
    QVERIFY(!decodeFrame(huge, &h, &patches, &error));

    QVERIFY(!decodeFrame(kFramePayload + bytes({0x00}), &h, &patches, &error));
    QVERIFY2(error.contains("1 bytes left over"), qPrintable(error));

    for (auto [offset, value] : {std::pair{12, 3}, std::pair{12, 0xFF}, std::pair{13, 3}, std::pair{13, 0x80}}) {
        QByteArray bad = kFramePayload;
        bad[offset] = char(value);
        error.clear();
        QVERIFY2(!decodeFrame(bad, &h, &patches, &error), qPrintable(QString("byte %1 = %2").arg(offset).arg(value)));
        QVERIFY(error.contains("unknown kind"));
    }
}

void TestProtocol::parseJsonObjectErrors() {
    for (const char* text : {"", "{", "{\"a\": }", "[1, 2]", "42", "\"text\"", "null",
                             "{\"x\": 1e400}"}) {  // out of range: the parser refuses, no infinity gets through
        QString error;
        QVERIFY2(!parseJsonObject(text, &error), text);
        QVERIFY2(!error.isEmpty(), text);
    }
    QString error;
    const auto ok = parseJsonObject("{\"a\": [1, {\"b\": null}]}", &error);
    QVERIFY(ok);
    QCOMPARE(ok->value("a").toArray().size(), 2);
}

void TestProtocol::helloDefaultsRolesAndImages() {
    RequestError error;
    auto h = parseHello(obj(R"({"protocol": 1, "role": "yellow"})"), &error);
    QVERIFY2(h, qPrintable(error.message));
    QCOMPARE(h->role, ClientRole::Yellow);
    QVERIFY(h->name.isEmpty());
    QVERIFY(h->images.has_value());
    QCOMPARE(h->images->kind, FrameKind::Patches);
    QCOMPARE(h->images->encoding, ImageEncoding::Png);
    QCOMPARE(h->images->jpegQuality, 90);
    QCOMPARE(h->state, false);

    for (auto [name, role] : {std::pair{"yellow", ClientRole::Yellow}, std::pair{"blue", ClientRole::Blue},
                              std::pair{"observer", ClientRole::Observer}}) {
        auto r = parseHello(QJsonObject{{"protocol", 1}, {"role", name}}, &error);
        QVERIFY2(r, qPrintable(error.message));
        QCOMPARE(r->role, role);
        QCOMPARE(roleName(role), QString(name));
    }

    h = parseHello(obj(R"({"protocol": 1, "role": "blue", "images": "none", "state": true, "name": "team"})"), &error);
    QVERIFY2(h, qPrintable(error.message));
    QVERIFY(!h->images.has_value());
    QCOMPARE(h->state, true);
    QCOMPARE(h->name, QString("team"));

    h = parseHello(obj(R"({"protocol": 1, "role": "observer", "images": "full", "encoding": "raw"})"), &error);
    QVERIFY2(h, qPrintable(error.message));
    QCOMPARE(h->images->kind, FrameKind::Full);
    QCOMPARE(h->images->encoding, ImageEncoding::Raw);

    h = parseHello(obj(R"({"protocol": 1, "role": "yellow", "encoding": "jpeg", "jpeg_quality": 37})"), &error);
    QVERIFY2(h, qPrintable(error.message));
    QCOMPARE(h->images->encoding, ImageEncoding::Jpeg);
    QCOMPARE(h->images->jpegQuality, 37);
    for (int q : {1, 100}) {
        h = parseHello(QJsonObject{{"protocol", 1}, {"role", "yellow"}, {"encoding", "jpeg"}, {"jpeg_quality", q}},
                       &error);
        QVERIFY2(h, qPrintable(error.message));
        QCOMPARE(h->images->jpegQuality, q);
    }
}

void TestProtocol::helloErrors_data() {
    QTest::addColumn<QString>("json");
    QTest::addColumn<QString>("code");
    QTest::addColumn<QString>("mentions");
    auto row = [](const char* tag, const char* json, const char* code, const char* mentions) {
        QTest::newRow(tag) << QString(json) << QString(code) << QString(mentions);
    };
    row("no protocol", R"({"role": "yellow"})", "malformed", "protocol");
    row("protocol string", R"({"protocol": "1", "role": "yellow"})", "malformed", "protocol");
    row("protocol 2", R"({"protocol": 2, "role": "yellow"})", "unsupported_protocol", "2");
    row("no role", R"({"protocol": 1})", "malformed", "role");
    row("bad role", R"({"protocol": 1, "role": "red"})", "malformed", "role");
    row("unknown key", R"({"protocol": 1, "role": "blue", "colour": "blue"})", "malformed", "\"colour\"");
    row("name not string", R"({"protocol": 1, "role": "blue", "name": 5})", "malformed", "name");
    row("images bad", R"({"protocol": 1, "role": "blue", "images": "some"})", "malformed", "some");
    row("images number", R"({"protocol": 1, "role": "blue", "images": 1})", "malformed", "images");
    row("encoding number", R"({"protocol": 1, "role": "blue", "encoding": 1})", "malformed", "encoding");
    row("encoding bad", R"({"protocol": 1, "role": "blue", "encoding": "gif"})", "malformed", "encoding");
    row("encoding upper", R"({"protocol": 1, "role": "blue", "encoding": "PNG"})", "malformed", "encoding");
    row("quality 0", R"({"protocol": 1, "role": "blue", "jpeg_quality": 0})", "malformed", "jpeg_quality");
    row("quality 101", R"({"protocol": 1, "role": "blue", "jpeg_quality": 101})", "malformed", "jpeg_quality");
    row("quality 90.5", R"({"protocol": 1, "role": "blue", "jpeg_quality": 90.5})", "malformed", "90.5");
    row("quality string", R"({"protocol": 1, "role": "blue", "jpeg_quality": "90"})", "malformed", "jpeg_quality");
    row("state string", R"({"protocol": 1, "role": "blue", "state": "yes"})", "malformed", "state");
    row("state number", R"({"protocol": 1, "role": "blue", "state": 1})", "malformed", "state");
}

void TestProtocol::helloErrors() {
    QFETCH(QString, json);
    QFETCH(QString, code);
    QFETCH(QString, mentions);
    RequestError error;
    QVERIFY(!parseHello(obj(json.toUtf8().constData()), &error));
    QCOMPARE(error.code, code);
    QVERIFY2(error.message.contains(mentions), qPrintable(error.message));
}

void TestProtocol::helloNameIsSanitised() {
    RequestError error;
    auto h = parseHello(QJsonObject{{"protocol", 1},
                                    {"role", "yellow"},
                                    {"name",
                                     "a\nb\tc\x01"
                                     "d\x7f"
                                     "é"}},
                        &error);
    QVERIFY2(h, qPrintable(error.message));
    QCOMPARE(h->name, QString::fromUtf8("a?b?c?d?é"));
    QVERIFY(parseHello(QJsonObject{{"protocol", 1}, {"role", "yellow"}, {"name", QString(64, 'n')}}, &error));
    QVERIFY(!parseHello(QJsonObject{{"protocol", 1}, {"role", "yellow"}, {"name", QString(65, 'n')}}, &error));
    QCOMPARE(error.code, QString("malformed"));
    QVERIFY(error.message.contains("64"));
}

void TestProtocol::checkVoltagesTeamsAndValues() {
    const Scene scene = fourRobotScene();
    using Entries = std::vector<std::pair<int, Voltages>>;
    // "code: message", or "none" when the entries pass.
    auto check = [&](const Entries& entries, ClientRole role) {
        const auto err = checkVoltages(entries, scene, role);
        return err ? err->code + ": " + err->message : QString("none");
    };
    auto says = [](const QString& got, const QString& code, QStringList mentions) {
        if (!got.startsWith(code + ": ")) return false;
        for (const QString& m : mentions)
            if (!got.contains(m)) return false;
        return true;
    };
    QCOMPARE(check({{0, {1, 2}}, {1, {-7.4, 100}}}, ClientRole::Yellow), QString("none"));
    QCOMPARE(check({{3, {0, 0}}, {2, {-1e9, 1e9}}, {3, {1, 1}}}, ClientRole::Blue), QString("none"));

    QString got = check({{0, {1, 1}}}, ClientRole::Observer);
    QVERIFY2(says(got, "not_your_robot", {"observer"}), qPrintable(got));
    got = check({{0, {1, 1}}, {2, {1, 1}}}, ClientRole::Yellow);
    QVERIFY2(says(got, "not_your_robot", {"entry 1", "robot 2", "blue0"}), qPrintable(got));
    got = check({{1, {1, 1}}}, ClientRole::Blue);
    QVERIFY2(says(got, "not_your_robot", {"entry 0", "yellow1"}), qPrintable(got));

    for (int robot : {4, -1, 255}) {
        got = check({{robot, {0, 0}}}, ClientRole::Yellow);
        QVERIFY2(says(got, "bad_robot", {QString("robot %1").arg(robot), "0 to 3"}), qPrintable(got));
    }

    for (double bad : {kNaN, kInf, -kInf}) {
        got = check({{2, {0, 0}}, {3, {1, bad}}}, ClientRole::Blue);
        QVERIFY2(says(got, "not_finite", {"entry 1", "robot 3", "left"}), qPrintable(got));
        got = check({{0, {bad, 1}}}, ClientRole::Yellow);
        QVERIFY2(says(got, "not_finite", {"entry 0", "robot 0", "right"}), qPrintable(got));
    }

    // The first bad entry is the one reported.
    got = check({{0, {1, 1}}, {1, {kNaN, 0}}, {9, {0, 0}}}, ClientRole::Yellow);
    QVERIFY2(says(got, "not_finite", {"entry 1"}), qPrintable(got));
    got = check({{9, {0, 0}}, {2, {0, 0}}, {1, {kNaN, 0}}}, ClientRole::Yellow);
    QVERIFY2(says(got, "bad_robot", {"entry 0"}), qPrintable(got));
    got = check({{1, {0, 0}}, {3, {kInf, 0}}, {7, {0, 0}}}, ClientRole::Yellow);
    QVERIFY2(says(got, "not_your_robot", {"entry 1"}), qPrintable(got));
}

void TestProtocol::controlCommands() {
    using Kind = EngineRequest::Kind;
    const Scene scene = fourRobotScene();
    RequestError error;
    for (auto [name, kind] : {std::pair{"pause", Kind::Pause}, std::pair{"resume", Kind::Resume},
                              std::pair{"reset", Kind::Reset}, std::pair{"stats", Kind::Stats}}) {
        auto r = parseControl(QJsonObject{{"command", name}, {"id", QJsonArray{1}}}, scene, &error);
        QVERIFY2(r, qPrintable(error.message));
        QCOMPARE(r->kind, kind);
        QCOMPARE(r->command, QString(name));
    }
    auto r = parseControl(obj(R"({"command": "step", "duration": 0.03, "id": 7})"), scene, &error);
    QVERIFY2(r, qPrintable(error.message));
    QCOMPARE(r->kind, Kind::Step);
    QCOMPARE(r->duration, 0.03);
    r = parseControl(obj(R"({"command": "step", "duration": 3600})"), scene, &error);
    QVERIFY2(r, qPrintable(error.message));
    QCOMPARE(r->duration, 3600.0);

    r = parseControl(
        obj(R"({"command": "place_robot", "robot": 3, "x": -0.5, "y": 0.25, "theta": 2, "v": 0.3, "omega": -4})"),
        scene, &error);
    QVERIFY2(r, qPrintable(error.message));
    QCOMPARE(r->kind, Kind::PlaceRobot);
    QCOMPARE(r->robot, 3);
    QCOMPARE(r->robotPose.x, -0.5);
    QCOMPARE(r->robotPose.y, 0.25);
    QCOMPARE(r->robotPose.theta, 2.0);
    QCOMPARE(r->robotPose.v, 0.3);
    QCOMPARE(r->robotPose.omega, -4.0);
    r = parseControl(obj(R"({"command": "place_robot", "robot": 0, "x": 0.1, "y": 0, "theta": 0})"), scene, &error);
    QVERIFY2(r, qPrintable(error.message));
    QCOMPARE(r->robotPose.v, 0.0);
    QCOMPARE(r->robotPose.omega, 0.0);

    r = parseControl(obj(R"({"command": "place_ball", "x": 0.2, "y": -0.3, "vx": 1.5, "vy": -0.5})"), scene, &error);
    QVERIFY2(r, qPrintable(error.message));
    QCOMPARE(r->kind, Kind::PlaceBall);
    QCOMPARE(r->ball.x, 0.2);
    QCOMPARE(r->ball.y, -0.3);
    QCOMPARE(r->ball.vx, 1.5);
    QCOMPARE(r->ball.vy, -0.5);
    // The ball's centre may come within one radius (0.02135 m) of the walls.
    QVERIFY(parseControl(QJsonObject{{"command", "place_ball"}, {"x", 0.75 - 0.02135}, {"y", -(0.65 - 0.02135)}}, scene,
                         &error));

    r = parseControl(obj(R"({"command": "speed", "speed": 2.5})"), scene, &error);
    QVERIFY2(r, qPrintable(error.message));
    QCOMPARE(r->kind, Kind::Speed);
    QCOMPARE(r->speed, 2.5);
    r = parseControl(obj(R"({"command": "speed", "speed": "max"})"), scene, &error);
    QVERIFY2(r, qPrintable(error.message));
    QCOMPARE(r->speed, 0.0);
}

void TestProtocol::controlPlaceRobotBoundary() {
    // Side 0.075 m: at heading 0 the robot reaches 0.0375 m from its centre
    // along x and y; at heading pi/4, 0.0375 sqrt(2) m.
    const Scene scene = fourRobotScene();
    RequestError error;
    auto place = [&](double x, double y, double theta) {
        return parseControl(QJsonObject{{"command", "place_robot"}, {"robot", 1}, {"x", x}, {"y", y}, {"theta", theta}},
                            scene, &error)
            .has_value();
    };
    const double edgeX = 0.75 - 0.0375, edgeY = 0.65 - 0.0375;
    QVERIFY(place(edgeX, 0, 0));
    QVERIFY(place(-edgeX, -edgeY, 0));
    QVERIFY(!place(edgeX + 1e-12, 0, 0));  // touching counts as inside to 1e-13 m (vssim/field.h)
    QCOMPARE(error.code, QString("outside_field"));
    QVERIFY(!place(0, -edgeY - 1e-12, 0));
    QCOMPARE(error.code, QString("outside_field"));
    const double quarter = std::atan(1.0);
    const double diagonal = 0.75 - 0.0375 * std::sqrt(2.0);
    QVERIFY(place(diagonal - 1e-12, 0, quarter));
    QVERIFY(!place(diagonal + 1e-12, 0, quarter));
    QCOMPARE(error.code, QString("outside_field"));
    QVERIFY(!place(edgeX, 0, quarter));  // inside at heading 0, not turned
    QVERIFY(place(edgeX, 0, 2 * quarter));
}

void TestProtocol::controlErrors_data() {
    QTest::addColumn<QString>("json");
    QTest::addColumn<QString>("code");
    QTest::addColumn<QString>("mentions");
    auto row = [](const char* tag, const char* json, const char* code, const char* mentions) {
        QTest::newRow(tag) << QString(json) << QString(code) << QString(mentions);
    };
    row("no command", R"({"id": 1})", "malformed", "command");
    row("command number", R"({"command": 3})", "malformed", "command");
    row("unknown command", R"({"command": "jump"})", "unknown_command", "jump");
    row("unknown key", R"({"command": "pause", "force": true})", "malformed", "\"force\"");
    row("step unknown key", R"({"command": "step", "duration": 1, "dt": 1})", "malformed", "\"dt\"");
    row("step no duration", R"({"command": "step"})", "malformed", "duration");
    row("step 0", R"({"command": "step", "duration": 0})", "malformed", "duration");
    row("step -1", R"({"command": "step", "duration": -1})", "malformed", "duration");
    row("step 3601", R"({"command": "step", "duration": 3601})", "malformed", "3601");
    row("step abc", R"({"command": "step", "duration": "abc"})", "malformed", "duration");
    row("robot 1.5", R"({"command": "place_robot", "robot": 1.5, "x": 0, "y": 0, "theta": 0})", "bad_robot", "1.5");
    row("robot -1", R"({"command": "place_robot", "robot": -1, "x": 0, "y": 0, "theta": 0})", "bad_robot", "-1");
    row("robot 4", R"({"command": "place_robot", "robot": 4, "x": 0, "y": 0, "theta": 0})", "bad_robot", "0 to 3");
    row("robot string", R"({"command": "place_robot", "robot": "0", "x": 0, "y": 0, "theta": 0})", "malformed",
        "robot");
    row("robot no theta", R"({"command": "place_robot", "robot": 0, "x": 0, "y": 0})", "malformed", "theta");
    row("robot v string", R"({"command": "place_robot", "robot": 0, "x": 0, "y": 0, "theta": 0, "v": "1"})",
        "malformed", "\"v\"");
    row("robot outside", R"({"command": "place_robot", "robot": 0, "x": 0, "y": 0.7, "theta": 0})", "outside_field",
        "robot 0");
    row("ball outside", R"({"command": "place_ball", "x": 0.74, "y": 0})", "outside_field", "ball");
    row("ball far", R"({"command": "place_ball", "x": 0, "y": -3})", "outside_field", "ball");
    row("ball no y", R"({"command": "place_ball", "x": 0})", "malformed", "\"y\"");
    row("ball key", R"({"command": "place_ball", "x": 0, "y": 0, "robot": 1})", "malformed", "\"robot\"");
    // The game's commands.
    row("halt key", R"({"command": "halt", "team": "yellow"})", "malformed", "\"team\"");
    row("call nothing", R"({"command": "call"})", "malformed", "\"call\"");
    row("call unknown", R"({"command": "call", "call": "free_kick", "team": "blue"})", "malformed", "free_kick");
    row("call no team", R"({"command": "call", "call": "penalty_kick"})", "malformed", "\"team\"");
    row("call bad team", R"({"command": "call", "call": "kickoff", "team": "red"})", "malformed", "red");
    row("call quadrant of a kick-off", R"({"command": "call", "call": "kickoff", "team": "blue", "quadrant": 1})",
        "malformed", "only a free ball");
    row("free ball without quadrant", R"({"command": "call", "call": "free_ball"})", "malformed", "quadrant");
    row("free ball quadrant 5", R"({"command": "call", "call": "free_ball", "quadrant": 5})", "malformed", "1 to 4");
    row("free ball for a team", R"({"command": "call", "call": "free_ball", "quadrant": 2, "team": "blue"})",
        "malformed", "no team");
    row("speed 0", R"({"command": "speed", "speed": 0})", "malformed", "speed");
    row("speed -1", R"({"command": "speed", "speed": -1})", "malformed", "speed");
    row("speed fast", R"({"command": "speed", "speed": "fast"})", "malformed", "speed");
    row("speed 2e6", R"({"command": "speed", "speed": 2e6})", "malformed", "speed");
    row("speed 101", R"({"command": "speed", "speed": 101})", "malformed", "100");
    row("speed 0.0005", R"({"command": "speed", "speed": 0.0005})", "malformed", "0.001");
    row("robot v 11", R"({"command": "place_robot", "robot": 0, "x": 0, "y": 0, "theta": 0, "v": 11})", "malformed",
        "10 m/s");
    row("robot omega -101", R"({"command": "place_robot", "robot": 0, "x": 0, "y": 0, "theta": 0, "omega": -101})",
        "malformed", "100 rad/s");
    row("ball 20.1 m/s", R"({"command": "place_ball", "x": 0, "y": 0, "vx": 12, "vy": 16.1})", "malformed", "20 m/s");
    row("speed missing", R"({"command": "speed"})", "malformed", "speed");
}

void TestProtocol::controlErrors() {
    QFETCH(QString, json);
    QFETCH(QString, code);
    QFETCH(QString, mentions);
    RequestError error;
    QVERIFY(!parseControl(obj(json.toUtf8().constData()), fourRobotScene(), &error));
    QCOMPARE(error.code, code);
    QVERIFY2(error.message.contains(mentions), qPrintable(error.message));
}

void TestProtocol::gameControlCommands() {
    const Scene scene = fourRobotScene();
    RequestError error;
    auto parse = [&](const char* json) { return parseControl(obj(json), scene, &error); };
    const auto halt = parse(R"({"command": "halt", "id": 4})");
    QVERIFY2(halt, qPrintable(error.message));
    QCOMPARE(halt->kind, EngineRequest::Kind::HaltGame);
    const auto on = parse(R"({"command": "game_on"})");
    QVERIFY2(on, qPrintable(error.message));
    QCOMPARE(on->kind, EngineRequest::Kind::ResumeGame);
    const auto penalty = parse(R"({"command": "call", "call": "penalty_kick", "team": "blue"})");
    QVERIFY2(penalty, qPrintable(error.message));
    QCOMPARE(penalty->kind, EngineRequest::Kind::CallFoul);
    QCOMPARE(penalty->call, Call::PenaltyKick);
    QCOMPARE(penalty->team, Team::Blue);
    const auto freeBall = parse(R"({"command": "call", "call": "free_ball", "quadrant": 3})");
    QVERIFY2(freeBall, qPrintable(error.message));
    QCOMPARE(freeBall->call, Call::FreeBall);
    QCOMPARE(freeBall->quadrant, 3);
    // Only `stats` leaves the game alone: a read-only observer may not halt, resume or call.
    QVERIFY(!leavesTheGameAlone(*halt) && !leavesTheGameAlone(*on) && !leavesTheGameAlone(*penalty));
}

void TestProtocol::placementChecks() {
    const Scene scene = fourRobotScene();
    RequestError error;
    const auto r = parsePlacement(
        obj(R"({"id": 9, "robots": [{"robot": 1, "x": -0.3, "y": 0.2, "theta": 1.5}, {"robot": 0, "x": -0.5, "y": 0, "theta": 0}]})"),
        scene, ClientRole::Yellow, &error);
    QVERIFY2(r, qPrintable(error.message));
    QCOMPARE(r->kind, EngineRequest::Kind::Placement);
    QCOMPARE(r->team, Team::Yellow);
    QCOMPARE(r->poses.size(), std::size_t(2));
    QCOMPARE(r->poses[0].first, 1);
    QCOMPARE(r->poses[0].second.x, -0.3);
    QCOMPARE(r->poses[0].second.theta, 1.5);
    QCOMPARE(r->poses[1].first, 0);
    // Blue places blue robots.
    QVERIFY(parsePlacement(obj(R"({"robots": [{"robot": 3, "x": 0.3, "y": 0, "theta": 3}]})"), scene, ClientRole::Blue,
                           &error));
    // Non-finite numbers, which JSON text cannot carry but a QJsonObject can.
    for (double bad : {kNaN, kInf, -kInf}) {
        const QJsonObject json{
            {"robots", QJsonArray{QJsonObject{{"robot", 0}, {"x", bad}, {"y", 0.0}, {"theta", 0.0}}}}};
        QVERIFY(!parsePlacement(json, scene, ClientRole::Yellow, &error));
        QCOMPARE(error.code, QString("malformed"));
        QVERIFY2(error.message.startsWith("PLACEMENT robots[0]: ") && error.message.contains("\"x\""),
                 qPrintable(error.message));
    }
}

void TestProtocol::placementErrors_data() {
    QTest::addColumn<QString>("json");
    QTest::addColumn<QString>("role");
    QTest::addColumn<QString>("code");
    QTest::addColumn<QString>("mentions");
    auto row = [](const char* tag, const char* json, const char* role, const char* code, const char* mentions) {
        QTest::newRow(tag) << QString(json) << QString(role) << QString(code) << QString(mentions);
    };
    const char* one = R"({"robots": [{"robot": 0, "x": -0.3, "y": 0, "theta": 0}]})";
    row("observer", one, "observer", "not_your_robot", "observer");
    row("other team's robot", one, "blue", "not_your_robot", "robot 0 (yellow0) belongs to the other team");
    row("no robots", R"({"id": 1})", "yellow", "malformed", "\"robots\"");
    row("robots empty", R"({"robots": []})", "yellow", "malformed", "non-empty array");
    row("robots not an array", R"({"robots": {"robot": 0}})", "yellow", "malformed", "non-empty array");
    row("unknown key", R"({"robots": [{"robot": 0, "x": 0, "y": 0, "theta": 0}], "team": "yellow"})", "yellow",
        "malformed", "\"team\"");
    row("entry not an object", R"({"robots": [3]})", "yellow", "malformed", "robots[0]: expected an object");
    row("unknown robot", R"({"robots": [{"robot": 7, "x": 0, "y": 0, "theta": 0}]})", "yellow", "bad_robot",
        "no robot 7 (the scene has robots 0 to 3)");
    row("robot not a number", R"({"robots": [{"robot": "yellow0", "x": 0, "y": 0, "theta": 0}]})", "yellow",
        "malformed", "\"robot\"");
    row("no theta", R"({"robots": [{"robot": 0, "x": -0.3, "y": 0}]})", "yellow", "malformed", "theta");
    row("x a string", R"({"robots": [{"robot": 0, "x": "NaN", "y": 0, "theta": 0}]})", "yellow", "malformed",
        "\"x\" must be a finite number");
    row("entry key", R"({"robots": [{"robot": 0, "x": -0.3, "y": 0, "theta": 0, "v": 1}]})", "yellow", "malformed",
        "\"v\"");
    row("twice",
        R"({"robots": [{"robot": 1, "x": -0.3, "y": 0, "theta": 0}, {"robot": 1, "x": -0.5, "y": 0, "theta": 0}]})",
        "yellow", "malformed", "robots[1]: robot 1 is placed twice");
    row("outside", R"({"robots": [{"robot": 0, "x": -0.74, "y": 0, "theta": 0}]})", "yellow", "outside_field",
        "robots[0]: robot 0 at (-0.74, 0) m");
    row("too many", R"({"robots": [{}, {}, {}, {}, {}]})", "yellow", "malformed", "5 entries");
}

void TestProtocol::placementErrors() {
    QFETCH(QString, json);
    QFETCH(QString, role);
    QFETCH(QString, code);
    QFETCH(QString, mentions);
    RequestError error;
    const ClientRole r = role == "yellow" ? ClientRole::Yellow
                         : role == "blue" ? ClientRole::Blue
                                          : ClientRole::Observer;
    QVERIFY(!parsePlacement(obj(json.toUtf8().constData()), fourRobotScene(), r, &error));
    QCOMPARE(error.code, code);
    QVERIFY2(error.message.startsWith("PLACEMENT"), qPrintable(error.message));
    QVERIFY2(error.message.contains(mentions), qPrintable(error.message));
}

void TestProtocol::controlNonFiniteNumbers() {
    // JSON text cannot carry them, but a QJsonObject can: the checks do not rely on the parser.
    const Scene scene = fourRobotScene();
    RequestError error;
    for (double bad : {kNaN, kInf, -kInf}) {
        const QJsonObject objects[] = {
            {{"command", "step"}, {"duration", bad}},
            {{"command", "speed"}, {"speed", bad}},
            {{"command", "place_robot"}, {"robot", 0}, {"x", bad}, {"y", 0}, {"theta", 0}},
            {{"command", "place_robot"}, {"robot", 0}, {"x", 0}, {"y", 0}, {"theta", bad}},
            {{"command", "place_robot"}, {"robot", 0}, {"x", 0}, {"y", 0}, {"theta", 0}, {"omega", bad}},
            {{"command", "place_robot"}, {"robot", bad}, {"x", 0}, {"y", 0}, {"theta", 0}},
            {{"command", "place_ball"}, {"x", 0}, {"y", bad}},
            {{"command", "place_ball"}, {"x", 0}, {"y", 0}, {"vx", bad}},
        };
        for (const QJsonObject& o : objects) {
            error = {};
            QVERIFY2(!parseControl(o, scene, &error), QJsonDocument(o).toJson(QJsonDocument::Compact).constData());
            QCOMPARE(error.code, QString("malformed"));
        }
    }
}

// Cases from a review: names count characters (not UTF-16 units), the
// version is checked before the keys, non-finite volts are named in words,
// and the encoder refuses what the one-byte fields cannot carry.
void TestProtocol::reviewFindings() {
    RequestError error;
    QString emoji;
    for (int i = 0; i < 64; ++i) emoji += QString::fromUtf8("\xF0\x9F\x98\x80");  // U+1F600, two UTF-16 units
    auto h = parseHello(QJsonObject{{"protocol", 1}, {"role", "blue"}, {"name", emoji}}, &error);
    QVERIFY2(h, qPrintable(error.message));
    QCOMPARE(h->name, emoji);
    QVERIFY(!parseHello(QJsonObject{{"protocol", 1}, {"role", "blue"}, {"name", emoji + "x"}}, &error));
    QVERIFY(!parseHello(QJsonObject{{"protocol", 2}, {"role", "blue"}, {"new_key", 1}}, &error));
    QCOMPARE(error.code, QString("unsupported_protocol"));
    const auto nan = checkVoltages({{0, {std::nan(""), 0.0}}}, fourRobotScene(), ClientRole::Yellow);
    QVERIFY(nan && nan->message.endsWith("is NaN"));
    const auto inf = checkVoltages({{0, {0.0, -HUGE_VAL}}}, fourRobotScene(), ClientRole::Yellow);
    QVERIFY(inf && inf->message.endsWith("is -infinity"));
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument,
                             protocol::encodeVoltages(std::vector<std::pair<int, Voltages>>(256, {0, Voltages{}})));
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, protocol::encodeVoltages({{256, Voltages{}}}));
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, protocol::encodeVoltages({}));
}

// A client's words reach log lines through error messages: a command name or
// key with a newline or ESC must not forge a line or a terminal sequence.
void TestProtocol::messagesCarryNoControlCharacters() {
    const Scene scene = fourRobotScene();
    auto clean = [](const QString& message) {
        for (QChar c : message)
            if (!c.isPrint()) return false;
        return true;
    };
    RequestError error;
    QVERIFY(!parseControl(QJsonObject{{"command", "pause\nvssim: server stopped\x1b[2J"}}, scene, &error));
    QCOMPARE(error.code, QString("unknown_command"));
    QVERIFY2(clean(error.message) && error.message.contains("pause?vssim: server stopped?[2J"),
             qPrintable(error.message));
    QVERIFY(!parseControl(QJsonObject{{"command", "pause"}, {"x\ny", 1}}, scene, &error));
    QVERIFY2(clean(error.message) && error.message.contains("\"x?y\""), qPrintable(error.message));
    QVERIFY(!parseControl(QJsonObject{{"command", QString(500, 'a')}}, scene, &error));
    QVERIFY2(error.message.size() < 200 && error.message.contains(QString(40, 'a') + "..."), qPrintable(error.message));
    QVERIFY(!parseHello(QJsonObject{{"protocol", 1}, {"role", "yellow\r\n"}}, &error));
    QVERIFY2(clean(error.message) && error.message.contains("\"yellow??\""), qPrintable(error.message));
    // A step is bounded in steps of dt too: with dt = 1 us, 10 s is ten million steps.
    Scene fine = scene;
    fine.simulation.dt = 1e-6;
    QVERIFY(parseControl(QJsonObject{{"command", "step"}, {"duration", 3.6}}, fine, &error));
    QVERIFY(!parseControl(QJsonObject{{"command", "step"}, {"duration", 10.0}}, fine, &error));
    QVERIFY2(error.code == "malformed" && error.message.contains("3600000 steps"), qPrintable(error.message));
    // The value as given, not rounded to six digits.
    QVERIFY(!parseControl(QJsonObject{{"command", "step"}, {"duration", 3600.0001}}, scene, &error));
    QVERIFY2(error.message.contains("3600.0001 s"), qPrintable(error.message));
}

void TestProtocol::printableTextCatchesEveryLineBreaker() {
    // C0 controls, DEL, C1 (NEL, U+0085), the line and paragraph separators
    // (which Qt calls printable) and format characters (U+202E turns the
    // rest of a line around): each a "?"; letters and symbols stay.
    const QString text = QString::fromUtf8("a\nb\rc\x1b[31md\x7f") + QChar(0x85) + QChar(0x2028) + QChar(0x2029) +
                         QChar(0x202E) + QString::fromUtf8("é😀");
    QCOMPARE(printableText(text, 100), QString::fromUtf8("a?b?c?[31md?????é😀"));
    // Cut by characters, not UTF-16 units.
    QCOMPARE(printableText(QString::fromUtf8("😀😀😀"), 2), QString::fromUtf8("😀😀..."));
}

void TestProtocol::portsAndAddresses() {
    QCOMPARE(parsePort("0"), std::optional<quint16>(0));
    QCOMPARE(parsePort("65535"), std::optional<quint16>(65535));
    QVERIFY(!parsePort("65536") && !parsePort("-1") && !parsePort("x") && !parsePort(""));
    const auto full = parseHostPort("10.0.0.7:10030");
    QVERIFY(full && full->host == "10.0.0.7" && full->port == 10030);
    const auto bare = parseHostPort("10031");
    QVERIFY(bare && bare->host == "127.0.0.1" && bare->port == 10031);
    const auto v6 = parseHostPort("::1:9000");
    QVERIFY(v6 && v6->host == "::1" && v6->port == 9000);
    QVERIFY(!parseHostPort("host:0") && !parseHostPort("host:70000") && !parseHostPort(":10030") &&
            !parseHostPort("host:"));
}

QTEST_APPLESS_MAIN(TestProtocol)
#include "test_protocol.moc"
