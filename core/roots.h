// Robust real roots of low-degree polynomials on an interval, for the exact torus.
// Coefficients are in increasing degree: c[0] + c[1] t + ... + c[n] t^n.
#pragma once

namespace rt {

// Real roots of c[0] + c[1] t + c[2] t^2 in [lo, hi], ascending; returns the count (<= 2).
[[nodiscard]] int solve_quadratic(const double c[3], double lo, double hi, double roots[2]);
// Real roots of the quartic in [lo, hi], ascending, each to near machine precision;
// a double root counts once. Returns the count (<= 4).
// Works by splitting [lo, hi] at the roots of the derivative (recursively) and
// bisecting each monotone piece with safeguarded Newton steps.
[[nodiscard]] int solve_quartic(const double c[5], double lo, double hi, double roots[4]);
[[nodiscard]] int solve_cubic(const double c[4], double lo, double hi, double roots[3]);

}  // namespace rt
