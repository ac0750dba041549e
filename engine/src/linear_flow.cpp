#include "vssim/linear_flow.h"

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
// this, relative to the leading term I (2^-60, under a double's rounding).
constexpr double kTaylorRemainder = 8.7e-19;

// The fewest terms K whose remainder, at most 2 x^(K+1) / (K+1)! for
// x = |A tau| <= 1/2 (the tail is a geometric series of ratio <= 1/(K+2)),
// is below kTaylorRemainder, for Phi; Psi's and Omega's terms are the same
// over (k+1) and (k+1)(k+2), smaller still.
int taylorTermsFor(double x) {
    double next = x;  // x^(k+1) / (k+1)! for k = 0
    for (int k = 1; k < kTaylorTerms; ++k) {
        next *= x / static_cast<double>(k + 1);
        if (2.0 * next <= kTaylorRemainder) return k;
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

    // Phi = sum (A tau)^k / k!, Psi = tau sum (A tau)^k / (k+1)!,
    // Omega = tau^2 sum (A tau)^k / (k+2)!; Horner from the highest term.
    const Eigen::Matrix2d X = A * tau;
    const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
    Eigen::Matrix2d phi = I, psi = I, omega = I;
    for (int k = taylorTermsFor(std::ldexp(norm, -doublings)); k >= 1; --k) {
        phi = I + X * phi / static_cast<double>(k);
        psi = I + X * psi / static_cast<double>(k + 1);
        omega = I + X * omega / static_cast<double>(k + 2);
    }
    LinearFlow f;
    f.t = tau;
    f.Phi = phi;
    f.Psi = tau * psi;
    f.Omega = (0.5 * tau * tau) * omega;
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
