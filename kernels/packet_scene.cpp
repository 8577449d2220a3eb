// kernels/packet_scene.cpp — Scene (AoS, double) -> PacketScene (SoA, float).
#include "scene_data.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <type_traits>

namespace octray {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3d normalized(const Vec3d& v) { return v * (1.0 / std::sqrt(dot(v, v))); }

void push(Floats& a, double v) { a.push_back(float(v)); }
void push3(Floats& x, Floats& y, Floats& z, const Vec3d& v) { push(x, v.x), push(y, v.y), push(z, v.z); }

// Pads every array of `arrays` to a multiple of the packet width with copies
// of element 0 (or zeros), so whole-width loads past the end stay in bounds.
template <class... A>
void pad(A&... arrays) {
    auto one = [](Floats& a) {
        const float fill = a.empty() ? 0.0f : a.front();
        while (a.size() % 8 != 0) a.push_back(fill);
    };
    (one(arrays), ...);
}

// A sphere that contains the primitive (none for the unbounded plane).
std::optional<Bound> bound_of(const Shape& shape) {
    return std::visit(
        [](const auto& p) -> std::optional<Bound> {
            using P = std::decay_t<decltype(p)>;
            if constexpr (std::is_same_v<P, Sphere>) {
                return Bound{p.center, p.radius};
            } else if constexpr (std::is_same_v<P, Plane>) {
                return std::nullopt;
            } else if constexpr (std::is_same_v<P, Disk>) {
                return Bound{p.center, p.radius};
            } else if constexpr (std::is_same_v<P, Rectangle>) {
                const Vec3d c = p.corner + (p.a + p.b) * 0.5;
                const double r = std::max(std::sqrt(length_squared((p.a + p.b) * 0.5)), std::sqrt(length_squared((p.a - p.b) * 0.5)));
                return Bound{c, r};
            } else if constexpr (std::is_same_v<P, Box>) {
                return Bound{(p.min + p.max) * 0.5, std::sqrt(length_squared((p.max - p.min) * 0.5))};
            } else {
                const Vec3d c = (p.v0 + p.v1 + p.v2) * (1.0 / 3.0);
                const double r = std::max({std::sqrt(length_squared(p.v0 - c)), std::sqrt(length_squared(p.v1 - c)),
                                           std::sqrt(length_squared(p.v2 - c))});
                return Bound{c, r};
            }
        },
        shape);
}

// 30-bit Morton code of a point in [0,1]^3 (10 bits per axis, interleaved).
std::uint32_t morton(double x, double y, double z) {
    auto spread = [](double v) {
        std::uint32_t b = std::uint32_t(std::clamp(v, 0.0, 1.0) * 1023.0);
        b = (b | (b << 16)) & 0x030000FFu;
        b = (b | (b << 8)) & 0x0300F00Fu;
        b = (b | (b << 4)) & 0x030C30C3u;
        return (b | (b << 2)) & 0x09249249u;
    };
    return (spread(x) << 2) | (spread(y) << 1) | spread(z);
}

// Object indices in the order compile() lays primitives out: within each type,
// bounded primitives sorted along a Morton curve of their bounding-sphere
// centres (stable, so equal codes keep scene order), which makes each cluster
// of kClusterSize spatially compact; planes keep scene order.
std::vector<std::size_t> spatial_order(const Scene& scene) {
    std::vector<std::size_t> order(scene.objects.size());
    std::vector<std::optional<Bound>> b(scene.objects.size());
    Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (std::size_t i = 0; i < order.size(); ++i) {
        order[i] = i;
        b[i] = bound_of(scene.objects[i].shape);
        if (!b[i]) continue;
        const Vec3d& c = b[i]->center;
        lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
        hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
    }
    const Vec3d extent = hi - lo;
    const double scale = 1.0 / std::max({extent.x, extent.y, extent.z, 1e-300});
    std::vector<std::uint32_t> code(order.size(), 0);
    for (std::size_t i = 0; i < order.size(); ++i)
        if (b[i]) {
            const Vec3d q = (b[i]->center - lo) * scale;
            code[i] = morton(q.x, q.y, q.z);
        }
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t c) {
        const auto ta = scene.objects[a].shape.index(), tc = scene.objects[c].shape.index();
        return ta != tc ? ta < tc : code[a] < code[c];
    });
    return order;
}

}  // namespace

PacketScene::PacketScene() : data_(std::make_shared<SceneData>()) {}

const Features& PacketScene::features() const noexcept { return data_->features; }
int PacketScene::count(PrimitiveType type) const noexcept { return data_->count[std::size_t(type)]; }
int PacketScene::primitive_count() const noexcept {
    int n = 0;
    for (const int c : data_->count) n += c;
    return n;
}
int PacketScene::width() const noexcept { return data_->camera.width; }
int PacketScene::height() const noexcept { return data_->camera.height; }

SceneData& mutable_data(PacketScene& scene) {
    // Copy on write: the copies of a PacketScene share its data.
    if (scene.data_.use_count() != 1) scene.data_ = std::make_shared<SceneData>(*scene.data_);
    return *scene.data_;
}

PacketScene compile(const Scene& scene) {
    constexpr std::size_t kMaxIndex = std::size_t(1) << 24;  // indices travel as exact floats
    if (scene.objects.size() >= kMaxIndex || scene.materials.size() >= kMaxIndex)
        throw std::invalid_argument("octray::compile: more than 2^24 objects or materials");
    validate(scene);

    PacketScene compiled;
    SceneData& s = *compiled.data_;
    s.features = features_of(scene);
    for (const Object& o : scene.objects) ++s.count[std::size_t(primitive_type(o.shape))];
    for (int t = 1; t < kPrimitiveTypeCount; ++t) s.offset[std::size_t(t)] = s.offset[std::size_t(t - 1)] + s.count[std::size_t(t - 1)];

    s.object_of.resize(scene.objects.size());
    s.compiled_of.resize(scene.objects.size());
    s.material_of.resize(scene.objects.size());
    std::array<int, kPrimitiveTypeCount> next = s.offset;
    std::array<std::vector<Bound>, kPrimitiveTypeCount> bounds;
    for (const std::size_t i : spatial_order(scene)) {
        const Object& o = scene.objects[i];
        const int cid = next[std::size_t(primitive_type(o.shape))]++;
        s.object_of[std::size_t(cid)] = float(i);
        s.compiled_of[i] = float(cid);
        s.material_of[std::size_t(cid)] = float(o.material);
        if (const auto b = bound_of(o.shape)) bounds[std::size_t(primitive_type(o.shape))].push_back(*b);
        std::visit(
            [&](const auto& p) {
                using P = std::decay_t<decltype(p)>;
                if constexpr (std::is_same_v<P, Sphere>) {
                    auto& a = s.spheres;
                    push3(a.cx, a.cy, a.cz, p.center);
                    push(a.inv_radius, 1.0 / p.radius);
                    push(a.radius, p.radius);
                } else if constexpr (std::is_same_v<P, Plane>) {
                    auto& a = s.planes;
                    push3(a.px, a.py, a.pz, p.point);
                    push3(a.nx, a.ny, a.nz, normalized(p.normal));
                } else if constexpr (std::is_same_v<P, Disk>) {
                    auto& a = s.disks;
                    push3(a.cx, a.cy, a.cz, p.center);
                    push3(a.nx, a.ny, a.nz, normalized(p.normal));
                    push(a.radius2, p.radius * p.radius);
                } else if constexpr (std::is_same_v<P, Rectangle>) {
                    // Dual basis of (a, b) in their plane: dual_a.a = 1, dual_a.b = 0, ...
                    auto& a = s.rectangles;
                    const Vec3d n = normalized(cross(p.a, p.b));
                    const Vec3d bn = cross(p.b, n), na = cross(n, p.a);
                    push3(a.cx, a.cy, a.cz, p.corner);
                    push3(a.nx, a.ny, a.nz, n);
                    push3(a.dual_ax, a.dual_ay, a.dual_az, bn * (1.0 / dot(p.a, bn)));
                    push3(a.dual_bx, a.dual_by, a.dual_bz, na * (1.0 / dot(p.b, na)));
                } else if constexpr (std::is_same_v<P, Box>) {
                    auto& a = s.boxes;
                    push3(a.minx, a.miny, a.minz, p.min);
                    push3(a.maxx, a.maxy, a.maxz, p.max);
                } else {
                    auto& a = s.triangles;
                    const auto first = std::int32_t(a.vx.size());
                    push3(a.vx, a.vy, a.vz, p.v0);
                    push3(a.vx, a.vy, a.vz, p.v1);
                    push3(a.vx, a.vy, a.vz, p.v2);
                    a.i0.push_back(first), a.i1.push_back(first + 1), a.i2.push_back(first + 2);
                    push3(a.nx, a.ny, a.nz, normalized(cross(p.v1 - p.v0, p.v2 - p.v0)));
                }
            },
            o.shape);
    }
    for (int t = 0; t < kPrimitiveTypeCount; ++t) s.clusters[std::size_t(t)] = build_cluster_tree(bounds[std::size_t(t)]);
    // The per-type arrays were filled in spatial_order, which is type-major like the compiled ids.
    pad(s.spheres.cx, s.spheres.cy, s.spheres.cz, s.spheres.inv_radius, s.spheres.radius);
    pad(s.planes.px, s.planes.py, s.planes.pz, s.planes.nx, s.planes.ny, s.planes.nz);
    pad(s.disks.cx, s.disks.cy, s.disks.cz, s.disks.nx, s.disks.ny, s.disks.nz, s.disks.radius2);
    auto& r = s.rectangles;
    pad(r.cx, r.cy, r.cz, r.nx, r.ny, r.nz, r.dual_ax, r.dual_ay, r.dual_az, r.dual_bx, r.dual_by, r.dual_bz);
    pad(s.boxes.minx, s.boxes.miny, s.boxes.minz, s.boxes.maxx, s.boxes.maxy, s.boxes.maxz);
    auto& t = s.triangles;
    pad(t.vx, t.vy, t.vz, t.nx, t.ny, t.nz);
    pad(s.object_of, s.material_of, s.compiled_of);

    for (const DirectionalLight& l : scene.directional_lights) {
        auto& a = s.directional;
        push3(a.lx, a.ly, a.lz, normalized(l.direction));
        push3(a.r, a.g, a.b, l.color * l.ls);
        push(a.shadows, l.shadows ? 1.0 : 0.0);
        ++s.directional_count;
    }
    for (const PointLight& l : scene.point_lights) {
        const bool att = l.attenuation == Attenuation::inverse_square;
        auto& a = att ? s.point_attenuated : s.point;
        push3(a.px, a.py, a.pz, l.position);
        push3(a.r, a.g, a.b, l.color * l.ls);
        push(a.shadows, l.shadows ? 1.0 : 0.0);
        ++(att ? s.point_attenuated_count : s.point_count);
    }

    for (const Material& m : scene.materials) {
        const Vec3d amb = scene.ambient ? hadamard(m.cd * m.ka, scene.ambient->color * scene.ambient->ls) : Vec3d{};
        const Vec3d dif = m.cd * (m.kd / kPi);
        push3(s.ambient_r, s.ambient_g, s.ambient_b, amb);
        push3(s.diffuse_r, s.diffuse_g, s.diffuse_b, dif);
    }
    if (scene.materials.empty()) {  // keep gathers in bounds for an object-free scene
        push3(s.ambient_r, s.ambient_g, s.ambient_b, Vec3d{});
        push3(s.diffuse_r, s.diffuse_g, s.diffuse_b, Vec3d{});
    }

    for (int i = 0; i < 3; ++i) {
        s.background[i] = float(i == 0 ? scene.background.x : i == 1 ? scene.background.y : scene.background.z);
        const Vec3d& cc = scene.render.clamp_color;
        s.clamp_color[i] = float(i == 0 ? cc.x : i == 1 ? cc.y : cc.z);
    }
    s.tonemap = scene.render.tonemap;
    s.inv_gamma = float(1.0 / scene.render.gamma);

    const Camera& c = scene.camera;
    PacketCamera& pc = s.camera;
    const Vec3d w = normalized(c.eye - c.look_at);
    const Vec3d u = normalized(cross(c.up, w));
    const Vec3d v = cross(w, u);
    auto put = [](float* dst, const Vec3d& x) { dst[0] = float(x.x), dst[1] = float(x.y), dst[2] = float(x.z); };
    put(pc.eye, c.eye), put(pc.u, u), put(pc.v, v), put(pc.w, w);
    pc.orthographic = c.type == CameraType::orthographic;
    const double half = pc.orthographic ? c.height_world / 2 : std::tan(c.fov_y * kPi / 360.0);
    pc.scale_y = float(half);
    pc.scale_x = float(half * c.width / c.height);
    pc.width = c.width;
    pc.height = c.height;
    return compiled;
}

}  // namespace octray
