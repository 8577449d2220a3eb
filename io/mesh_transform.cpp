// io/mesh_transform.cpp — a mesh object's transform (model_loader.hpp,
// MeshTransform): its matrix and the checks of its fields.
#include "model_loader.hpp"

#include "model_math.hpp"

#include <octray/constants.hpp>

#include <cmath>
#include <string>

namespace octray {

using namespace model_math;

MeshTransform MeshTransform::from_trs(const Vec3d& translate, const Vec3d& rotate_deg, double scale) {
    MeshTransform t;
    t.translate = translate;
    t.rotate_deg = rotate_deg;
    t.scale = scale;
    return t;
}

MeshTransform MeshTransform::from_matrix(const Matrix4d& m) {
    MeshTransform t;
    t.matrix = m;
    return t;
}

namespace {

constexpr Matrix4d kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

// sin and cos of an angle in degrees; exact for whole multiples of 90 degrees.
void sin_cos_deg(double deg, double& s, double& c) {
    const double quarter = deg / 90.0;
    if (quarter == std::floor(quarter) && std::fabs(quarter) < 1e15) {
        static constexpr double kSin[4] = {0, 1, 0, -1};
        static constexpr double kCos[4] = {1, 0, -1, 0};
        const auto q = static_cast<long long>(quarter);
        const int k = static_cast<int>(((q % 4) + 4) % 4);
        s = kSin[k];
        c = kCos[k];
        return;
    }
    const double rad = deg * (kPi / 180.0);
    s = std::sin(rad);
    c = std::cos(rad);
}

Matrix4d rotation(int axis, double deg) {
    double s = 0, c = 1;
    sin_cos_deg(deg, s, c);
    Matrix4d r = kIdentity;
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // x: (y, z); y: (z, x); z: (x, y)
    r[4 * i + i] = c;
    r[4 * i + j] = -s;
    r[4 * j + i] = s;
    r[4 * j + j] = c;
    return r;
}

}  // namespace

Matrix4d MeshTransform::to_matrix() const {
    if (matrix) return *matrix;
    Matrix4d s = kIdentity;
    s[0] = s[5] = s[10] = scale;
    Matrix4d t = kIdentity;
    t[3] = translate.x;
    t[7] = translate.y;
    t[11] = translate.z;
    const Matrix4d r = multiply(rotation(2, rotate_deg.z), multiply(rotation(1, rotate_deg.y), rotation(0, rotate_deg.x)));
    return multiply(t, multiply(r, s));
}

std::string translate_problem(const Vec3d& t) { return finite3(t) ? "" : "must be finite, got " + vec_str(t); }

std::string rotate_deg_problem(const Vec3d& r) { return finite3(r) ? "" : "must be finite, got " + vec_str(r); }

std::string scale_problem(double s) {
    if (std::isfinite(s) && s > 0) return "";
    return "must be finite and > 0, got " + num(s);
}

std::string matrix_problem(const Matrix4d& m) {
    for (double v : m)
        if (!std::isfinite(v)) return "must be finite, got " + num(v);
    if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
        return "must be affine (last row 0 0 0 1), got " + num(m[12]) + " " + num(m[13]) + " " + num(m[14]) + " " +
               num(m[15]);
    Vec3d rows[3];
    for (int r = 0; r < 3; ++r) {
        const double n = std::hypot(m[4 * r], std::hypot(m[4 * r + 1], m[4 * r + 2]));
        if (!(n > 0)) return "must be invertible (row " + std::to_string(r) + " of the 3x3 part is zero)";
        rows[r] = {m[4 * r] / n, m[4 * r + 1] / n, m[4 * r + 2] / n};
    }
    const double det = dot(rows[0], cross(rows[1], rows[2]));
    if (!(std::fabs(det) > 1e-12))
        return "must be invertible (the 3x3 part with unit rows has determinant " + num(det) + ")";
    return "";
}

std::string MeshTransform::problem() const {
    if (matrix) {
        const std::string p = matrix_problem(*matrix);
        return p.empty() ? p : "matrix: " + p;
    }
    std::string p;
    if (!(p = translate_problem(translate)).empty()) return "translate: " + p;
    if (!(p = rotate_deg_problem(rotate_deg)).empty()) return "rotate_deg: " + p;
    if (!(p = scale_problem(scale)).empty()) return "scale: " + p;
    return "";
}

}  // namespace octray
