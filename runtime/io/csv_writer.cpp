#include "io/csv_writer.h"

#include <cmath>
#include <cstdio>

namespace vssim {

CsvWriter::CsvWriter(OutputFile& out) : out_(out) { buffer_.reserve(1 << 16); }

void CsvWriter::writeHeader() {
    buffer_ += "t,body,x,y,theta,v,omega,e_right,e_left,omega_right,omega_left,i_right,i_left\n";
    flush(false);
}

void CsvWriter::appendNumber(double value) {
    char text[32];
    const int n = std::snprintf(text, sizeof text, "%.17g", value);
    buffer_.append(text, n);
}

void CsvWriter::writeSample(const Simulation& simulation) {
    const WorldState& s = simulation.state();
    const Scene& scene = simulation.scene();
    for (int i = 0; i < static_cast<int>(s.robots.size()); ++i) {
        const RobotState& r = s.robots[i];
        const Voltages& e = s.voltages[i];
        const RobotOutputs o = simulation.robotOutputs(i);
        appendNumber(s.time);
        buffer_ += ',';
        buffer_ += scene.robots[i].name.c_str();
        for (double value : {r.x, r.y, r.theta, r.v, r.omega, e.right, e.left, o.wheel_speed_right, o.wheel_speed_left,
                             o.current_right, o.current_left}) {
            buffer_ += ',';
            appendNumber(value);
        }
        buffer_ += '\n';
    }
    const BallState& b = s.ball;
    appendNumber(s.time);
    buffer_ += ",ball";
    for (double value : {b.x, b.y, std::atan2(b.vy, b.vx), std::hypot(b.vx, b.vy)}) {
        buffer_ += ',';
        appendNumber(value);
    }
    buffer_ += ",,,,,,,\n";
    flush(false);
}

bool CsvWriter::finish() {
    flush(true);
    return ok_;
}

void CsvWriter::flush(bool force) {
    if (!force && buffer_.size() < (1 << 15)) return;
    ok_ = ok_ && out_.write(buffer_);
    buffer_.clear();
}

}  // namespace vssim
