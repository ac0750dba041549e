#include "realtime/frame_encoder.h"

#include "vssim/camera/image_codec.h"
#include "realtime/monotonic_clock.h"
#include "wire/protocol.h"

namespace vssim {

QString subscriptionName(const ImageSubscription& s) {
    QString name = s.kind == protocol::FrameKind::Full ? QStringLiteral("full/") : QStringLiteral("patches/");
    name += encodingName(s.encoding);
    if (s.encoding == ImageEncoding::Jpeg) name += QString::number(s.jpegQuality);
    return name;
}

FrameEncoder::FrameEncoder(std::function<void(std::shared_ptr<const FramePacket>, std::optional<EngineReply>)> deliver)
    : deliver_(std::move(deliver)), thread_([this] { run(); }) {}

FrameEncoder::~FrameEncoder() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
}

void FrameEncoder::submit(EncodeJob job) {
    {
        std::lock_guard lock(mutex_);
        jobs_.push_back(std::move(job));
    }
    wake_.notify_one();
}

void FrameEncoder::run() {
    for (;;) {
        EncodeJob job;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || !jobs_.empty(); });
            if (jobs_.empty()) return;  // stopping, and nothing left
            job = std::move(jobs_.front());
            jobs_.pop_front();
        }
        if (job.reply) {
            EngineReply reply = std::move(*job.reply);
            if (reply.stats) {
                for (const auto& [name, samples] : encodeMs_) reply.stats->encodeMs[name] = samples.summary();
                for (const auto& [name, samples] : frameBytes_) reply.stats->frameBytes[name] = samples.summary();
            }
            deliver_(nullptr, std::move(reply));
            continue;
        }
        deliver_(encode(job), std::nullopt);
    }
}

std::shared_ptr<const FramePacket> FrameEncoder::encode(const EncodeJob& job) {
    auto packet = std::make_shared<FramePacket>();
    packet->frame = job.frame;
    packet->time = job.time;
    packet->instantNs = job.instantNs;
    packet->state = job.state;
    packet->stateJson = job.stateJson;
    const PngDeflate png = job.noisy ? PngDeflate::Stored : PngDeflate::Fast;
    for (const ImageSubscription& s : job.subscriptions) {
        const std::int64_t startNs = monotonicNs();
        protocol::FrameHeader header;
        header.frame = static_cast<std::uint32_t>(job.frame);
        header.time = job.time;
        header.kind = s.kind;
        header.encoding = s.encoding;
        std::vector<protocol::FramePatch> patches;
        if (s.kind == protocol::FrameKind::Full) {
            patches.push_back(
                {0, 0, job.image.cols, job.image.rows, encodeImage(job.image, s.encoding, s.jpegQuality, png)});
        } else {
            for (const cv::Rect& r : job.patches) {
                protocol::FramePatch p{r.x, r.y, r.width, r.height, {}};
                if (!r.empty()) p.data = encodeImage(job.image(r), s.encoding, s.jpegQuality, png);
                patches.push_back(std::move(p));
            }
        }
        QByteArray message =
            protocol::encodeMessage(protocol::MessageType::Frame, protocol::encodeFrame(header, patches));
        const QString name = subscriptionName(s);
        encodeMs_[name].add(1e-6 * static_cast<double>(monotonicNs() - startNs));
        frameBytes_[name].add(static_cast<double>(message.size()));
        packet->images.emplace_back(s, std::move(message));
    }
    return packet;
}

}  // namespace vssim
