// Real roots of polynomials up to degree four on a closed interval, for the exact
// ray-torus intersection. Derivative splitting plus safeguarded Newton bisection: a
// little slower than Ferrari's formula, but it cannot lose a root to cancellation.
#include "roots.h"

#include <cfloat>
#include <cmath>
#include <utility>

namespace rt {
namespace {

// |p(x)| at or below this many eps times the Horner error scale sum |c_i| |x|^i is
// indistinguishable from zero. Horner's own error is about 2n eps of that scale, and
// coefficients built by multiplying out roots carry a few eps more; the margin above
// that is what lets a tangent (double root) be recognised instead of being missed
// when rounding lifts the touching minimum just above zero.
constexpr double kZeroTolerance = 32 * DBL_EPSILON;

struct Eval {
    double f = 0;      // p(x)
    double df = 0;     // p'(x)
    double scale = 0;  // sum |c_i| |x|^i, the size of Horner's rounding error
};

Eval eval(const double* c, int n, double x) {
    Eval e;
    e.f = c[n];
    e.scale = std::fabs(c[n]);
    const double ax = std::fabs(x);
    for (int i = n - 1; i >= 0; --i) {
        e.df = e.df * x + e.f;
        e.f = e.f * x + c[i];
        e.scale = e.scale * ax + std::fabs(c[i]);
    }
    return e;
}

bool negligible(const Eval& e, int n) { return std::fabs(e.f) <= kZeroTolerance * n * e.scale; }

// (a + b) / 2 without overflow for intervals spanning most of the double range.
double midpoint(double a, double b) { return 0.5 * a + 0.5 * b; }

// One root of p in (a, b), given p(a) = fa and p(b) = fb of opposite signs.
// Newton steps while they stay inside the bracket and each is at most half the
// previous one; bisection otherwise, so it always converges.
double refine(const double* c, int n, double a, double b, double fa, double fb) {
    // Measured on torus rays, a midpoint start needs fewer steps than a secant one.
    double x = midpoint(a, b);
    double last_step = b - a;
    for (int iter = 0; iter < 200; ++iter) {
        if (!(x > a && x < b)) break;  // a and b are adjacent doubles
        const Eval e = eval(c, n, x);
        // Below Horner's error bound the sign of p(x) means nothing: x is as close
        // to the root as evaluating p can tell.
        if (std::fabs(e.f) <= 2 * n * DBL_EPSILON * e.scale) return x;
        if ((e.f < 0) == (fa < 0)) {
            a = x;
            fa = e.f;
        } else {
            b = x;
            fb = e.f;
        }
        const double step = e.f / e.df;
        const double next = x - step;
        // A correction of an ulp or two is rounding noise in p: x is as good as it
        // gets, and bisecting further would only spend iterations.
        if (std::fabs(step) <= 2 * DBL_EPSILON * std::fabs(x)) return next > a && next < b ? next : x;
        if (next > a && next < b && 2 * std::fabs(step) <= last_step) {
            last_step = std::fabs(step);
            x = next;
        } else {
            last_step = b - a;
            x = midpoint(a, b);
        }
    }
    return std::fabs(fa) <= std::fabs(fb) ? a : b;
}

// Closed form, in the cancellation-free form q = -(b + sign(b) sqrt(D)) / 2,
// roots q/a and c/q. A tiny `a` is harmless: q/a then lands far outside [lo, hi].
int quadratic(const double* c, double lo, double hi, double* out) {
    const double a = c[2], b = c[1], k = c[0];
    const double disc = b * b - 4 * a * k;
    int count = 0;
    auto keep = [&](double r) {
        if (std::isfinite(r) && r >= lo && r <= hi && (count == 0 || r != out[count - 1])) out[count++] = r;
    };
    // |p(vertex)| = |D| / 4|a| and its Horner scale is (4|ak| + 3b^2) / 4|a|, so
    // this is the same tangent test as negligible(), without dividing by `a`.
    if (std::fabs(disc) <= kZeroTolerance * 2 * (4 * std::fabs(a * k) + 3 * b * b)) {
        keep(-b / (2 * a));
        return count;
    }
    if (disc < 0) return 0;
    const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));  // nonzero: disc > 0
    double r1 = q / a, r2 = k / q;
    if (r2 < r1) std::swap(r1, r2);
    keep(r1);
    keep(r2);
    return count;
}

// Roots of c[0..n] in [lo, hi] (finite, lo <= hi), ascending, at most n of them.
int solve(const double* c, int n, double lo, double hi, double* out) {
    while (n > 0 && c[n] == 0) --n;
    if (n == 0) return 0;  // a constant: no isolated roots, even when it is zero
    if (n == 1) {
        const double r = -c[0] / c[1];
        if (r >= lo && r <= hi) {
            out[0] = r;
            return 1;
        }
        return 0;
    }
    if (n == 2) return quadratic(c, lo, hi, out);

    // Between consecutive roots of p' the polynomial is monotone, so each piece
    // holds at most one root and has one exactly when its ends differ in sign.
    double d[4];
    for (int i = 0; i < n; ++i) d[i] = (i + 1) * c[i + 1];
    double crit[3];
    const int ncrit = solve(d, n - 1, lo, hi, crit);

    double x[5];
    int m = 0;
    x[m++] = lo;
    for (int i = 0; i < ncrit; ++i)
        if (crit[i] > x[m - 1] && crit[i] < hi) x[m++] = crit[i];
    if (hi > lo) x[m++] = hi;

    Eval e[5];
    bool zero[5];
    for (int i = 0; i < m; ++i) {
        e[i] = eval(c, n, x[i]);
        zero[i] = negligible(e[i], n);
    }

    // A breakpoint where p is within rounding of zero is a root; at a critical point
    // that is a tangent (double root), reported once. Pieces touching such a point
    // are skipped: being monotone, they cannot hold a second root.
    // Two roots closer than one ulp (both pieces around a critical point converging
    // onto it) are one root as far as doubles can tell.
    int count = 0;
    auto keep = [&](double r) {
        if (count == 0 || r != out[count - 1]) out[count++] = r;
    };
    for (int i = 0; i < m && count < n; ++i) {
        if (zero[i]) {
            keep(x[i]);
            continue;
        }
        if (i + 1 < m && !zero[i + 1] && (e[i].f < 0) != (e[i + 1].f < 0))
            keep(refine(c, n, x[i], x[i + 1], e[i].f, e[i + 1].f));
    }
    return count;
}

// Common front end: rejects NaN input, rescales by a power of two (exact, so the
// roots do not move) to keep b^2 - 4ac and Horner from overflowing, and bounds an
// infinite interval by Cauchy's root bound.
int solve_public(const double* coef, int n, double lo, double hi, double* out) {
    if (!(lo <= hi)) return 0;  // also catches NaN bounds
    double c[5];
    double biggest = 0;
    for (int i = 0; i <= n; ++i) {
        if (!std::isfinite(coef[i])) return 0;
        c[i] = coef[i];
        biggest = std::fmax(biggest, std::fabs(c[i]));
    }
    if (biggest == 0) return 0;
    int exponent = 0;
    std::frexp(biggest, &exponent);
    for (int i = 0; i <= n; ++i) c[i] = std::ldexp(c[i], -exponent);

    if (!std::isfinite(lo) || !std::isfinite(hi)) {
        for (;;) {
            while (n > 0 && c[n] == 0) --n;
            if (n == 0) return 0;
            double ratio = 0;
            for (int i = 0; i < n; ++i) ratio = std::fmax(ratio, std::fabs(c[i] / c[n]));
            const double bound = 1 + ratio;
            if (std::isfinite(bound)) {
                lo = std::fmax(lo, -bound);
                hi = std::fmin(hi, bound);
                break;
            }
            // The leading coefficient is below 1e-308 of another one: the root it adds
            // lies beyond the largest double, so drop it as the degree-drop it is.
            --n;
        }
        if (!(lo <= hi)) return 0;
    }
    return solve(c, n, lo, hi, out);
}

}  // namespace

int solve_quadratic(const double c[3], double lo, double hi, double roots[2]) {
    return solve_public(c, 2, lo, hi, roots);
}

int solve_cubic(const double c[4], double lo, double hi, double roots[3]) {
    return solve_public(c, 3, lo, hi, roots);
}

int solve_quartic(const double c[5], double lo, double hi, double roots[4]) {
    return solve_public(c, 4, lo, hi, roots);
}

}  // namespace rt
