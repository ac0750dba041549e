#include "vssim/linear_flow.h"

#include <cmath>

namespace vssim {

namespace {
// Scaled so that |A t| <= 1/2 in the infinity norm; 20 Taylor terms then
// leave a remainder below 0.5^20 / 20! ~ 4e-25, far under rounding.
constexpr double kScaledNorm = 0.5;
constexpr int kTaylorTerms = 20;
constexpr int kMaxDoublings = 200;
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
    for (int k = kTaylorTerms; k >= 1; --k) {
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
