// octray/vec3.hpp — a 3-vector over any lane type.
//
// Vec3<T> works for T = float, double and xsimd::batch<...>: the packet kernels
// and the scalar reference share it. Only arithmetic lives here; anything that
// needs a square root or a division takes a precision mode and lives in
// kernels/ (packet path) or reference.hpp (double oracle).
#pragma once

namespace octray {

template <class T>
struct Vec3 {
    T x{}, y{}, z{};

    constexpr Vec3() = default;
    constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    // Broadcast from another lane type (float -> batch, double -> float, ...).
    template <class U>
    explicit constexpr Vec3(const Vec3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}

    friend constexpr Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend constexpr Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend constexpr Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
    friend constexpr Vec3 operator*(const Vec3& a, const T& s) { return {a.x * s, a.y * s, a.z * s}; }
    friend constexpr Vec3 operator*(const T& s, const Vec3& a) { return {a.x * s, a.y * s, a.z * s}; }
    // Component-wise product: the shading model's ⋆ operator on colours.
    friend constexpr Vec3 hadamard(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
    Vec3& operator+=(const Vec3& b) { x = x + b.x; y = y + b.y; z = z + b.z; return *this; }
};

template <class T>
constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

template <class T>
constexpr Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

template <class T>
constexpr T length_squared(const Vec3<T>& a) { return dot(a, a); }

using Vec3d = Vec3<double>;
using Vec3f = Vec3<float>;

// x rounded to float, as a double. Through a volatile: GCC 12.2's SLP
// vectorizer (at -O3, and -O2 in places) takes the (double)(float)x round
// trip of paired components for a no-op and leaves them unrounded.
inline double round_to_float(double x) {
    volatile float f = float(x);
    return f;
}
inline Vec3d round_to_float(const Vec3d& v) { return {round_to_float(v.x), round_to_float(v.y), round_to_float(v.z)}; }

}  // namespace octray
