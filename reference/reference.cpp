// reference/reference.cpp — the scalar double reference renderer (the oracle).
//
// Shaped like the equations of docs/shading-model.md: one camera ray per
// pixel, the nearest hit over all objects, then Matte::shade.
// Every choice here is the simplest correct one; speed is not a goal.
#include <octray/reference.hpp>
#include "reference/reference_parts.hpp"

#include "kernels/shading/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace octray::reference {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double length(const Vec3d& a) { return std::sqrt(length_squared(a)); }

// Divide by the length (not multiply by 1/length): one rounding per component.
Vec3d normalize(const Vec3d& a) {
    const double len = length(a);
    return {a.x / len, a.y / len, a.z / len};
}

double component(const Vec3d& a, int k) { return k == 0 ? a.x : (k == 1 ? a.y : a.z); }

Vec3d axis_vector(int k, double sign) {
    Vec3d n;
    (k == 0 ? n.x : (k == 1 ? n.y : n.z)) = sign;
    return n;
}

bool finite(const Vec3d& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

Vec3d point_at(const Ray& ray, double t) { return ray.origin + ray.direction * t; }

bool in_interval(double t, double tmin, double tmax) { return t > tmin && t < tmax; }

// The nearer of two candidate parameters inside (tmin, tmax); t0 <= t1.
std::optional<double> nearest_of(double t0, double t1, double tmin, double tmax) {
    if (in_interval(t0, tmin, tmax)) return t0;
    if (in_interval(t1, tmin, tmax)) return t1;
    return std::nullopt;
}

// |f|^2 - r^2 without cancellation: each square split exactly with an FMA
// (x*x = p + fma(x, x, -p)) and the sum's rounding errors recovered (TwoSum),
// so near a huge sphere's surface, where |f|^2 and r^2 agree to many digits,
// c keeps its relative accuracy (the plain difference loses |f|^2 / |c| ulps:
// a radius-1e9 sphere seen from 1 above would leave 1e-7 in the oracle).
double norm2_minus(const Vec3d& f, double r) {
    const double terms[4] = {f.x * f.x, f.y * f.y, f.z * f.z, -(r * r)};
    double sum = 0, err = std::fma(f.x, f.x, -terms[0]) + std::fma(f.y, f.y, -terms[1]) +
                         std::fma(f.z, f.z, -terms[2]) - std::fma(r, r, terms[3]);
    for (double x : terms) {
        const double s = sum + x, bv = s - sum;
        err += (sum - (s - bv)) + (x - bv);
        sum = s;
    }
    return sum + err;
}

// Sphere. BOUNDARY RULE: a tangent ray (discriminant exactly 0) is a hit.
// From inside, the near root is behind the origin, so the far root is returned.
// Discriminant in the perpendicular-distance form b^2 - 4ac = 4a (r - |v|)(r + |v|),
// v = f - (f.d / d.d) d the offset of the centre from the ray's line (pbrt-v4,
// "Sphere::BasicIntersect"): no cancellation for far or huge spheres. Roots by
// the stable quadratic q = -(b + sign(b) sqrt(disc)) / 2, t = q/a and c/q.
std::optional<double> intersect_sphere(const Sphere& s, const Ray& ray, double tmin, double tmax) {
    const Vec3d& d = ray.direction;
    const Vec3d f = ray.origin - s.center;
    const double a = dot(d, d);
    const double b = 2.0 * dot(f, d);
    const double c = norm2_minus(f, s.radius);
    const double vlen = length(f - d * (dot(f, d) / a));
    const double disc = 4.0 * a * (s.radius - vlen) * (s.radius + vlen);
    if (!(disc >= 0.0)) return std::nullopt;  // also rejects NaN
    const double root = std::sqrt(disc);
    const double q = -0.5 * (b + std::copysign(root, b));
    // q == 0 only when b == 0 and disc == 0: the origin is on the sphere moving
    // tangentially; both roots are 0 (and c/q would be 0/0).
    const double t0 = q / a;
    const double t1 = q == 0.0 ? t0 : c / q;
    return nearest_of(std::min(t0, t1), std::max(t0, t1), tmin, tmax);
}

// Infinite plane through p0 with normal n (any length). BOUNDARY RULE: a ray
// parallel to the plane (d.n == 0), including one lying in it, misses.
std::optional<double> intersect_plane_raw(const Vec3d& p0, const Vec3d& n, const Ray& ray, double tmin,
                                          double tmax) {
    const double dn = dot(ray.direction, n);
    if (dn == 0.0) return std::nullopt;
    const double t = dot(p0 - ray.origin, n) / dn;
    if (!in_interval(t, tmin, tmax)) return std::nullopt;
    return t;
}

// Disk. BOUNDARY RULE: the plane rule above, then |p - c|^2 <= r^2 — the rim is a hit.
std::optional<double> intersect_disk(const Disk& disk, const Ray& ray, double tmin, double tmax) {
    const auto t = intersect_plane_raw(disk.center, disk.normal, ray, tmin, tmax);
    if (!t || length_squared(point_at(ray, *t) - disk.center) > disk.radius * disk.radius) return std::nullopt;
    return t;
}

// Parallelogram corner + s a + t b. BOUNDARY RULE: the plane rule, then s and t
// in [0, 1] inclusive — edges and corners are hits. a and b need not be
// orthogonal: with n = a x b, q = p - corner = s a + t b gives q x b = s n and
// a x q = t n, so s = (q x b).n / n.n and t = (a x q).n / n.n (the dual basis).
std::optional<double> intersect_rectangle(const Rectangle& r, const Ray& ray, double tmin, double tmax) {
    const Vec3d n = cross(r.a, r.b);
    const auto t = intersect_plane_raw(r.corner, n, ray, tmin, tmax);
    if (!t) return std::nullopt;
    const Vec3d q = point_at(ray, *t) - r.corner;
    const double nn = dot(n, n);
    const double s = dot(cross(q, r.b), n) / nn;
    const double u = dot(cross(r.a, q), n) / nn;
    if (s < 0.0 || s > 1.0 || u < 0.0 || u > 1.0) return std::nullopt;
    return t;
}

// Axis-aligned box by the slab test. BOUNDARY RULE: closed — faces, edges and
// corners are hits, and so is a ray that only grazes (entry t == exit t). A
// direction component of 0 (where 1/d would be inf and 0*inf NaN) is handled
// explicitly: the slab then never ends, and the ray misses unless the origin
// lies in the closed slab (on its face counts). From inside, the exit face.
// `normal` receives the face of the slab whose t decided the hit (on a tie,
// e.g. through an edge, the lowest axis).
std::optional<double> intersect_box(const Box& box, const Ray& ray, double tmin, double tmax,
                                    Vec3d* normal = nullptr) {
    double t_enter = -kInf, t_exit = kInf;
    int enter_axis = -1, exit_axis = -1;
    double enter_sign = 0, exit_sign = 0;
    for (int k = 0; k < 3; ++k) {
        const double o = component(ray.origin, k), d = component(ray.direction, k);
        const double lo = component(box.min, k), hi = component(box.max, k);
        if (d == 0.0) {
            if (o < lo || o > hi) return std::nullopt;
            continue;
        }
        const double t_lo = (lo - o) / d, t_hi = (hi - o) / d;
        // Entering through the min face gives the outward normal -e_k.
        const double near = d > 0 ? t_lo : t_hi, far = d > 0 ? t_hi : t_lo;
        if (near > t_enter) { t_enter = near; enter_axis = k; enter_sign = d > 0 ? -1.0 : 1.0; }
        if (far < t_exit) { t_exit = far; exit_axis = k; exit_sign = d > 0 ? 1.0 : -1.0; }
    }
    if (t_enter > t_exit || enter_axis < 0) return std::nullopt;  // enter_axis < 0: zero direction
    if (in_interval(t_enter, tmin, tmax)) {
        if (normal) *normal = axis_vector(enter_axis, enter_sign);
        return t_enter;
    }
    if (in_interval(t_exit, tmin, tmax)) {
        if (normal) *normal = axis_vector(exit_axis, exit_sign);
        return t_exit;
    }
    return std::nullopt;
}

// Triangle: the watertight test of Woop, Benthin and Wald, "Watertight
// Ray/Triangle Intersection", JCGT 2(1), 2013 (section 3), in double.
// BOUNDARY RULE: edges and vertices are hits (a barycentric U, V or W of
// exactly 0 passes), so a ray through an edge shared by two triangles hits at
// least one of them. A ray in the triangle's plane, or a degenerate
// triangle, has det == 0 and misses.
std::optional<double> intersect_triangle(const Triangle& tri, const Ray& ray, double tmin, double tmax) {
    const Vec3d& dir = ray.direction;
    const double ad[3] = {std::fabs(dir.x), std::fabs(dir.y), std::fabs(dir.z)};
    const int kz = ad[0] >= ad[1] ? (ad[0] >= ad[2] ? 0 : 2) : (ad[1] >= ad[2] ? 1 : 2);
    int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
    if (component(dir, kz) < 0.0) std::swap(kx, ky);  // keep the winding
    const double dz = component(dir, kz);
    const double sx = component(dir, kx) / dz, sy = component(dir, ky) / dz, sz = 1.0 / dz;

    // Vertices relative to the origin, sheared so the ray runs along +z.
    const Vec3d A = tri.v0 - ray.origin, B = tri.v1 - ray.origin, C = tri.v2 - ray.origin;
    const double ax = component(A, kx) - sx * component(A, kz), ay = component(A, ky) - sy * component(A, kz);
    const double bx = component(B, kx) - sx * component(B, kz), by = component(B, ky) - sy * component(B, kz);
    const double cx = component(C, kx) - sx * component(C, kz), cy = component(C, ky) - sy * component(C, kz);

    // Scaled barycentrics: 2D edge functions of the sheared vertices.
    const double U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
    if ((U < 0 || V < 0 || W < 0) && (U > 0 || V > 0 || W > 0)) return std::nullopt;
    const double det = U + V + W;
    if (det == 0.0) return std::nullopt;
    const double T = U * (sz * component(A, kz)) + V * (sz * component(B, kz)) + W * (sz * component(C, kz));
    const double t = T / det;
    if (!in_interval(t, tmin, tmax)) return std::nullopt;
    return t;
}

// Outward normal of the box face nearest to p (ties: lower axis, min face first).
Vec3d box_normal_at(const Box& box, const Vec3d& p) {
    double best = kInf;
    Vec3d n;
    for (int k = 0; k < 3; ++k) {
        const double to_min = std::fabs(component(p, k) - component(box.min, k));
        const double to_max = std::fabs(component(p, k) - component(box.max, k));
        if (to_min < best) { best = to_min; n = axis_vector(k, -1.0); }
        if (to_max < best) { best = to_max; n = axis_vector(k, 1.0); }
    }
    return n;
}

// Is anything hit in (0, tmax) along the ray? (Shadow rays.)
bool occluded(const Scene& scene, const Ray& ray, double tmax) {
    return for_each_primitive(scene, [&](int, const Shape& shape) { return intersect(shape, ray, 0.0, tmax).has_value(); });
}

// Lambertian term of one light: (kd cd / pi) * (ls cl) * (n.l).
Vec3d lambert(const Material& m, const Vec3d& light_color, double ls, double n_dot_l) {
    return hadamard(lambertian_brdf(m), light_color * ls) * n_dot_l;
}

// Shadow rays start just off the surface on the side the facing normal points
// to (the lit side: n faces the viewer and n.l > 0), so they do not re-hit the
// surface they leave.
Vec3d shadow_origin(const Hit& hit) { return hit.point + hit.normal * (1e-9 * (1.0 + length(hit.point))); }

}  // namespace

Ray camera_ray(const Camera& cam, int i, int j) {
    const Vec3d w = normalize(cam.eye - cam.look_at);
    const Vec3d u = normalize(cross(cam.up, w));
    const Vec3d v = cross(w, u);
    const double half = cam.type == CameraType::pinhole ? std::tan(cam.fov_y * (kPi / 180.0) / 2.0)
                                                        : cam.height_world / 2.0;
    const double W = cam.width, H = cam.height;
    const double sx = (2.0 * (i + 0.5) / W - 1.0) * half * W / H;
    const double sy = (1.0 - 2.0 * (j + 0.5) / H) * half;
    if (cam.type == CameraType::pinhole) return {cam.eye, normalize(u * sx + v * sy - w)};
    return {cam.eye + u * sx + v * sy, -w};
}

std::optional<double> intersect(const Shape& shape, const Ray& ray, double tmin, double tmax) {
    return std::visit(
        [&](const auto& s) -> std::optional<double> {
            using S = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<S, Sphere>) return intersect_sphere(s, ray, tmin, tmax);
            else if constexpr (std::is_same_v<S, Plane>) return intersect_plane_raw(s.point, s.normal, ray, tmin, tmax);
            else if constexpr (std::is_same_v<S, Disk>) return intersect_disk(s, ray, tmin, tmax);
            else if constexpr (std::is_same_v<S, Rectangle>) return intersect_rectangle(s, ray, tmin, tmax);
            else if constexpr (std::is_same_v<S, Box>) return intersect_box(s, ray, tmin, tmax);
            else return intersect_triangle(s, ray, tmin, tmax);
        },
        shape);
}

// For a box, p alone does not say which slab decided a hit; this picks the
// nearest face. trace() instead uses the deciding slab (they differ only
// within rounding of an edge).
Vec3d geometric_normal(const Shape& shape, const Vec3d& p) {
    return std::visit(
        [&](const auto& s) -> Vec3d {
            using S = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<S, Sphere>) return normalize(p - s.center);
            else if constexpr (std::is_same_v<S, Plane> || std::is_same_v<S, Disk>) return unit_direction(s.normal);
            else if constexpr (std::is_same_v<S, Rectangle>) return normalize(cross(s.a, s.b));
            else if constexpr (std::is_same_v<S, Box>) return box_normal_at(s, p);
            else return normalize(cross(s.v1 - s.v0, s.v2 - s.v0));
        },
        shape);
}

// A ray with a non-finite or zero-length direction, or a non-finite origin,
// is degenerate input and misses (docs/shading-model.md, invalid input: background).
Hit trace(const Scene& scene, const Ray& ray, double tmin, double tmax) {
    Hit hit;
    if (!finite(ray.origin) || !finite(ray.direction) || length_squared(ray.direction) == 0.0) return hit;
    double nearest = tmax;
    // The interval is open at `nearest`, so an equal t keeps the lower id.
    for_each_primitive(scene, [&](int id, const Shape& shape) {
        if (const auto t = intersect(shape, ray, tmin, nearest)) {
            nearest = *t;
            hit.object = id;
        }
        return false;
    });
    if (hit.object < 0) return hit;
    const Shape shape = primitive_shape(scene, hit.object);
    hit.t = nearest;
    hit.point = point_at(ray, nearest);
    if (const Box* box = std::get_if<Box>(&shape)) intersect_box(*box, ray, tmin, tmax, &hit.normal);
    else hit.normal = geometric_normal(shape, hit.point);
    if (dot(hit.normal, ray.direction) > 0.0) hit.normal = -hit.normal;  // face the incoming ray
    return hit;
}

Shape primitive_shape(const Scene& scene, int id) {
    std::size_t k = std::size_t(id);
    if (k < scene.objects.size()) return scene.objects[k].shape;
    k -= scene.objects.size();
    for (const Mesh& m : scene.meshes) {
        if (k < m.triangle_count()) return mesh_triangle(m, k);
        k -= m.triangle_count();
    }
    return Sphere{};  // not reached for a valid id
}

int primitive_material(const Scene& scene, int id) {
    std::size_t k = std::size_t(id);
    if (k < scene.objects.size()) return scene.objects[k].material;
    k -= scene.objects.size();
    for (const Mesh& m : scene.meshes) {
        if (k < m.triangle_count()) return m.material;
        k -= m.triangle_count();
    }
    return -1;
}

Vec3d ambient_term(const Scene& scene, const Material& m) {
    return scene.ambient ? hadamard(m.cd * m.ka, scene.ambient->color * scene.ambient->ls) : Vec3d{};
}

Vec3d lambertian_brdf(const Material& m) { return m.cd * (m.kd / kPi); }

bool shadowed(const Scene& scene, const Hit& hit, const DirectionalLight& light) {
    return light.shadows && occluded(scene, {shadow_origin(hit), unit_direction(light.direction)}, kInf);
}

bool shadowed(const Scene& scene, const Hit& hit, const PointLight& light) {
    if (!light.shadows) return false;
    const Vec3d o = shadow_origin(hit), from_origin = light.position - o;
    return occluded(scene, {o, normalize(from_origin)}, length(from_origin));
}

// Matte::shade (docs/shading-model.md): ambient + the sum over lights with
// n.l > 0; point lights with 1/r^2 only under inverse_square. A light with
// shadows on is skipped when a shadow ray from p meets any object before it.
Vec3d shade(const Scene& scene, const Ray& /*ray*/, const Hit& hit, std::uint32_t pixel) {
    if (hit.object < 0) return scene.background;
    const Material& m = scene.materials.at(std::size_t(primitive_material(scene, hit.object)));
    const Vec3d& p = hit.point;
    const Vec3d& n = hit.normal;

    Vec3d L = ambient_term(scene, m) * occlusion_factor(scene, hit, pixel);
    for (const DirectionalLight& light : scene.directional_lights) {
        const double n_dot_l = dot(n, unit_direction(light.direction));  // scene.hpp: any length, used as unit
        if (!(n_dot_l > 0.0) || shadowed(scene, hit, light)) continue;
        L += lambert(m, light.color, light.ls, n_dot_l);
    }
    for (const PointLight& light : scene.point_lights) {
        const Vec3d to_light = light.position - p;
        const double r = length(to_light);
        const Vec3d l = normalize(to_light);  // NaN when the light sits at p: skipped below
        const double n_dot_l = dot(n, l);
        if (!(n_dot_l > 0.0) || shadowed(scene, hit, light)) continue;
        const double falloff = light.attenuation == Attenuation::inverse_square ? 1.0 / (r * r) : 1.0;
        L += lambert(m, light.color, light.ls * falloff, n_dot_l);
    }
    return L;
}

// Ambient occlusion. The frame about n: Duff et al., "Building an orthonormal
// basis, revisited" (JCGT 2017), n.z = -0 taken as + (kernels/shading/occlusion.hpp).
Vec3d occlusion_direction(const Vec3d& n, std::uint32_t pixel, int k) {
    double u1, u2;
    sampling::occlusion_uniforms(pixel, std::uint32_t(k), u1, u2);
    const double sign = n.z >= 0 ? 1.0 : -1.0;
    const double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
    const Vec3d b1{1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x}, b2{b, sign + n.y * n.y * a, -n.y};
    const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
    return b1 * (r * std::cos(phi)) + b2 * (r * std::sin(phi)) + n * std::sqrt(1.0 - u1);
}

Ray occlusion_ray(const Hit& hit, std::uint32_t pixel, int k) {
    return {shadow_origin(hit), occlusion_direction(hit.normal, pixel, k)};  // from where shadow rays leave
}

double occlusion_factor(const Scene& scene, const Hit& hit, std::uint32_t pixel) {
    if (!scene.ambient || !scene.ambient_occlusion || hit.object < 0) return 1.0;
    const AmbientOcclusion& ao = *scene.ambient_occlusion;
    int visible = 0;
    for (int k = 0; k < ao.samples; ++k) visible += !occluded(scene, occlusion_ray(hit, pixel, k), ao.distance);
    return std::max(ao.min_amount, double(visible) / double(ao.samples));
}

// Tone mapping per docs/shading-model.md, then gamma. Non-finite radiance still lands in
// gamut, by this rule: NaN counts as 0; under max_to_one, if any component is
// +inf the result is the limit of c / max(c) as it grows — inf components
// become 1, finite ones 0; clamp_to_color treats +inf as > 1 and saturate
// clips it to 1. Negative values (and -inf) clip to 0 in every mode.
Vec3d tonemap(const Vec3d& radiance, const RenderSettings& settings) {
    double c[3] = {radiance.x, radiance.y, radiance.z};
    for (double& x : c)
        if (std::isnan(x)) x = 0.0;
    switch (settings.tonemap) {
    case ToneMap::max_to_one: {
        const double mx = std::max({c[0], c[1], c[2]});
        if (mx == kInf)
            for (double& x : c) x = x == kInf ? 1.0 : 0.0;
        else if (mx > 1.0)
            for (double& x : c) x /= mx;
        break;
    }
    case ToneMap::clamp_to_color:
        if (c[0] > 1.0 || c[1] > 1.0 || c[2] > 1.0) {
            c[0] = settings.clamp_color.x;
            c[1] = settings.clamp_color.y;
            c[2] = settings.clamp_color.z;
        }
        break;
    case ToneMap::saturate: break;  // the clip below is the whole operator
    }
    for (double& x : c) {
        x = std::clamp(x, 0.0, 1.0);
        x = std::pow(x, 1.0 / settings.gamma);  // exact for gamma 1
    }
    return {c[0], c[1], c[2]};
}

std::uint8_t to_8bit(double c) {
    const double q = std::floor(255.0 * c + 0.5);
    if (!(q > 0.0)) return 0;  // also NaN
    return static_cast<std::uint8_t>(std::min(q, 255.0));
}

Image<double> render(const Scene& scene) {
    Image<double> img(scene.camera.width, scene.camera.height);
    for (int j = 0; j < img.height; ++j)
        for (int i = 0; i < img.width; ++i) {
            const Ray ray = camera_ray(scene.camera, i, j);
            const Vec3d L = shade(scene, ray, trace(scene, ray), std::uint32_t(j) * std::uint32_t(img.width) + std::uint32_t(i));
            double* px = img.pixel(i, j);
            px[0] = L.x; px[1] = L.y; px[2] = L.z;
        }
    return img;
}

ImageRGB8 to_display(const Image<double>& hdr, const RenderSettings& settings) {
    ImageRGB8 out(hdr.width, hdr.height);
    for (int j = 0; j < hdr.height; ++j)
        for (int i = 0; i < hdr.width; ++i) {
            const double* in = hdr.pixel(i, j);
            const Vec3d c = tonemap({in[0], in[1], in[2]}, settings);
            std::uint8_t* px = out.pixel(i, j);
            px[0] = to_8bit(c.x); px[1] = to_8bit(c.y); px[2] = to_8bit(c.z);
        }
    return out;
}

}  // namespace octray::reference
