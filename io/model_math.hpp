// io/model_math.hpp — what the model code shares about 4x4 matrices and
// vectors in double: their product, finiteness, and how messages print them
// (mesh_transform.cpp, model_loader.cpp, ply_writer.cpp). Internal to io/.
#pragma once

#include "model_loader.hpp"

#include <cmath>
#include <sstream>
#include <string>

namespace octray::model_math {

inline Matrix4d multiply(const Matrix4d& a, const Matrix4d& b) {
    Matrix4d r{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += a[4 * i + k] * b[4 * k + j];
            r[4 * i + j] = s;
        }
    return r;
}

inline bool finite3(const Vec3d& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

inline std::string num(double v) {
    std::ostringstream o;
    o.precision(17);
    o << v;
    return o.str();
}

inline std::string vec_str(const Vec3d& v) { return "(" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ")"; }

}  // namespace octray::model_math
