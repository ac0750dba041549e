// Benchmark: the camera's cost per frame. The 3-vs-3 kick-off with random
// voltages every 30 ms (bodies moving), one camera frame every 30 ms of
// simulated time; each frame rendered by three cameras, interleaved frame by
// frame so that they share the machine's moods: the ideal camera (the
// baseline), the realistic preset without motion blur, and the realistic
// preset (exposure 10 ms, 6 sub-frames). Each rendered frame is then encoded
// as a full frame (raw, PNG, JPEG 90) and as patches (PNG, as vssim serve
// sends them by default: each patch encoded on its own). Medians over the
// frames of render, encode and their sum per frame, and of the bytes.
#include <chrono>
#include <iomanip>
#include <map>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "bench_timing.h"
#include "benchmarks.h"
#include "vssim/camera/camera_renderer.h"
#include "vssim/camera/image_codec.h"
#include "vssim/world.h"

namespace vssim::bench {

namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

struct Encoding {
    const char* name;
    bool patches;  // each patch encoded on its own; else the full frame
    ImageEncoding encoding;
    bool deflated = false;  // PNG deflated even for a noisy camera (the server stores those)
};

}  // namespace

int cameraRender(const Options& options, std::ostream& out, std::ostream& log) {
    const int frames = options.quick ? 20 : 300;
    constexpr double kPeriod = 0.03;  // s, the camera's period
    const Scene scene = kickoffWithRandomVoltages(options.sceneFile, 11, frames * kPeriod + 1.0, kPeriod);

    // The states at the camera instants.
    std::vector<WorldState> states;
    {
        Simulation sim(scene);
        for (int k = 1; k <= frames; ++k) {
            sim.advanceTo(Simulation::stepIndexAtOrAfter(k * kPeriod, scene.simulation.dt));
            states.push_back(sim.state());
        }
    }
    CameraSettings noBlur = realisticCamera();
    noBlur.exposure = 0.0;
    const CameraSettings blurred = realisticCamera();  // exposure 10 ms, 6 sub-frames
    const std::vector<std::pair<std::string, CameraSettings>> cameras{
        {"ideal", idealCamera()}, {"realistic, no blur", noBlur}, {"realistic, blur 10 ms x 6", blurred}};
    // PNG as the server writes it: deflated, or stored for a camera with sensor
    // noise (image_codec.h); "full png deflated" always deflates (the figure before).
    const std::vector<Encoding> encodings{{"full raw", false, ImageEncoding::Raw},
                                          {"full png", false, ImageEncoding::Png},
                                          {"full png deflated", false, ImageEncoding::Png, true},
                                          {"full jpeg 90", false, ImageEncoding::Jpeg},
                                          {"patches png", true, ImageEncoding::Png}};

    std::vector<CameraRenderer> renderers;
    std::vector<double> constructionMs;
    for (const auto& [name, settings] : cameras) {
        const auto start = std::chrono::steady_clock::now();
        renderers.emplace_back(scene, settings);
        constructionMs.push_back(millisecondsSince(start));
    }

    // Per camera: render times; per camera and encoding: encode times, sums, bytes.
    std::vector<std::vector<double>> renderMs(cameras.size()), patchPercent(cameras.size());
    std::vector<std::vector<std::vector<double>>> encodeMs(cameras.size(),
                                                           std::vector<std::vector<double>>(encodings.size())),
        totalMs = encodeMs, bytes = encodeMs;
    cv::Mat frame;
    std::vector<cv::Rect> patches;
    for (int pass = 0; pass < 2; ++pass) {  // the first pass warms up (caches, page faults)
        for (int k = 0; k < frames; ++k) {
            for (std::size_t c = 0; c < cameras.size(); ++c) {
                const auto start = std::chrono::steady_clock::now();
                renderers[c].render(states[k], frame, patches, static_cast<std::uint64_t>(k));
                const double render = millisecondsSince(start);
                double area = 0.0;
                for (const cv::Rect& r : patches) area += r.area();
                for (std::size_t e = 0; e < encodings.size(); ++e) {
                    const auto encodeStart = std::chrono::steady_clock::now();
                    std::size_t size = 0;
                    const PngDeflate png = cameras[c].second.noise > 0.0 && !encodings[e].deflated
                                               ? PngDeflate::Stored
                                               : PngDeflate::Fast;
                    if (encodings[e].patches) {
                        for (const cv::Rect& r : patches)
                            if (!r.empty()) size += encodeImage(frame(r), encodings[e].encoding, 90, png).size();
                    } else {
                        size = encodeImage(frame, encodings[e].encoding, 90, png).size();
                    }
                    const double encode = millisecondsSince(encodeStart);
                    if (pass == 0) continue;
                    encodeMs[c][e].push_back(encode);
                    totalMs[c][e].push_back(render + encode);
                    bytes[c][e].push_back(static_cast<double>(size));
                }
                if (pass == 0) continue;
                renderMs[c].push_back(render);
                patchPercent[c].push_back(100.0 * area / (static_cast<double>(frame.cols) * frame.rows));
            }
        }
    }

    out << "camera,construction_ms,render_ms,patch_percent,encoding,encode_ms,render_plus_encode_ms,bytes,frames\n"
        << std::setprecision(5);
    log << "  " << frames << " frames of the kick-off with random voltages, medians per frame:\n";
    for (std::size_t c = 0; c < cameras.size(); ++c) {
        log << "  " << cameras[c].first << ": render " << median(renderMs[c]) << " ms (patches "
            << median(patchPercent[c]) << " % of the image; made in " << constructionMs[c] << " ms)\n";
        for (std::size_t e = 0; e < encodings.size(); ++e) {
            out << '"' << cameras[c].first << "\"," << constructionMs[c] << ',' << median(renderMs[c]) << ','
                << median(patchPercent[c]) << ",\"" << encodings[e].name << "\"," << median(encodeMs[c][e]) << ','
                << median(totalMs[c][e]) << ',' << median(bytes[c][e]) << ',' << frames << '\n';
            log << "    " << std::setw(13) << encodings[e].name << ": encode " << std::setw(7) << median(encodeMs[c][e])
                << " ms, render + encode " << std::setw(7) << median(totalMs[c][e]) << " ms, " << std::setw(8)
                << median(bytes[c][e]) << " bytes\n";
        }
    }
    return 0;
}

}  // namespace vssim::bench
