// Two doubles operated on at once, for the engine's inner loops (the exact
// step's quadrature nodes, the flows' series): one SSE2 register on x86-64,
// the compiler's generic vectors elsewhere. Each lane's arithmetic is the
// scalar IEEE operation, so a loop that does a scalar computation's
// operations in the same order on each lane gives its results bit for bit.
// Internal to the engine's sources (a GCC/Clang vector extension).
#pragma once

#include <cstring>

namespace vssim {

typedef double Pair __attribute__((vector_size(2 * sizeof(double))));

// From and to two consecutive doubles (which need not be 16-byte aligned).
inline Pair loadPair(const double* p) {
    Pair r;
    std::memcpy(&r, p, sizeof r);
    return r;
}
inline void storePair(double* p, const Pair& value) { std::memcpy(p, &value, sizeof value); }

}  // namespace vssim
