// Small value types for the physics library: a 3-vector, a 3x3 rotation and a rigid transform, all
// double precision (positions in m). Everything here is constexpr/inline, noexcept and
// allocation-free, so the 1 kHz loop may use any of it.
#pragma once

#include <cmath>

namespace kerf::physics {

/// A 3-vector (a position in m, a direction, a velocity in m/s, a force in N ...).
struct Vec3 {
    double x = 0, y = 0, z = 0;

    constexpr Vec3& operator+=(const Vec3& o) noexcept {
        return x += o.x, y += o.y, z += o.z, *this;
    }
    constexpr Vec3& operator-=(const Vec3& o) noexcept {
        return x -= o.x, y -= o.y, z -= o.z, *this;
    }
    constexpr Vec3& operator*=(double s) noexcept { return x *= s, y *= s, z *= s, *this; }
    constexpr double operator[](int i) const noexcept { return i == 0 ? x : (i == 1 ? y : z); }
};

constexpr Vec3 operator+(Vec3 a, const Vec3& b) noexcept { return a += b; }
constexpr Vec3 operator-(Vec3 a, const Vec3& b) noexcept { return a -= b; }
constexpr Vec3 operator-(const Vec3& a) noexcept { return {-a.x, -a.y, -a.z}; }
constexpr Vec3 operator*(Vec3 a, double s) noexcept { return a *= s; }
constexpr Vec3 operator*(double s, Vec3 a) noexcept { return a *= s; }
constexpr bool operator==(const Vec3& a, const Vec3& b) noexcept {
    return a.x == b.x && a.y == b.y && a.z == b.z;
}
constexpr double dot(const Vec3& a, const Vec3& b) noexcept {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3 cross(const Vec3& a, const Vec3& b) noexcept {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr double norm2(const Vec3& a) noexcept { return dot(a, a); }
inline double norm(const Vec3& a) noexcept { return std::sqrt(dot(a, a)); }
/// `a` scaled to unit length; the zero vector stays zero.
inline Vec3 normalized(const Vec3& a) noexcept {
    const double n = norm(a);
    return n > 0 ? a * (1.0 / n) : Vec3{};
}
inline bool is_finite(const Vec3& a) noexcept {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

/// A 3x3 matrix, row-major: `m[r][c]`. Used as a rotation (orthonormal, det +1).
struct Mat3 {
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

    /// Column `c` (for a rotation: the image of basis axis c).
    constexpr Vec3 column(int c) const noexcept { return {m[0][c], m[1][c], m[2][c]}; }
};

constexpr Vec3 operator*(const Mat3& r, const Vec3& v) noexcept {
    return {r.m[0][0] * v.x + r.m[0][1] * v.y + r.m[0][2] * v.z,
            r.m[1][0] * v.x + r.m[1][1] * v.y + r.m[1][2] * v.z,
            r.m[2][0] * v.x + r.m[2][1] * v.y + r.m[2][2] * v.z};
}
/// transpose(r) * v: for a rotation, the inverse rotation applied to v.
constexpr Vec3 transpose_times(const Mat3& r, const Vec3& v) noexcept {
    return {r.m[0][0] * v.x + r.m[1][0] * v.y + r.m[2][0] * v.z,
            r.m[0][1] * v.x + r.m[1][1] * v.y + r.m[2][1] * v.z,
            r.m[0][2] * v.x + r.m[1][2] * v.y + r.m[2][2] * v.z};
}

/// The rotation of the unit quaternion (w, x, y, z); a non-unit quaternion is normalised first.
inline Mat3 rotation_from_quaternion(double w, double x, double y, double z) noexcept {
    const double n = std::sqrt(w * w + x * x + y * y + z * z);
    if (!(n > 0)) return Mat3{};
    w /= n, x /= n, y /= n, z /= n;
    Mat3 r;
    r.m[0][0] = 1 - 2 * (y * y + z * z), r.m[0][1] = 2 * (x * y - w * z),
    r.m[0][2] = 2 * (x * z + w * y);
    r.m[1][0] = 2 * (x * y + w * z), r.m[1][1] = 1 - 2 * (x * x + z * z),
    r.m[1][2] = 2 * (y * z - w * x);
    r.m[2][0] = 2 * (x * z - w * y), r.m[2][1] = 2 * (y * z + w * x),
    r.m[2][2] = 1 - 2 * (x * x + y * y);
    return r;
}

/// A rigid transform world_from_body: p_world = rotation * p_body + translation (m).
struct RigidTransform {
    Mat3 rotation;
    Vec3 translation;

    /// Body point -> world point.
    constexpr Vec3 apply(const Vec3& p) const noexcept { return rotation * p + translation; }
    /// World point -> body point.
    constexpr Vec3 apply_inverse(const Vec3& p) const noexcept {
        return transpose_times(rotation, p - translation);
    }
    /// Body direction -> world direction.
    constexpr Vec3 rotate(const Vec3& d) const noexcept { return rotation * d; }
    /// World direction -> body direction.
    constexpr Vec3 rotate_inverse(const Vec3& d) const noexcept {
        return transpose_times(rotation, d);
    }

    /// From a column-major 4x4 matrix (ipc::MeshBodyEntry::world_from_body), translation in m.
    static RigidTransform from_column_major(const float (&m)[16]) noexcept {
        RigidTransform t;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) t.rotation.m[r][c] = m[c * 4 + r];
        t.translation = {m[12], m[13], m[14]};
        return t;
    }
};

}  // namespace kerf::physics
