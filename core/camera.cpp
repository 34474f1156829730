// Camera rays as in docs/rendering.md §1, with column 0 on the camera's left unless the
// original's mirrored picture is asked for.
#include "camera.h"

#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace rt {

const char* camera_problem(const Camera& cam) {
    Vec3 f = cam.centre - cam.position;
    if (length2(f) == 0) return "'centre' equals 'position', so there is no view direction";
    Vec3 up = cam.up - cam.centre;
    Vec3 fu = normalize(f);
    Vec3 ortho = up - fu * dot(up, fu);
    if (!(length(ortho) > 1e-9 * length(up)) || length2(up) == 0)
        return "'up' point gives an up direction (up - centre) parallel to the view direction";
    if (!(cam.angle_x > 0 && cam.angle_x < 180)) return "angle_x must be between 0 and 180 degrees";
    if (!(cam.angle_y > 0 && cam.angle_y < 180)) return "angle_y must be between 0 and 180 degrees";
    return nullptr;
}

CameraBasis CameraBasis::make(const Camera& cam, int width, int height, bool mirror) {
    CameraBasis b;
    b.origin = cam.position;
    b.forward = normalize(cam.centre - cam.position);
    Vec3 v = cam.up - cam.centre;
    b.up = normalize(v - b.forward * dot(v, b.forward));
    b.side = normalize(cross(b.forward, b.up));
    b.half_x = cam.angle_x / 2;
    b.half_y = cam.angle_y / 2;
    b.tan_x = std::tan(b.half_x * kDegree);
    b.tan_y = std::tan(b.half_y * kDegree);
    b.projection = cam.projection;
    b.width = width < 1 ? 1 : width;
    b.height = height < 1 ? 1 : height;
    b.mirror = mirror;
    b.lens = cam.aperture > 0 ? cam.aperture / 2 : 0;
    b.focus = cam.focus_distance > 0 ? cam.focus_distance : length(cam.centre - cam.position);
    return b;
}

Ray CameraBasis::lens_ray(const Vec3& d, double u, double v) const {
    // Shirley and Chiu's concentric map: strata of the square stay compact on the disc.
    double a = 2 * u - 1, b = 2 * v - 1, r = 0, phi = 0;
    constexpr double kQuarterPi = 0.78539816339744831;
    if (a * a > b * b) {
        r = a;
        phi = kQuarterPi * (b / a);
    } else if (b != 0) {
        r = b;
        phi = 2 * kQuarterPi - kQuarterPi * (a / b);
    }
    const Vec3 o = origin + (side * std::cos(phi) + up * std::sin(phi)) * (r * lens);
    // Linear: the point of the focal plane on the pinhole ray; polar (whose rays may look
    // sideways or back): the point at the focus distance.
    const double along = dot(d, forward);
    const double t = projection == Projection::Linear && along > 1e-6 ? focus / along : focus;
    return {o, normalize(origin + d * t - o)};
}

namespace {
// The factors of the up and side vectors for the row j and the column i.
inline double row_factor(const CameraBasis& b, double j) {
    if (b.projection == Projection::Linear) {
        double hh = b.height / 2.0;
        return b.tan_y * (hh - j) / hh;
    }
    double ay = 2 * b.half_y;
    return b.height > 1 ? std::tan((b.half_y - ay * j / (b.height - 1)) * kDegree) : 0.0;
}
inline double column_factor(const CameraBasis& b, double i) {
    double sx;
    if (b.projection == Projection::Linear) {
        double hw = b.width / 2.0;
        sx = b.tan_x * (hw - i) / hw;
    } else {
        double ax = 2 * b.half_x;
        sx = b.width > 1 ? std::tan((b.half_x - ax * i / (b.width - 1)) * kDegree) : 0.0;
    }
    // The original puts column 0 on the +side (F x U) half: a mirrored picture.
    return b.mirror ? sx : -sx;
}
}  // namespace

Vec3 CameraBasis::direction(double i, double j) const {
    return forward + up * row_factor(*this, j) + side * column_factor(*this, i);
}

void CameraBasis::unit_directions(int i0, int step, int count, double j, Vec3* out) const {
    // (forward + up sy) + side sx, as direction() adds them.
    const Vec3 row = forward + up * row_factor(*this, j);
    int k = 0;
#if defined(__SSE2__)
    static_assert(sizeof(Vec3) == 3 * sizeof(double), "the stores below write two Vec3s as six doubles");
    if (projection == Projection::Linear) {
        // Two pixels at a time: each lane does column_factor()'s and normalize()'s
        // operations in their order, so gets their bits, and the divisions and square
        // roots (most of the cost) go two to an instruction.
        const __m128d hw = _mm_set1_pd(width / 2.0), tx = _mm_set1_pd(tan_x), zero = _mm_setzero_pd();
        const __m128d flip = mirror ? zero : _mm_set1_pd(-0.0);  // -sx unless mirrored
        const __m128d rx = _mm_set1_pd(row.x), ry = _mm_set1_pd(row.y), rz = _mm_set1_pd(row.z);
        const __m128d ux = _mm_set1_pd(side.x), uy = _mm_set1_pd(side.y), uz = _mm_set1_pd(side.z);
        for (; k + 2 <= count; k += 2) {
            const __m128d i = _mm_set_pd(double(i0 + (k + 1) * step), double(i0 + k * step));
            const __m128d sx = _mm_xor_pd(_mm_div_pd(_mm_mul_pd(tx, _mm_sub_pd(hw, i)), hw), flip);
            const __m128d vx = _mm_add_pd(rx, _mm_mul_pd(ux, sx));
            const __m128d vy = _mm_add_pd(ry, _mm_mul_pd(uy, sx));
            const __m128d vz = _mm_add_pd(rz, _mm_mul_pd(uz, sx));
            const __m128d l =
                _mm_sqrt_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(vx, vx), _mm_mul_pd(vy, vy)), _mm_mul_pd(vz, vz)));
            // (l > 0 is false for NaN too: normalize()'s zero vector.)
            const __m128d ok = _mm_cmpgt_pd(l, zero);
            const __m128d x = _mm_and_pd(_mm_div_pd(vx, l), ok), y = _mm_and_pd(_mm_div_pd(vy, l), ok),
                          z = _mm_and_pd(_mm_div_pd(vz, l), ok);
            _mm_storeu_pd(&out[k].x, _mm_unpacklo_pd(x, y));
            _mm_storeu_pd(&out[k].z, _mm_unpacklo_pd(z, _mm_unpackhi_pd(x, x)));
            _mm_storeu_pd(&out[k + 1].y, _mm_unpackhi_pd(y, z));
        }
    }
#endif
    for (; k < count; ++k) out[k] = normalize(row + side * column_factor(*this, i0 + k * step));
}

}  // namespace rt
