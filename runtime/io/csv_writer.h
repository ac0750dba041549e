// CSV output of a headless run: one row per body per sample time.
#pragma once

#include <QByteArray>

#include "io/output_file.h"
#include "vssim/world.h"

namespace vssim {

// Header: t,body,x,y,theta,v,omega,e_right,e_left,omega_right,omega_left,i_right,i_left
// Units: s, -, m, m, rad, m/s, rad/s, V, V, rad/s, rad/s, A, A. For the ball,
// theta is its heading atan2(vy, vx), v its speed, and the robot-only columns
// are empty. Numbers are printed with 17 significant digits (round-trip).
class CsvWriter {
public:
    explicit CsvWriter(OutputFile& out);
    void writeHeader();
    void writeSample(const Simulation& simulation);
    // Writes what is buffered; false if any write failed (out.error() says why).
    bool finish();
    // False once a write has failed: nothing more gets through.
    bool ok() const { return ok_; }

private:
    void appendNumber(double value);
    void flush(bool force);

    OutputFile& out_;
    QByteArray buffer_;
    bool ok_ = true;
};

}  // namespace vssim
