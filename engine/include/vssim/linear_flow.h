// The exact flow of the robot's velocity dynamics u' = A u + g (model.md §2,
// eq. 8) over a time t with constant input g = G e (piecewise-constant
// voltages, model.md §7):
//
//     u(t)     = Phi(t) u0 + Psi(t) g
//     int_0^t u = Psi(t) u0 + Omega(t) g
//
// with Phi(t) = exp(A t), Psi(t) = int_0^t Phi, Omega(t) = int_0^t Psi.
// The second line gives the heading exactly (theta' = omega).
//
// Computed by Taylor series of the three at once on a scaled time (each a
// I + b A by Cayley-Hamilton, so the sums are of scalars), then
// doubling back (Phi(2t) = Phi^2, Psi(2t) = (I + Phi) Psi, Omega(2t) =
// (I + Phi) Omega + t Psi). This needs neither A^-1 (A may be singular for a
// frictionless robot) nor eigenvalues, has no cancellation for short times,
// and is the same for every 2x2 A: no case split on real or complex modes.
#pragma once

#include <Eigen/Core>

namespace vssim {

struct LinearFlow {
    double t = 0.0;                                     // s
    Eigen::Matrix2d Phi = Eigen::Matrix2d::Identity();  // exp(A t), dimensionless
    Eigen::Matrix2d Psi = Eigen::Matrix2d::Zero();      // int_0^t exp(A s) ds, s
    Eigen::Matrix2d Omega = Eigen::Matrix2d::Zero();    // int_0^t Psi(s) ds, s^2
};

LinearFlow linearFlow(const Eigen::Matrix2d& A, double t);

// The flows over fractions[i] * t (each in [0, 1]) for i < count, into
// out[i]: what linearFlow(A, fractions[i] * t) gives, to rounding. Where
// |A t| needs no scaling (at most 1/2: any step of a few milliseconds) they
// share one series, since (c X)^k = c^k X^k: one Cayley-Hamilton recursion,
// then only the sums, weighted by c^k, for each fraction (the quadrature
// nodes of a panel, exact_integrator.cpp). A fraction of exactly 1 gives
// linearFlow(A, t)'s bits. Otherwise (and for a fraction outside [0, 1],
// or NaN) each is linearFlow's.
void linearFlowsAlong(const Eigen::Matrix2d& A, double t, const double* fractions, int count, LinearFlow* out);

}  // namespace vssim
