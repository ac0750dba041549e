#include "vssim/linear_flow.h"

#include <array>
#include <cmath>

#include "double_pair.h"

namespace vssim {

namespace {
// Scaled so that |A t| <= 1/2 in the infinity norm; 20 Taylor terms then
// leave a remainder below 0.5^20 / 20! ~ 4e-25, far under rounding.
constexpr double kScaledNorm = 0.5;
constexpr int kTaylorTerms = 20;
constexpr int kMaxDoublings = 200;
// Fewer terms suffice for a smaller |A t| (a step of a millisecond is about
// 0.015 for a default robot): the series stops once the remainder is below
// this, relative to its first-order term A t (2^-60, under a double's
// rounding). Relative to A t, not to I: an entry that starts at first order
// (an off-diagonal one, a coupling of the wheels) keeps its own relative
// accuracy, down to entries a thousandth of |A|.
constexpr double kTaylorRemainder = 8.7e-19;

// 1 / k! for k = 0 to kTaylorTerms + 2.
constexpr std::array<double, kTaylorTerms + 3> kInverseFactorial = [] {
    std::array<double, kTaylorTerms + 3> f{};
    f[0] = 1.0;
    for (int k = 1; k < kTaylorTerms + 3; ++k) f[k] = f[k - 1] / k;
    return f;
}();

// The fewest terms K whose remainder, at most 2 x^(K+1) / (K+1)! for
// x = |A tau| <= 1/2 (the tail is a geometric series of ratio <= 1/(K+2)),
// is below kTaylorRemainder x, for Phi; Psi's and Omega's terms are the
// same over (k+1) and (k+1)(k+2), smaller still.
int taylorTermsFor(double x) {
    double next = x;  // x^(k+1) / (k+1)! for k = 0
    for (int k = 1; k < kTaylorTerms; ++k) {
        next *= x / static_cast<double>(k + 1);
        if (2.0 * next <= kTaylorRemainder * x) return k;
    }
    return kTaylorTerms;  // also for NaN
}

double scaledNormOf(const Eigen::Matrix2d& A, double t) { return (A * t).cwiseAbs().rowwise().sum().maxCoeff(); }

// The (p_k, q_k) of X^k = p_k I + q_k X (below) for k = 0 to `terms`.
using PowerCoefficients = std::array<Pair, kTaylorTerms + 1>;
void powerCoefficients(const Eigen::Matrix2d& X, int terms, PowerCoefficients& pq) {
    const double trace = X.trace(), det = X(0, 0) * X(1, 1) - X(0, 1) * X(1, 0);
    pq[0] = Pair{1.0, 0.0};
    for (int k = 0; k < terms; ++k) pq[k + 1] = Pair{-det * pq[k][1], pq[k][0] + trace * pq[k][1]};
}

// The three flows of X = A tau from the series' sums, each a I + b X.
LinearFlow flowFromSums(const Eigen::Matrix2d& X, double tau, const Pair& phi, const Pair& psi, const Pair& omega) {
    const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
    LinearFlow f;
    f.t = tau;
    f.Phi = phi[0] * I + phi[1] * X;
    f.Psi = tau * (psi[0] * I + psi[1] * X);
    f.Omega = (tau * tau) * (omega[0] * I + omega[1] * X);
    return f;
}
}  // namespace

LinearFlow linearFlow(const Eigen::Matrix2d& A, double t) {
    const double norm = scaledNormOf(A, t);
    int doublings = 0;
    if (std::isfinite(norm) && norm > kScaledNorm)
        doublings = std::min(kMaxDoublings, static_cast<int>(std::ceil(std::log2(norm / kScaledNorm))));
    // Exact: a power-of-two scaling (none in most calls: a step of
    // milliseconds, whose |A t| is already below kScaledNorm).
    const double tau = doublings == 0 ? t : std::ldexp(t, -doublings);

    // Phi = sum X^k / k!, Psi = tau sum X^k / (k+1)!, Omega = tau^2 sum
    // X^k / (k+2)! with X = A tau. By Cayley-Hamilton X^2 = tr(X) X - det(X) I,
    // so every power is X^k = p_k I + q_k X with p_(k+1) = -det(X) q_k and
    // q_(k+1) = p_k + tr(X) q_k, and each series is a I + b X with scalar
    // sums a and b: a tenth of the work of summing 2x2 matrices. The sums
    // run from the smallest term up. (Where X is close to a multiple of I,
    // p_k and q_k X cancel by a factor of about k; the terms they make up
    // fall as |X|^k / k!, so the flow stays within a few units of rounding.)
    const Eigen::Matrix2d X = A * tau;
    const int terms = taylorTermsFor(doublings == 0 ? norm : std::ldexp(norm, -doublings));
    // (p_k, q_k) side by side, so that each series' two sums go as one pair
    // of doubles: each lane does its scalar sum's operations in the same
    // order, so the same bits. Entries 0 to `terms` are written before read.
    PowerCoefficients pq;
    powerCoefficients(X, terms, pq);
    Pair phi = {0.0, 0.0}, psi = {0.0, 0.0}, omega = {0.0, 0.0};  // (the I and the X sums)
    for (int k = terms; k >= 0; --k) {
        phi += pq[k] * kInverseFactorial[k];
        psi += pq[k] * kInverseFactorial[k + 1];
        omega += pq[k] * kInverseFactorial[k + 2];
    }
    LinearFlow f = flowFromSums(X, tau, phi, psi, omega);
    const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
    for (int d = 0; d < doublings; ++d) {
        const Eigen::Matrix2d onePlusPhi = I + f.Phi;
        f.Omega = onePlusPhi * f.Omega + f.t * f.Psi;
        f.Psi = onePlusPhi * f.Psi;
        f.Phi = f.Phi * f.Phi;
        f.t *= 2.0;
    }
    f.t = t;
    return f;
}

void linearFlowsAlong(const Eigen::Matrix2d& A, double t, const double* fractions, int count, LinearFlow* out) {
    const double norm = scaledNormOf(A, t);
    if (!(norm <= kScaledNorm)) {  // (also NaN: linearFlow's answer, whatever it is)
        for (int i = 0; i < count; ++i) out[i] = linearFlow(A, fractions[i] * t);
        return;
    }
    // The terms |A t| needs suffice for every fraction of it: the remainder
    // relative to the first-order term, 2 (c x)^K / (K+1)!, falls with c.
    const Eigen::Matrix2d X = A * t;
    const int terms = taylorTermsFor(norm);
    PowerCoefficients pq;
    powerCoefficients(X, terms, pq);
    for (int i = 0; i < count; ++i) {
        const double c = fractions[i];
        if (!(c >= 0.0 && c <= 1.0)) {  // (outside the series' reach: on its own)
            out[i] = linearFlow(A, c * t);
            continue;
        }
        // (c X)^k / (k + m)! = c^k / (k + m)! (p_k I + q_k X); c^k times the
        // factorials' reciprocals, so that c = 1 gives linearFlow's sums.
        std::array<double, kTaylorTerms + 1> power;  // c^k
        power[0] = 1.0;
        for (int k = 0; k < terms; ++k) power[k + 1] = power[k] * c;
        Pair phi = {0.0, 0.0}, psi = {0.0, 0.0}, omega = {0.0, 0.0};
        for (int k = terms; k >= 0; --k) {
            const Pair term = pq[k] * power[k];
            phi += term * kInverseFactorial[k];
            psi += term * kInverseFactorial[k + 1];
            omega += term * kInverseFactorial[k + 2];
        }
        // In terms of X, not c X: Psi(c t) = c t sum (c X)^k / (k+1)!, and so on.
        out[i] = flowFromSums(X, c * t, phi, psi, omega);
    }
}

}  // namespace vssim
