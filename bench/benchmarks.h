// The benchmarks of docs/performance.md. Each writes CSV to `out` and a
// short human summary to `log`.
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include "vssim/field.h"

namespace vssim::bench {

struct Options {
    std::string sceneFile;  // the 3-vs-3 scene file
    std::string sceneDir;   // resources/scenes of the source tree
    bool quick = false;     // fewer configurations and repetitions (a smoke run)
    // The 3-vs-3 scene's field replaced by this one (realtime; box2d, whose default is
    // the official 3 vs 3 field); none: the scene's own.
    std::optional<FieldType> field;
};

int workPrecision(const Options& options, std::ostream& out, std::ostream& log);
int realtimeFactor(const Options& options, std::ostream& out, std::ostream& log);
int scale(const Options& options, std::ostream& out, std::ostream& log);
int stability(const Options& options, std::ostream& out, std::ostream& log);
int serveLatency(const Options& options, std::ostream& out, std::ostream& log);
int firasimLatency(const Options& options, std::ostream& out, std::ostream& log);
int matchBenchmark(const Options& options, std::ostream& out, std::ostream& log);
int cameraRender(const Options& options, std::ostream& out, std::ostream& log);
// Built only with Box2D (VSSIM_HAVE_BOX2D): box2d_baseline.cpp.
int box2dBaseline(const Options& options, std::ostream& out, std::ostream& log);

}  // namespace vssim::bench
