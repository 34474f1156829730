// Tests for the polynomial root finders in core/roots.cpp: accuracy on polynomials
// with known roots, tangents (double roots) reported once, degree drops, and random
// polynomials checked against a dense sign-change scan. All randomness is seeded.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "roots.h"

using namespace rt;

namespace {

// Coefficients in increasing degree, as roots.h wants them.
using Poly = std::vector<double>;

Poly times_linear(const Poly& p, double r) {  // p * (t - r)
    Poly q(p.size() + 1, 0.0);
    for (std::size_t i = 0; i < p.size(); ++i) {
        q[i + 1] += p[i];
        q[i] -= r * p[i];
    }
    return q;
}

Poly times_quadratic(const Poly& p, double b, double c) {  // p * (t^2 + b t + c)
    Poly q(p.size() + 2, 0.0);
    for (std::size_t i = 0; i < p.size(); ++i) {
        q[i] += c * p[i];
        q[i + 1] += b * p[i];
        q[i + 2] += p[i];
    }
    return q;
}

Poly scaled(Poly p, double k) {
    for (double& c : p) c *= k;
    return p;
}

double horner(const Poly& p, double x) {
    double f = 0;
    for (std::size_t i = p.size(); i-- > 0;) f = f * x + p[i];
    return f;
}

double horner_scale(const Poly& p, double x) {
    double s = 0;
    for (std::size_t i = p.size(); i-- > 0;) s = s * std::fabs(x) + std::fabs(p[i]);
    return s;
}

// Dispatches on the polynomial's length so tests can loop over degrees.
std::vector<double> solve(const Poly& p, double lo, double hi) {
    double out[4] = {NAN, NAN, NAN, NAN};
    int n = 0;
    if (p.size() == 3) n = solve_quadratic(p.data(), lo, hi, out);
    else if (p.size() == 4) n = solve_cubic(p.data(), lo, hi, out);
    else if (p.size() == 5) n = solve_quartic(p.data(), lo, hi, out);
    else FAIL("unsupported degree");
    REQUIRE(n >= 0);
    REQUIRE(n <= int(p.size()) - 1);
    return std::vector<double>(out, out + n);
}

// Roots in [-10, 10] at least `gap` apart, so each is well conditioned.
std::vector<double> separated_roots(std::mt19937_64& rng, int n, double gap) {
    std::uniform_real_distribution<double> u(-10, 10);
    for (;;) {
        std::vector<double> r(n);
        for (double& x : r) x = u(rng);
        std::sort(r.begin(), r.end());
        bool ok = true;
        for (int i = 1; i < n; ++i) ok = ok && r[i] - r[i - 1] >= gap;
        if (ok) return r;
    }
}

double random_leading(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> e(-3, 3);
    std::bernoulli_distribution neg(0.5);
    return (neg(rng) ? -1 : 1) * std::pow(10.0, e(rng));
}

void check_close(const std::vector<double>& got, const std::vector<double>& want, double rel) {
    REQUIRE(got.size() == want.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        INFO("root " << i << " got " << got[i] << " want " << want[i]);
        CHECK(std::fabs(got[i] - want[i]) <= rel * std::max(1.0, std::fabs(want[i])));
    }
}

// Ray o + t d (d unit) against a torus at the origin with axis z: the quartic in t of
// (|x|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + y^2), as an exact torus intersection builds it.
Poly torus_quartic(const double o[3], const double d[3], double R, double r) {
    const double od = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
    const double oo = o[0] * o[0] + o[1] * o[1] + o[2] * o[2];
    const double a1 = 2 * od, a0 = oo + R * R - r * r;
    const double q2 = d[0] * d[0] + d[1] * d[1];
    const double q1 = 2 * (o[0] * d[0] + o[1] * d[1]);
    const double q0 = o[0] * o[0] + o[1] * o[1];
    const double k = 4 * R * R;
    return {a0 * a0 - k * q0, 2 * a1 * a0 - k * q1, a1 * a1 + 2 * a0 - k * q2, 2 * a1, 1};
}

}  // namespace

TEST_CASE("polynomials built from well-separated roots give those roots back to 1e-9") {
    std::mt19937_64 rng(20130101);
    for (int degree = 2; degree <= 4; ++degree) {
        for (int trial = 0; trial < 2000; ++trial) {
            const std::vector<double> want = separated_roots(rng, degree, 0.01);
            Poly p{random_leading(rng)};
            for (double r : want) p = times_linear(p, r);
            INFO("degree " << degree << " trial " << trial);
            check_close(solve(p, -20, 20), want, 1e-9);
        }
    }
}

TEST_CASE("complex root pairs contribute no real roots") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-5, 5), gap(0.1, 10);
    for (int trial = 0; trial < 2000; ++trial) {
        const double b = u(rng), c = b * b / 4 + gap(rng);  // t^2 + b t + c > 0 for all t
        std::vector<double> want = separated_roots(rng, 2, 0.01);
        const Poly quartic = scaled(times_linear(times_linear(times_quadratic({1}, b, c), want[0]), want[1]),
                                    random_leading(rng));
        check_close(solve(quartic, -20, 20), want, 1e-9);
        const Poly quadratic = times_quadratic({random_leading(rng)}, b, c);
        CHECK(solve(quadratic, -1e6, 1e6).empty());
        const Poly two_pairs = times_quadratic(times_quadratic({1}, b, c), -b, c);
        CHECK(solve(two_pairs, -1e6, 1e6).empty());
    }
}

TEST_CASE("only roots inside [lo, hi] are reported, including roots at the ends") {
    // (t + 3)(t + 1)(t - 2)(t - 5): integer coefficients, so p(-1) and p(2) are exactly 0.
    const Poly p = times_linear(times_linear(times_linear(times_linear({1}, -3), -1), 2), 5);
    check_close(solve(p, 0, 4), {2}, 1e-12);
    check_close(solve(p, -1, 2), {-1, 2}, 1e-12);
    check_close(solve(p, -2.5, 6), {-1, 2, 5}, 1e-12);
    CHECK(solve(p, 2.5, 4.5).empty());
    check_close(solve(p, 2, 2), {2}, 0);  // a one-point interval that is a root
    CHECK(solve(p, 3, 3).empty());
    CHECK(solve(p, 4, 0).empty());  // lo > hi
}

TEST_CASE("a double root is reported exactly once") {
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> u(-10, 10), gap(0.1, 10);
    for (int trial = 0; trial < 2000; ++trial) {
        const std::vector<double> r = separated_roots(rng, 3, 0.5);
        const double k = random_leading(rng);
        INFO("trial " << trial << " double root " << r[1]);
        // Quadratic (t - r)^2: the discriminant is zero up to rounding.
        check_close(solve(scaled(times_linear(times_linear({1}, r[1]), r[1]), k), -20, 20), {r[1]}, 1e-7);
        // Cubic (t - a)(t - r)^2 and quartic (t - a)(t - r)^2 (t - b).
        const Poly cubic = scaled(times_linear(times_linear(times_linear({1}, r[0]), r[1]), r[1]), k);
        check_close(solve(cubic, -20, 20), {r[0], r[1]}, 1e-7);
        check_close(solve(times_linear(cubic, r[2]), -20, 20), {r[0], r[1], r[2]}, 1e-7);
        // (t - r)^2 (t^2 + b t + c): the tangent is the only real root.
        const double b = u(rng), c = b * b / 4 + gap(rng);
        const Poly touch = scaled(times_quadratic(times_linear(times_linear({1}, r[1]), r[1]), b, c), k);
        check_close(solve(touch, -20, 20), {r[1]}, 1e-7);
        // Two tangents: (t - r0)^2 (t - r2)^2.
        const Poly two = times_linear(times_linear(times_linear(times_linear({k}, r[0]), r[0]), r[2]), r[2]);
        check_close(solve(two, -20, 20), {r[0], r[2]}, 1e-7);
    }
}

TEST_CASE("triple and quadruple roots are reported once") {
    check_close(solve({-8, 12, -6, 1}, -10, 10), {2}, 1e-12);                   // (t - 2)^3
    check_close(solve({-8, 4, 6, -5, 1}, -10, 10), {-1, 2}, 1e-12);             // (t - 2)^3 (t + 1)
    check_close(solve({1, -4, 6, -4, 1}, -10, 10), {1}, 1e-12);                 // (t - 1)^4
    check_close(solve({0.0625, -0.5, 1.5, -2, 1}, -10, 10), {0.5}, 1e-12);      // (t - 0.5)^4
    // A quadruple root away from a dyadic value: only eps^(1/4) accuracy is possible.
    const Poly p = times_linear(times_linear(times_linear(times_linear({1}, 0.3), 0.3), 0.3), 0.3);
    const std::vector<double> got = solve(p, -10, 10);
    REQUIRE(!got.empty());
    CHECK(got.size() <= 2);
    for (double x : got) CHECK(std::fabs(x - 0.3) < 1e-3);
}

TEST_CASE("ray-torus quartic: through hits, and tangent rays touching once per contact") {
    const double R = 2, r = 0.5;
    {   // Along the x axis through the hole: four crossings.
        const double o[3] = {-5, 0, 0}, d[3] = {1, 0, 0};
        check_close(solve(torus_quartic(o, d, R, r), 0, 100), {2.5, 3.5, 6.5, 7.5}, 1e-12);
    }
    {   // Grazing the outer equator: one double root.
        const double o[3] = {-5, R + r, 0}, d[3] = {1, 0, 0};
        check_close(solve(torus_quartic(o, d, R, r), 0, 100), {5}, 1e-7);
    }
    {   // Along the top of the tube: it touches the top circle twice.
        const double o[3] = {-5, 0, r}, d[3] = {1, 0, 0};
        check_close(solve(torus_quartic(o, d, R, r), 0, 100), {3, 7}, 1e-7);
    }
    // The same in random directions and offsets, so the coefficients carry rounding:
    // a horizontal line in the plane z = r meets the top circle (radius R) twice, and
    // touches the torus there, so each contact must come out as exactly one root.
    std::mt19937_64 rng(4242);
    std::uniform_real_distribution<double> angle(0, 2 * M_PI), offset(-0.9 * R, 0.9 * R);
    std::uniform_real_distribution<double> major(0.5, 5), ratio(0.05, 0.9);
    for (int trial = 0; trial < 2000; ++trial) {
        const double big = major(rng), small = big * ratio(rng);
        const double th = angle(rng), h = offset(rng) * big / R;
        const double d[3] = {std::cos(th), std::sin(th), 0};
        const double start = 3 * (big + small);
        // Closest approach to the axis is |h|, reached at t = start.
        const double o[3] = {-start * d[0] - h * d[1], -start * d[1] + h * d[0], small};
        const double half = std::sqrt(big * big - h * h);
        INFO("trial " << trial << " R " << big << " r " << small << " h " << h);
        check_close(solve(torus_quartic(o, d, big, small), 0, 2 * start), {start - half, start + half}, 1e-6);
    }
}

TEST_CASE("a vanishing leading coefficient drops the degree gracefully") {
    std::mt19937_64 rng(5);
    for (int trial = 0; trial < 1000; ++trial) {
        const std::vector<double> want = separated_roots(rng, 3, 0.01);
        Poly cubic{random_leading(rng)};
        for (double x : want) cubic = times_linear(cubic, x);
        INFO("trial " << trial);
        Poly quartic = cubic;
        quartic.push_back(0.0);
        check_close(solve(quartic, -20, 20), want, 1e-9);
        // A leading term far too small to matter on [-20, 20]: its extra root is
        // around -c3/c4, nowhere near the interval.
        quartic.back() = cubic[3] * 1e-30;
        check_close(solve(quartic, -20, 20), want, 1e-9);
        // Exactly zero leading terms down to a linear polynomial.
        check_close(solve({-want[0], 1, 0, 0, 0}, -20, 20), {want[0]}, 1e-15);
        check_close(solve({-want[0], 1, 0, 0}, -20, 20), {want[0]}, 1e-15);
        check_close(solve({-want[0], 1, 0}, -20, 20), {want[0]}, 1e-15);
    }
    CHECK(solve({0, 0, 0, 0, 0}, -1, 1).empty());  // the zero polynomial has no isolated roots
    CHECK(solve({3, 0, 0, 0, 0}, -1, 1).empty());
    CHECK(solve({0, 0, 0}, -1, 1).empty());
}

TEST_CASE("random polynomials: every reported root is a root, and a dense scan finds none missed") {
    std::mt19937_64 rng(31337);
    std::uniform_real_distribution<double> u(-1, 1), e(-2, 2);
    const double lo = -5, hi = 5;
    const int samples = 20000;
    int total_roots = 0;
    for (int degree = 2; degree <= 4; ++degree) {
        for (int trial = 0; trial < 300; ++trial) {
            Poly p(degree + 1);
            for (double& c : p) c = u(rng) * std::pow(10.0, e(rng));
            INFO("degree " << degree << " trial " << trial);
            const std::vector<double> roots = solve(p, lo, hi);
            total_roots += int(roots.size());
            for (std::size_t i = 0; i < roots.size(); ++i) {
                REQUIRE(std::isfinite(roots[i]));
                CHECK(roots[i] >= lo);
                CHECK(roots[i] <= hi);
                if (i > 0) CHECK(roots[i] > roots[i - 1]);
                // Within a few dozen roundings of zero for Horner at that point; a root
                // off by even 1e-9 would leave a residual thousands of times larger.
                CHECK(std::fabs(horner(p, roots[i])) <= 1e-13 * horner_scale(p, roots[i]));
            }
            double x0 = lo, f0 = horner(p, lo);
            for (int k = 1; k <= samples; ++k) {
                const double x1 = lo + (hi - lo) * k / samples, f1 = horner(p, x1);
                if ((f0 < 0 && f1 > 0) || (f0 > 0 && f1 < 0)) {
                    const double slack = 1e-9;
                    const bool found = std::any_of(roots.begin(), roots.end(), [&](double r) {
                        return r >= x0 - slack && r <= x1 + slack;
                    });
                    INFO("sign change in [" << x0 << ", " << x1 << "]");
                    CHECK(found);
                }
                x0 = x1;
                f0 = f1;
            }
        }
    }
    CHECK(total_roots > 500);  // the scan above must have had something to check
}

TEST_CASE("extreme and invalid input never produces NaN or out-of-range roots") {
    std::mt19937_64 rng(666);
    std::uniform_real_distribution<double> u(-1, 1), e(-300, 300), bound(-1e6, 1e6);
    std::bernoulli_distribution coin(0.3);
    for (int trial = 0; trial < 20000; ++trial) {
        Poly p(2 + trial % 3 + 1);
        for (double& c : p) c = coin(rng) ? 0.0 : u(rng) * std::pow(10.0, e(rng));
        double lo = bound(rng), hi = bound(rng);
        if (lo > hi) std::swap(lo, hi);
        if (coin(rng)) lo = -HUGE_VAL;
        if (coin(rng)) hi = HUGE_VAL;
        INFO("trial " << trial);
        const std::vector<double> roots = solve(p, lo, hi);
        for (std::size_t i = 0; i < roots.size(); ++i) {
            REQUIRE(std::isfinite(roots[i]));
            CHECK(roots[i] >= lo);
            CHECK(roots[i] <= hi);
            if (i > 0) CHECK(roots[i] > roots[i - 1]);
        }
    }
    CHECK(solve({NAN, 1, 1, 1, 1}, -1, 1).empty());
    CHECK(solve({1, 1, HUGE_VAL, 1, 1}, -1, 1).empty());
    CHECK(solve({-1, 0, 1}, NAN, 1).empty());
    CHECK(solve({-1, 0, 1}, -1, NAN).empty());
}

TEST_CASE("an infinite interval still finds every real root") {
    // (t - 1)(t + 2)(t - 1e6)(t + 3)
    const Poly p = times_linear(times_linear(times_linear(times_linear({1}, 1), -2), 1e6), -3);
    check_close(solve(p, -HUGE_VAL, HUGE_VAL), {-3, -2, 1, 1e6}, 1e-9);
    check_close(solve(p, 0, HUGE_VAL), {1, 1e6}, 1e-9);
    // A tiny quadratic term adds a root near -1e20 that only an unbounded search sees.
    const double c[3] = {-1, 1, 1e-20};
    double out[2];
    REQUIRE(solve_quadratic(c, -HUGE_VAL, HUGE_VAL, out) == 2);
    CHECK(std::fabs(out[0] / -1e20 - 1) < 1e-12);
    CHECK(std::fabs(out[1] - 1) < 1e-12);
}
