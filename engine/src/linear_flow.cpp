#include "vssim/linear_flow.h"

#include <array>
#include <cmath>

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
}  // namespace

LinearFlow linearFlow(const Eigen::Matrix2d& A, double t) {
    const double norm = (A * t).cwiseAbs().rowwise().sum().maxCoeff();
    int doublings = 0;
    if (std::isfinite(norm) && norm > kScaledNorm)
        doublings = std::min(kMaxDoublings, static_cast<int>(std::ceil(std::log2(norm / kScaledNorm))));
    const double tau = std::ldexp(t, -doublings);  // exact: a power-of-two scaling

    // Phi = sum X^k / k!, Psi = tau sum X^k / (k+1)!, Omega = tau^2 sum
    // X^k / (k+2)! with X = A tau. By Cayley-Hamilton X^2 = tr(X) X - det(X) I,
    // so every power is X^k = p_k I + q_k X with p_(k+1) = -det(X) q_k and
    // q_(k+1) = p_k + tr(X) q_k, and each series is a I + b X with scalar
    // sums a and b: a tenth of the work of summing 2x2 matrices. The sums
    // run from the smallest term up. (Where X is close to a multiple of I,
    // p_k and q_k X cancel by a factor of about k; the terms they make up
    // fall as |X|^k / k!, so the flow stays within a few units of rounding.)
    const Eigen::Matrix2d X = A * tau;
    const int terms = taylorTermsFor(std::ldexp(norm, -doublings));
    const double trace = X.trace(), det = X(0, 0) * X(1, 1) - X(0, 1) * X(1, 0);
    std::array<double, kTaylorTerms + 1> p{}, q{};
    p[0] = 1.0;
    for (int k = 0; k < terms; ++k) {
        p[k + 1] = -det * q[k];
        q[k + 1] = p[k] + trace * q[k];
    }
    double phiI = 0.0, phiX = 0.0, psiI = 0.0, psiX = 0.0, omegaI = 0.0, omegaX = 0.0;
    for (int k = terms; k >= 0; --k) {
        phiI += p[k] * kInverseFactorial[k];
        phiX += q[k] * kInverseFactorial[k];
        psiI += p[k] * kInverseFactorial[k + 1];
        psiX += q[k] * kInverseFactorial[k + 1];
        omegaI += p[k] * kInverseFactorial[k + 2];
        omegaX += q[k] * kInverseFactorial[k + 2];
    }
    const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
    LinearFlow f;
    f.t = tau;
    f.Phi = phiI * I + phiX * X;
    f.Psi = tau * (psiI * I + psiX * X);
    f.Omega = (tau * tau) * (omegaI * I + omegaX * X);
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

}  // namespace vssim
