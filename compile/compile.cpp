// compile/compile.cpp — Scene (AoS, double) -> PacketScene (SoA, float).
#include "compile/primitive_bounds.hpp"
#include "kernels/scene_data.hpp"
#include <octray/packet.hpp>
#include <octray/reference.hpp>
#include "reference/reference_parts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <type_traits>

namespace octray {
namespace {


Vec3d normalized(const Vec3d& v) { return unit_direction(v); }  // the reference's normalization (scene.hpp)

void push(Floats& a, double v) { a.push_back(float(v)); }
void push3(Floats& x, Floats& y, Floats& z, const Vec3d& v) { push(x, v.x), push(y, v.y), push(z, v.z); }
// Element k of arrays sized beforehand (size_arrays): no push_back's
// capacity check and call per float.
void put(Floats& a, std::size_t k, double v) { a[k] = float(v); }
void put3(Floats& x, Floats& y, Floats& z, std::size_t k, const Vec3d& v) { put(x, k, v.x), put(y, k, v.y), put(z, k, v.z); }

// Triangle k (index within the type), primitive `id`, into its block
// (TriangleBlocks), whose header place_triangle_blocks wrote.
void put_triangle(SceneData& s, std::size_t k, const Triangle& t, std::size_t id) {
    float* at = reinterpret_cast<float*>(s.bvh.nodes.data()) + s.triangles.block_of[k];
    std::uint32_t k0, n;
    std::memcpy(&k0, at, sizeof k0);
    std::memcpy(&n, at + 1, sizeof n);
    float* field = at + kTriangleHeader + (k - k0);
    const Vec3d normal = normalized(cross(t.v1 - t.v0, t.v2 - t.v0));
    for (const Vec3d& v : {t.v0, t.v1, t.v2, normal})
        for (const double c : {v.x, v.y, v.z}) *field = float(c), field += n;
    *field = float(id);  // exact: compile() refuses 2^24 primitives or more
}

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

// As pad, after a whole packet width of zeros past the last element, for the
// types tested a leaf's run at a time (test_run loads 8 from the run's start;
// lanes past the run are off). An empty array stays empty: no leaf loads it.
template <class... A>
void pad_for_runs(A&... arrays) {
    auto one = [](Floats& a) {
        if (!a.empty()) a.resize(a.size() + std::size_t(kPacketWidth), 0.0f);
    };
    (one(arrays), ...);
    pad(arrays...);
}

// Each type's arrays sized for its primitives (written by index), with room
// for the padding compile() adds (a whole packet width past the last one,
// rounded up to a multiple of it), so no array regrows (a grown vector holds
// up to twice its size).
void size_arrays(SceneData& s) {
    auto room = [&](PrimitiveType type, std::initializer_list<Floats*> arrays) {
        const std::size_t count = std::size_t(s.count[std::size_t(type)]);
        if (count == 0) return;  // stays empty
        for (Floats* a : arrays) a->reserve(count + 2 * std::size_t(kPacketWidth)), a->resize(count);
    };
    auto& sp = s.spheres;
    room(PrimitiveType::sphere, {&sp.cx, &sp.cy, &sp.cz, &sp.radius, &sp.cx_lo, &sp.cy_lo, &sp.cz_lo});
    auto& p = s.planes;
    room(PrimitiveType::plane, {&p.px, &p.py, &p.pz, &p.nx, &p.ny, &p.nz});
    auto& d = s.disks;
    room(PrimitiveType::disk, {&d.cx, &d.cy, &d.cz, &d.nx, &d.ny, &d.nz, &d.radius2});
    auto& r = s.rectangles;
    room(PrimitiveType::rectangle, {&r.cx, &r.cy, &r.cz, &r.nx, &r.ny, &r.nz, &r.dual_ax, &r.dual_ay, &r.dual_az,
                                    &r.dual_bx, &r.dual_by, &r.dual_bz});
    auto& b = s.boxes;
    room(PrimitiveType::box, {&b.minx, &b.miny, &b.minz, &b.maxx, &b.maxy, &b.maxz});
}

// The centres' residuals in 16 bits (SphereArrays::cx_q..), where every one
// decodes to within 2^-27 of its sphere's radius of the float residual (an
// eighth of u of the radius: the normal's bound does not move); false, and
// nothing kept, where one does not.
bool compress_residuals(SphereArrays& sp) {
    const std::size_t n = sp.cx_lo.size();
    const Floats* c[3] = {&sp.cx, &sp.cy, &sp.cz};
    const Floats* lo[3] = {&sp.cx_lo, &sp.cy_lo, &sp.cz_lo};
    AlignedVector<std::int16_t>* q[3] = {&sp.cx_q, &sp.cy_q, &sp.cz_q};
    for (int a = 0; a < 3; ++a) q[a]->resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double tolerance = double(sp.radius[i]) * 0x1p-27;
        for (int a = 0; a < 3; ++a) {
            const float centre = (*c[a])[i], residual = (*lo[a])[i];
            const float unit = residual_unit(centre);
            const double k = unit > 0.0f ? std::nearbyint(double(residual) / double(unit)) : 0.0;
            // A non-finite residual (a centre beyond float range; NaN fails
            // the compare): floats. k = +-2^15 is a residual of exactly half
            // an ulp (a tie): +2^15 is stored as 2^15 - 1, one unit off,
            // which the tolerance below accepts or not like any other error.
            const bool fits = std::abs(k) <= 32768.0;
            const std::int16_t stored = fits ? std::int16_t(std::clamp(k, -32768.0, 32767.0)) : std::int16_t(0);
            (*q[a])[i] = stored;
            if (!fits || !(std::abs(double(residual16(centre, stored)) - double(residual)) <= tolerance)) {
                for (int b = 0; b < 3; ++b) AlignedVector<std::int16_t>().swap(*q[b]);
                return false;
            }
        }
    }
    return true;
}

// Materials and meshes (PrimitiveOwners); material_of sized, not filled.
void fill_owners(const Scene& scene, const std::vector<std::size_t>& first_triangle, std::size_t total,
               PrimitiveOwners& o) {
    o.object_count = int(scene.objects.size());
    const bool common = std::all_of(scene.objects.begin(), scene.objects.end(),
                                    [&](const Object& x) { return x.material == scene.objects.front().material; });
    if (common) {
        o.common_material = scene.objects.empty() ? 0.0f : float(scene.objects.front().material);
    } else {
        o.material_of.reserve(total + std::size_t(kPacketWidth));
        o.material_of.resize(total);
    }
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        o.mesh_first.push_back(float(first_triangle[m]));
        o.mesh_material.push_back(float(scene.meshes[m].material));
    }
    pad(o.mesh_material);
}

// Writes primitive `id` as element k of its type's arrays.
void put_primitive(SceneData& s, std::size_t k, const Shape& shape, std::size_t id) {
    std::visit(
        [&](const auto& p) {
            using P = std::decay_t<decltype(p)>;
            if constexpr (std::is_same_v<P, Sphere>) {
                auto& a = s.spheres;
                put3(a.cx, a.cy, a.cz, k, p.center);
                put3(a.cx_lo, a.cy_lo, a.cz_lo, k, p.center - round_to_float(p.center));
                put(a.radius, k, p.radius);
            } else if constexpr (std::is_same_v<P, Plane>) {
                auto& a = s.planes;
                put3(a.px, a.py, a.pz, k, p.point);
                put3(a.nx, a.ny, a.nz, k, normalized(p.normal));
            } else if constexpr (std::is_same_v<P, Disk>) {
                auto& a = s.disks;
                put3(a.cx, a.cy, a.cz, k, p.center);
                put3(a.nx, a.ny, a.nz, k, normalized(p.normal));
                put(a.radius2, k, p.radius * p.radius);
            } else if constexpr (std::is_same_v<P, Rectangle>) {
                // Dual basis of (a, b) in their plane: dual_a.a = 1, dual_a.b = 0, ...
                auto& a = s.rectangles;
                const Vec3d n = normalized(cross(p.a, p.b));
                const Vec3d bn = cross(p.b, n), na = cross(n, p.a);
                put3(a.cx, a.cy, a.cz, k, p.corner);
                put3(a.nx, a.ny, a.nz, k, n);
                put3(a.dual_ax, a.dual_ay, a.dual_az, k, bn * (1.0 / dot(p.a, bn)));
                put3(a.dual_bx, a.dual_by, a.dual_bz, k, na * (1.0 / dot(p.b, na)));
            } else if constexpr (std::is_same_v<P, Box>) {
                auto& a = s.boxes;
                put3(a.minx, a.miny, a.minz, k, p.min);
                put3(a.maxx, a.maxy, a.maxz, k, p.max);
            } else {
                put_triangle(s, k, p, id);
            }
        },
        shape);
}

// The builder's options: sah's, where a deprecated field of CompileOptions
// that differs from its default stands in for its sah twin.
bvh::BuildOptions build_options(const CompileOptions& o) {
    const SahOptions defaults;
    bvh::BuildOptions b;
    b.max_leaf_size = o.sah.max_leaf_size;
    b.bins = o.sah.bins;
    b.traversal_cost = o.sah.traversal_cost;
    b.intersection_cost = o.sah.intersection_cost;
    b.leaf_block = o.sah.leaf_block;
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
    if (o.max_leaf_size != defaults.max_leaf_size) b.max_leaf_size = o.max_leaf_size;
    if (o.bins != defaults.bins) b.bins = o.bins;
    if (o.traversal_cost != defaults.traversal_cost) b.traversal_cost = o.traversal_cost;
    if (o.intersection_cost != defaults.intersection_cost) b.intersection_cost = o.intersection_cost;
    if (o.leaf_block != defaults.leaf_block) b.leaf_block = o.leaf_block;
#pragma GCC diagnostic pop
    b.threads = o.threads;
    return b;
}

// Acceleration::none: every node's children made infinite boxes, so a walk
// enters every node and tests every bounded primitive.
void open_every_node(bvh::Bvh8& tree) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    for (bvh::Node8& node : tree.nodes)
        for (int c = 0; c < bvh::kWidth; ++c)
            if (node.child[c] != bvh::kEmptySlot)
                node.lo_x[c] = node.lo_y[c] = node.lo_z[c] = -inf, node.hi_x[c] = node.hi_y[c] = node.hi_z[c] = inf;
}

// ---- compile()'s phases, in the order it runs them ----------------------------

// Primitives per type, and each type's first compiled id.
void count_primitives(const Scene& scene, SceneData& s) {
    for (const Object& o : scene.objects) ++s.count[std::size_t(primitive_type(o.shape))];
    s.count[std::size_t(PrimitiveType::triangle)] += int(scene.mesh_triangle_count());
    for (int t = 1; t < kPrimitiveTypeCount; ++t)
        s.offset[std::size_t(t)] = s.offset[std::size_t(t - 1)] + s.count[std::size_t(t - 1)];
}

// Every primitive by type, in primitive-id order (scene.hpp: objects, then
// mesh triangles), and the BVH's input: the bounded ones' boxes and types.
struct Collected {
    std::array<std::vector<std::size_t>, kPrimitiveTypeCount> of_type;  // primitive ids per type
    std::vector<std::size_t> first_triangle;  // per mesh: its first triangle's primitive id
    bvh::BuildInput input;
    std::size_t total = 0;  // primitives
};

Collected collect_primitives(const Scene& scene, const SceneData& s) {
    Collected c;
    const std::size_t object_count = scene.objects.size();
    c.input.kind_count = kPrimitiveTypeCount;
    for (int t = 0; t < kPrimitiveTypeCount; ++t) c.of_type[std::size_t(t)].reserve(std::size_t(s.count[std::size_t(t)]));
    const std::size_t bounded = std::size_t(std::accumulate(s.count.begin(), s.count.end(), 0) -
                                            s.count[std::size_t(PrimitiveType::plane)]);
    c.input.boxes.reserve(bounded);
    c.input.kind.reserve(bounded);
    for (std::size_t i = 0; i < object_count; ++i) {
        const PrimitiveType type = primitive_type(scene.objects[i].shape);
        c.of_type[std::size_t(type)].push_back(i);
        if (type == PrimitiveType::plane) continue;
        c.input.boxes.push_back(box_of(scene.objects[i].shape));
        c.input.kind.push_back(std::uint8_t(type));
    }
    c.first_triangle.reserve(scene.meshes.size());
    std::size_t id = object_count;
    for (const Mesh& m : scene.meshes) {
        c.first_triangle.push_back(id);
        for (std::size_t k = 0; k < m.triangle_count(); ++k, ++id) {
            c.of_type[std::size_t(PrimitiveType::triangle)].push_back(id);
            c.input.boxes.push_back(box_of(reference::mesh_triangle(m, k)));
            c.input.kind.push_back(std::uint8_t(PrimitiveType::triangle));
        }
    }
    c.total = id;
    return c;
}

// Each leaf's triangles a block beside its parent node (TriangleBlocks): the
// blocks placed, their headers written, block_of filled.
void place_triangle_blocks(SceneData& s) {
    constexpr int tri = int(PrimitiveType::triangle);
    std::vector<std::uint32_t> floats(s.bvh.leaves.size(), 0);
    for (std::size_t l = 0; l < floats.size(); ++l)
        if (const std::uint32_t n = s.bvh.leaves[l].count[tri]; n > 0) floats[l] = kTriangleHeader + kTriangleFields * n;
    if (std::all_of(floats.begin(), floats.end(), [](std::uint32_t f) { return f == 0; })) return;
    bvh::place_leaf_blocks(s.bvh, floats);
    s.triangles.block_of.resize(std::size_t(s.count[std::size_t(tri)]));
    float* nodes = reinterpret_cast<float*>(s.bvh.nodes.data());
    for (const bvh::Leaf& l : s.bvh.leaves) {
        const std::uint32_t n = l.count[tri], k0 = l.begin[tri];
        if (n == 0) continue;
        std::memcpy(nodes + l.block, &k0, sizeof k0);
        std::memcpy(nodes + l.block + 1, &n, sizeof n);
        for (std::uint32_t k = k0; k < k0 + n; ++k) s.triangles.block_of[k] = l.block;
    }
}

// The one BVH over the bounded primitives; returns its leaf order per type
// (read once, by lay_out_primitives; not kept in the scene).
std::vector<std::vector<std::uint32_t>> build_tree(const bvh::BuildInput& input, const CompileOptions& options,
                                                   SceneData& s) {
    s.bvh = bvh::build_bvh8(input, build_options(options));
    if (options.acceleration == CompileOptions::Acceleration::none) open_every_node(s.bvh);
    place_triangle_blocks(s);
    // A walked tree whose leaves are all inline needs no leaf records.
    if (s.bvh.primitive_count() > kTestAllPrimitives && bvh::every_leaf_inline(s.bvh))
        AlignedVector<bvh::Leaf>().swap(s.bvh.leaves);
    std::vector<std::vector<std::uint32_t>> order = std::move(s.bvh.order);
    s.bvh.order.clear();
    return order;
}

// Each type's arrays in compiled order (the tree's leaf order; planes in
// scene order), the maps between compiled and primitive ids, and the owners.
void lay_out_primitives(const Scene& scene, const Collected& c, const std::vector<std::vector<std::uint32_t>>& order,
                        SceneData& s) {
    const std::size_t object_count = scene.objects.size();
    size_arrays(s);
    for (Floats* f : {&s.object_of.wide, &s.compiled_of.wide}) f->reserve(c.total + std::size_t(kPacketWidth));
    s.object_of.wide.resize(c.total);
    s.compiled_of.wide.resize(c.total);
    fill_owners(scene, c.first_triangle, c.total, s.owners);
    Floats& material_of = s.owners.material_of;
    for (int type = 0; type < kPrimitiveTypeCount; ++type) {
        const std::vector<std::size_t>& ids = c.of_type[std::size_t(type)];
        const bool planes = type == int(PrimitiveType::plane);
        auto id_at = [&](std::size_t pos) { return ids[planes ? pos : order[std::size_t(type)][pos]]; };
        for (std::size_t pos = 0; pos < ids.size(); ++pos) {
            const std::size_t i = id_at(pos);
            // Leaf order visits the scene's objects out of order: their reads
            // miss the cache, so fetch a few ahead.
            if (constexpr std::size_t ahead = 8; pos + ahead < ids.size())
                if (const std::size_t next = id_at(pos + ahead); next < object_count)
                    __builtin_prefetch(&scene.objects[next]), __builtin_prefetch(&scene.objects[next].material);
            const std::size_t cid = std::size_t(s.offset[std::size_t(type)]) + pos;
            s.object_of.wide[cid] = float(i);
            s.compiled_of.wide[i] = float(cid);
            if (i < object_count) {
                if (!material_of.empty()) material_of[cid] = float(scene.objects[i].material);
                put_primitive(s, pos, scene.objects[i].shape, i);
                continue;
            }
            const std::size_t m = std::size_t(s.owners.mesh(int(i)));
            if (!material_of.empty()) material_of[cid] = float(scene.meshes[m].material);
            put_triangle(s, pos, reference::mesh_triangle(scene.meshes[m], i - c.first_triangle[m]), i);
        }
    }
}

// Padding for whole-width loads past each array's end; the spheres' centre
// residuals dropped where zero, else narrowed to 16 bits where they fit; the
// id maps narrowed to 16 bits where they fit.
void pad_and_narrow(SceneData& s, std::size_t total) {
    SphereArrays& sp = s.spheres;
    pad_for_runs(sp.cx, sp.cy, sp.cz, sp.radius, sp.cx_lo, sp.cy_lo, sp.cz_lo);
    // Float centres leave every residual zero: no arrays, and the normal reads none.
    auto is_zero = [](const Floats& f) { return std::all_of(f.begin(), f.end(), [](float x) { return x == 0.0f; }); };
    if (is_zero(sp.cx_lo) && is_zero(sp.cy_lo) && is_zero(sp.cz_lo))
        for (Floats* f : {&sp.cx_lo, &sp.cy_lo, &sp.cz_lo}) Floats().swap(*f);  // released (= {} keeps the capacity)
    else if (compress_residuals(sp))
        for (Floats* f : {&sp.cx_lo, &sp.cy_lo, &sp.cz_lo}) Floats().swap(*f);
    pad(s.planes.px, s.planes.py, s.planes.pz, s.planes.nx, s.planes.ny, s.planes.nz);
    pad(s.disks.cx, s.disks.cy, s.disks.cz, s.disks.nx, s.disks.ny, s.disks.nz, s.disks.radius2);
    auto& r = s.rectangles;
    pad(r.cx, r.cy, r.cz, r.nx, r.ny, r.nz, r.dual_ax, r.dual_ay, r.dual_az, r.dual_bx, r.dual_by, r.dual_bz);
    pad(s.boxes.minx, s.boxes.miny, s.boxes.minz, s.boxes.maxx, s.boxes.maxy, s.boxes.maxz);
    if (total == 0) {  // keep the miss lanes' id lookups in bounds for an object-free scene
        s.object_of.wide.push_back(0.0f);
        s.compiled_of.wide.push_back(0.0f);
    }
    pad(s.object_of.wide, s.compiled_of.wide, s.owners.material_of);
    s.object_of.narrow();
    s.compiled_of.narrow();
}

// Lights: directions unit, ls * colour premultiplied; point lights by attenuation.
void compile_lights(const Scene& scene, SceneData& s) {
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
    if (scene.ambient && scene.ambient_occlusion) {
        const AmbientOcclusion& ao = *scene.ambient_occlusion;
        s.occlusion = {ao.samples, float(ao.distance), float(ao.min_amount)};
    }
}

// Materials' terms, premultiplied in double as the reference computes them.
void compile_materials(const Scene& scene, SceneData& s) {
    for (const Material& m : scene.materials) {
        const Vec3d amb = reference::ambient_term(scene, m);  // the reference's eq. 7 and 8 terms, in double
        const Vec3d dif = reference::lambertian_brdf(m);
        push3(s.ambient_r, s.ambient_g, s.ambient_b, amb);
        push3(s.diffuse_r, s.diffuse_g, s.diffuse_b, dif);
    }
    if (scene.materials.empty()) {  // keep gathers in bounds for an object-free scene
        push3(s.ambient_r, s.ambient_g, s.ambient_b, Vec3d{});
        push3(s.diffuse_r, s.diffuse_g, s.diffuse_b, Vec3d{});
    }
}

// Background, clamp colour, tone map and gamma.
void compile_render_settings(const Scene& scene, SceneData& s) {
    for (int i = 0; i < 3; ++i) {
        s.background[i] = float(i == 0 ? scene.background.x : i == 1 ? scene.background.y : scene.background.z);
        const Vec3d& cc = scene.render.clamp_color;
        s.clamp_color[i] = float(i == 0 ? cc.x : i == 1 ? cc.y : cc.z);
    }
    s.tonemap = scene.render.tonemap;
    s.inv_gamma = float(1.0 / scene.render.gamma);
}

// The camera's frame and image-plane mapping, in double (camera rays are
// formed in double and rounded once, as the reference forms them).
void compile_camera(const Camera& c, PacketCamera& pc) {
    const Vec3d w = normalized(c.eye - c.look_at);
    const Vec3d u = normalized(cross(c.up, w));
    const Vec3d v = cross(w, u);
    auto put = [](double* dst, const Vec3d& x) { dst[0] = x.x, dst[1] = x.y, dst[2] = x.z; };
    put(pc.eye, c.eye), put(pc.u, u), put(pc.v, v), put(pc.w, w);
    pc.orthographic = c.type == CameraType::orthographic;
    const double half = pc.orthographic ? c.height_world / 2 : std::tan(c.fov_y * kPi / 360.0);
    pc.scale_y = half;
    pc.scale_x = half * c.width / c.height;
    pc.width = c.width;
    pc.height = c.height;
    pc.sx_step = 2.0 * pc.scale_x / c.width, pc.sx_first = (1.0 / c.width - 1.0) * pc.scale_x;
    pc.sy_step = -2.0 * pc.scale_y / c.height, pc.sy_first = (1.0 - 1.0 / c.height) * pc.scale_y;
    for (int i = 0; i < 3; ++i) {
        const double shared = pc.orthographic ? -pc.w[i] : pc.eye[i];
        pc.shared_hi[i] = float(shared);
        pc.shared_lo[i] = float(shared - round_to_float(shared));  // (GCC 12 folds shared - double(float(shared)) to 0)
    }
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

const SceneData& packet_scene_data(const PacketScene& scene) noexcept { return scene_data(scene); }

PacketScene compile(const Scene& scene, const CompileOptions& options) {
    validate(scene);  // includes the limits on primitives and materials (scene.hpp)

    PacketScene compiled;
    SceneData& s = *compiled.data_;
    s.features = features_of(scene);
    count_primitives(scene, s);
    // Bounded primitives go into one BVH; its leaf order is each type's
    // compiled order. Planes keep scene order.
    const Collected collected = collect_primitives(scene, s);
    const std::vector<std::vector<std::uint32_t>> order = build_tree(collected.input, options, s);
    lay_out_primitives(scene, collected, order, s);
    pad_and_narrow(s, collected.total);
    compile_lights(scene, s);
    compile_materials(scene, s);
    compile_render_settings(scene, s);
    compile_camera(scene.camera, s.camera);
    return compiled;
}

}  // namespace octray
