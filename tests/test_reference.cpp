// tests/test_reference.cpp — the oracle's camera rays and ray-primitive
// intersections (sphere, plane, disk, rectangle, box, triangle, nearest hit)
// checked against values worked out by hand (the arithmetic is in the
// comments) from the camera convention and the primitives' definitions in
// docs/shading-model.md. Shading: test_reference_shade.cpp; tone map and whole
// images: test_reference_image.cpp.
#include "reference_fixtures.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace octray;
using namespace octray::reference;
using namespace reference_fixtures;

// ---------------------------------------------------------------- camera ----

TEST_CASE("camera: pinhole corner and centre rays, pixel-centre convention") {
    // eye (0,0,5), look_at 0, up y: w = (0,0,1), u = up x w = (1,0,0), v = w x u = (0,1,0).
    // fov 90: tan 45deg = 1. 5x3 image.
    const Camera cam = camera_5x3(CameraType::pinhole, {0, 0, 5});
    // Pixel (0,0): sx = (2*0.5/5 - 1) * 1 * 5/3 = -0.8 * 5/3 = -4/3; sy = 1 - 2*0.5/3 = 2/3.
    // dir = normalize(-4/3, 2/3, -1) = (-4, 2, -3)/sqrt(29).
    Ray r = camera_ray(cam, 0, 0);
    CHECK_VEC(r.origin, Vec3d(0, 0, 5));
    const double s29 = std::sqrt(29.0);
    CHECK_VEC(r.direction, Vec3d(-4 / s29, 2 / s29, -3 / s29));
    // Centre pixel (2,1): sx = (2*2.5/5 - 1) = 0, sy = 1 - 2*1.5/3 = 0 -> dir = -w.
    r = camera_ray(cam, 2, 1);
    CHECK_VEC(r.direction, Vec3d(0, 0, -1));
    // Last pixel (4,2): sx = (2*4.5/5 - 1)*5/3 = 0.8*5/3 = 4/3, sy = 1 - 5/3 = -2/3.
    r = camera_ray(cam, 4, 2);
    CHECK_VEC(r.direction, Vec3d(4 / s29, -2 / s29, -3 / s29));
}

TEST_CASE("camera: pinhole looking down -x (u and v from the cross products)") {
    // eye (5,0,0): w = (1,0,0); u = (0,1,0) x (1,0,0) = (1*0-0*0, 0*1-0*0, 0*0-1*1) = (0,0,-1);
    // v = w x u = (1,0,0) x (0,0,-1) = (0*-1-0*0, 0*0-1*-1, 1*0-0*0) = (0,1,0).
    // Pixel (0,0) of 5x3, fov 90: sx=-4/3, sy=2/3: sx*u + sy*v - w = (-1, 2/3, 4/3) ∝ (-3, 2, 4).
    const Camera cam = camera_5x3(CameraType::pinhole, {5, 0, 0});
    const double s29 = std::sqrt(29.0);
    CHECK_VEC(camera_ray(cam, 0, 0).direction, Vec3d(-3 / s29, 2 / s29, 4 / s29));
}

TEST_CASE("camera: pinhole fov 60 scales by tan 30deg") {
    // 2x2, fov 60: t = tan 30deg = 1/sqrt 3; pixel (1,0): sx = (2*1.5/2 - 1)*t = t/2, sy = (1 - 0.5)*t = t/2.
    // dir ∝ (t/2, t/2, -1); |.|^2 = 1/12 + 1/12 + 1 = 7/6.
    Camera cam;
    cam.fov_y = 60;
    cam.width = 2;
    cam.height = 2;
    const double h = 0.5 / std::sqrt(3.0), len = std::sqrt(7.0 / 6.0);
    CHECK_VEC(camera_ray(cam, 1, 0).direction, Vec3d(h / len, h / len, -1 / len));
}

TEST_CASE("camera: orthographic corner and centre rays") {
    // height_world 2 -> tan(fov/2) is replaced by 1. 5x3 as above: pixel (0,0) has sx=-4/3, sy=2/3.
    Camera cam = camera_5x3(CameraType::orthographic, {0, 0, 5});
    Ray r = camera_ray(cam, 0, 0);
    CHECK_VEC(r.origin, Vec3d(-4.0 / 3, 2.0 / 3, 5));
    CHECK_VEC(r.direction, Vec3d(0, 0, -1));
    r = camera_ray(cam, 2, 1);
    CHECK_VEC(r.origin, Vec3d(0, 0, 5));
    CHECK_VEC(r.direction, Vec3d(0, 0, -1));
    // height_world 4 doubles the offsets: pixel (4,2) -> (2*4/3, -2*2/3).
    cam.height_world = 4;
    CHECK_VEC(camera_ray(cam, 4, 2).origin, Vec3d(8.0 / 3, -4.0 / 3, 5));
}

// ---------------------------------------------------------------- sphere ----

TEST_CASE("sphere: hits, misses, tangent, inside, interval") {
    const Sphere s{{0, 0, 0}, 1};
    // o=(0,0,5), d=-z: f=(0,0,5), a=1, b=-10, c=24, v=0, disc=4*1*(1-0)(1+0)=4, q=-(-10-2)/2=6,
    // roots 6/1=6 and 24/6=4 -> 4.
    CHECK_T(hit(s, {0, 0, 5}, kDown), 4.0);
    // Non-unit d=(0,0,-2): a=4, b=-20, c=24, disc=16, q=12, roots 3 and 2 -> 2 (same point).
    CHECK_T(hit(s, {0, 0, 5}, {0, 0, -2}), 2.0);
    // Off axis at x=0.6: surface z = sqrt(1-0.36) = 0.8, t = 5 - 0.8 = 4.2.
    CHECK_T(hit(s, {0.6, 0, 5}, kDown), 4.2);
    CHECK_FALSE(hit(s, {1.5, 0, 5}, kDown));
    CHECK_FALSE(hit(s, {0, 0, 5}, {0, 0, 1}));  // sphere behind the origin
    // Tangent: o=(1,0,5): v=(1,0,0), |v|=1, disc=0 -> a hit at t=5 (the boundary rule).
    CHECK_T(hit(s, {1, 0, 5}, kDown), 5.0);
    // One ulp outside the tangent line: |v| > 1, disc < 0 -> miss.
    CHECK_FALSE(hit(s, {up(1.0), 0, 5}, kDown));
    // From inside (centre): roots -1 and 1 -> the far root 1.
    CHECK_T(hit(s, {0, 0, 0}, {0, 0, 1}), 1.0);
    // From inside (z=0.5) going -z: roots -0.5 and 1.5 -> 1.5.
    CHECK_T(hit(s, {0, 0, 0.5}, kDown), 1.5);
    // Open interval: t=4 is excluded by tmax=4 and the far root 6 too.
    CHECK_FALSE(hit(s, {0, 0, 5}, kDown, 0.0, 4.0));
    CHECK_T(hit(s, {0, 0, 5}, kDown, 0.0, up(4.0)), 4.0);
    CHECK_T(hit(s, {0, 0, 5}, kDown, 4.0, kInf), 6.0);  // tmin=4 excludes the near root
}

TEST_CASE("sphere: far sphere keeps its discriminant (perpendicular form)") {
    // Centre (0,0,-1e8), r=1, o=(0.6,0,0), d=-z. Hand: v=(0.6,0,0), disc = 4*(1-0.6)(1+0.6) = 2.56,
    // t = 1e8 - sqrt(1 - 0.36) = 1e8 - 0.8. The textbook b^2-4ac = 4e16 - 4*(1e16-0.64)
    // loses all of 2.56 (the ulp of 4e16 is 8), so a naive test misses or lands far off.
    const Sphere s{{0, 0, -1e8}, 1};
    const auto t = hit(s, {0.6, 0, 0}, kDown);
    REQUIRE(t.has_value());
    CHECK(std::fabs(*t - (1e8 - 0.8)) <= 1e-6);
    // Huge sphere: r=1e6 centred at (0,0,-1e6-1); from the origin along -z, t = 1.
    CHECK_T(hit(Sphere{{0, 0, -1e6 - 1}, 1e6}, {0, 0, 0}, kDown), 1.0);
}

// ----------------------------------------------------------------- plane ----

TEST_CASE("plane: hits, parallel rays miss, two-sided") {
    const Plane p{{0, -1, 0}, {0, 1, 0}};
    // t = (p0-o).n/(d.n) = (0,-2,0).(0,1,0)/(-1) = 2.
    CHECK_T(hit(p, {0, 1, 0}, {0, -1, 0}), 2.0);
    // Oblique, non-unit d=(3,-4,0): t = -2/-4 = 0.5.
    CHECK_T(hit(p, {0, 1, 0}, {3, -4, 0}), 0.5);
    // From below: (0,2,0).(0,1,0)/1 = 2.
    CHECK_T(hit(p, {0, -3, 0}, {0, 1, 0}), 2.0);
    CHECK_FALSE(hit(p, {0, 1, 0}, {0, 1, 0}));   // t = -2 behind
    CHECK_FALSE(hit(p, {0, 1, 0}, {1, 0, 0}));   // parallel: d.n = 0
    CHECK_FALSE(hit(p, {0, -1, 0}, {1, 0, 0}));  // lying in the plane: d.n = 0 -> miss
    CHECK_VEC(geometric_normal(p, {5, -1, 3}), Vec3d(0, 1, 0));
}

// ------------------------------------------------------------------ disk ----

TEST_CASE("disk: inside, rim (edge hits), outside, parallel") {
    const Disk d{{0, 0, 0}, {0, 0, 1}, 0.5};
    CHECK_T(hit(d, {0, 0, 1}, kDown), 1.0);
    // Rim: |p-c|^2 = 0.25 = r^2 -> hit (the boundary rule).
    CHECK_T(hit(d, {0.5, 0, 1}, kDown), 1.0);
    CHECK_T(hit(d, {0, -0.5, 1}, kDown), 1.0);
    CHECK_FALSE(hit(d, {up(0.5), 0, 1}, kDown));
    // Oblique: o=(0,0,2), d=(0.125,0,-1): t = 2, p = (0.25,0,0) inside.
    CHECK_T(hit(d, {0, 0, 2}, {0.125, 0, -1}), 2.0);
    // Oblique through the rim: d=(0.25,0,-1) from (0,0,2) lands on (0.5,0,0).
    CHECK_T(hit(d, {0, 0, 2}, {0.25, 0, -1}), 2.0);
    CHECK_FALSE(hit(d, {0, 0, 1}, {1, 0, 0}));    // parallel above the disk
    CHECK_FALSE(hit(d, {-1, 0, 0}, {1, 0, 0}));   // in its plane, across it: still a miss
    CHECK_VEC(geometric_normal(d, {0.1, 0, 0}), Vec3d(0, 0, 1));
}

// ------------------------------------------------------------- rectangle ----

TEST_CASE("rectangle: inside, edges and corners hit, just outside misses") {
    const Rectangle r{{0, 0, 0}, {2, 0, 0}, {0, 1, 0}};  // [0,2]x[0,1] in z=0
    CHECK_T(hit(r, {1, 0.5, 3}, kDown), 3.0);
    CHECK_T(hit(r, {2, 0.5, 3}, kDown), 3.0);  // s = 1
    CHECK_T(hit(r, {1, 0, 3}, kDown), 3.0);    // t = 0
    CHECK_T(hit(r, {0, 0, 3}, kDown), 3.0);    // corner
    CHECK_T(hit(r, {2, 1, 3}, kDown), 3.0);    // opposite corner
    CHECK_FALSE(hit(r, {up(2.0), 0.5, 3}, kDown));
    // q=(1,-1e-300,0): a x q = (0,0,-2e-300), .n = -4e-300, /|n|^2=4 -> t = -1e-300 < 0.
    CHECK_FALSE(hit(r, {1, -1e-300, 3}, kDown));
    CHECK_FALSE(hit(r, {1, 0.5, 3}, {1, 0, 0}));  // parallel
    // n = a x b = (0,0,2) -> unit (0,0,1).
    CHECK_VEC(geometric_normal(r, {1, 0.5, 0}), Vec3d(0, 0, 1));
}

TEST_CASE("rectangle: non-orthogonal a, b (parallelogram, dual basis)") {
    // a=(2,0,0), b=(1,1,0): p = s a + t b = (2s + t, t). n = a x b = (0,0,2).
    const Rectangle r{{0, 0, 0}, {2, 0, 0}, {1, 1, 0}};
    // (2.5,0.5): t=0.5, s=(2.5-0.5)/2=1 -> edge, hit.
    // By the formula: q x b = (2.5,0.5,0)x(1,1,0) = (0,0,2), .n=4, /4 -> s=1; a x q=(0,0,1) -> t=0.5.
    CHECK_T(hit(r, {2.5, 0.5, 1}, kDown), 1.0);
    // (2.25,0.5): s=0.875 -> hit (orthogonal projection p.a/|a|^2 = 1.125 would miss).
    CHECK_T(hit(r, {2.25, 0.5, 1}, kDown), 1.0);
    // (0.25,0.5): s=(0.25-0.5)/2=-0.125 -> miss (orthogonal projection 0.125 would hit).
    CHECK_FALSE(hit(r, {0.25, 0.5, 1}, kDown));
    CHECK_FALSE(hit(r, {2.75, 0.5, 1}, kDown));  // s = 1.125
    CHECK_T(hit(r, {1, 1, 1}, kDown), 1.0);      // corner + b: s=0, t=1
}

// ------------------------------------------------------------------- box ----

TEST_CASE("box: faces, edges, grazing, zero direction components") {
    const Box b{{-1, -1, -1}, {1, 1, 1}};
    CHECK_T(hit(b, {0, 0, 5}, kDown), 4.0);
    // Origin on the x and y slab boundaries with d.x = d.y = 0 (1/d = inf, 0*inf = NaN
    // naively): the edge x=1,y=1 of the top face is hit at t=4.
    CHECK_T(hit(b, {1, 1, 5}, kDown), 4.0);
    CHECK_T(hit(b, {-1, 0, 5}, kDown), 4.0);
    CHECK_FALSE(hit(b, {up(1.0), 0, 5}, kDown));
    CHECK_FALSE(hit(b, {2, 2, 5}, kDown));
    CHECK_FALSE(hit(b, {0, 0, 5}, {0, 0, 1}));  // behind: t in [-6,-4]
    // Graze the edge y=1,z=1: o=(0,2,0), d=(0,-1,1): y slab t in [1,3], z slab t in [-1,1];
    // entry 1 == exit 1 -> hit (closed box).
    CHECK_T(hit(b, {0, 2, 0}, {0, -1, 1}), 1.0);
    // Shift up by an ulp: y slab starts later than z ends -> miss.
    CHECK_FALSE(hit(b, {0, up(2.0), 0}, {0, -1, 1}));
    // Diagonal through the corner (1,1,1) only: o=(2,2,0), d=(-1,-1,1):
    // x,y slabs t in [1,3], z slab t in [-1,1] -> t = 1.
    CHECK_T(hit(b, {2, 2, 0}, {-1, -1, 1}), 1.0);
    // A non-symmetric box: min (1,-1,1), max (2,0,2); z slab from 10: t = 10-2 = 8.
    CHECK_T(hit(Box{{1, -1, 1}, {2, 0, 2}}, {1.5, -0.5, 10}, kDown), 8.0);
}

TEST_CASE("box: from inside returns the exit face") {
    const Box b{{-1, -1, -1}, {1, 1, 1}};
    CHECK_T(hit(b, {0, 0, 0}, {0, 0, 1}), 1.0);
    // d=(1,0.5,0): x exits at 1, y at 2 -> t = 1 (x face).
    CHECK_T(hit(b, {0, 0, 0}, {1, 0.5, 0}), 1.0);
    // Origin on a face, moving inward: entry t=0 is not in (0,inf) -> exit t = 2.
    CHECK_T(hit(b, {0, 0, 1}, kDown), 2.0);
}

TEST_CASE("box: normals (deciding slab in trace, nearest face in geometric_normal)") {
    Scene s;
    s.materials.push_back({});
    s.objects.push_back({Box{{-1, -1, -1}, {1, 1, 1}}, 0});
    // Top face from above: entering through the z max face, n = +z.
    Hit h = trace(s, {{0.5, 0.25, 5}, kDown});
    REQUIRE(h.object == 0);
    CHECK_VEC(h.normal, Vec3d(0, 0, 1));
    // Grazing edge (y slab decided the entry at t=1): n = +y.
    h = trace(s, {{0, 2, 0}, {0, -1, 1}});
    REQUIRE(h.object == 0);
    CHECK_VEC(h.normal, Vec3d(0, 1, 0));
    // From inside along (1,0.5,0): exit through +x, face-forwarded to -x.
    h = trace(s, {{0, 0, 0}, {1, 0.5, 0}});
    REQUIRE(h.object == 0);
    CHECK_VEC(h.normal, Vec3d(-1, 0, 0));
    CHECK_VEC(h.point, Vec3d(1, 0.5, 0));
    // Left face from the left: -x.
    h = trace(s, {{-5, 0, 0}, {1, 0, 0}});
    CHECK_VEC(h.normal, Vec3d(-1, 0, 0));
    CHECK_VEC(geometric_normal(Box{{-1, -1, -1}, {1, 1, 1}}, {0.5, 1, 0.2}), Vec3d(0, 1, 0));
    CHECK_VEC(geometric_normal(Box{{-1, -1, -1}, {1, 1, 1}}, {-1, 0, 0.3}), Vec3d(-1, 0, 0));
}

// -------------------------------------------------------------- triangle ----

TEST_CASE("triangle: interior, edges and vertices hit, outside misses") {
    const Triangle tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    // o=(0.25,0.25,1), d=-z. Woop et al.: kz=2, d.z<0 swaps kx,ky -> kx=1, ky=0; Sx=Sy=-0, Sz=-1.
    // Sheared A=(-0.25,-0.25), B=(-0.25,0.75), C=(0.75,-0.25): U = 0.75*0.75-(-0.25)(-0.25)=0.5,
    // V = (-0.25)(-0.25)-(-0.25)(0.75) = 0.25, W = 0.25; det = 1; T = (0.5+0.25+0.25)*1 -> t = 1.
    CHECK_T(hit(tri, {0.25, 0.25, 1}, kDown), 1.0);
    CHECK_T(hit(tri, {0.5, 0, 1}, kDown), 1.0);    // edge v0-v1
    CHECK_T(hit(tri, {0, 0.5, 1}, kDown), 1.0);    // edge v0-v2
    CHECK_T(hit(tri, {0.5, 0.5, 1}, kDown), 1.0);  // edge v1-v2: U = 0.25-0.25 = 0
    CHECK_T(hit(tri, {1, 0, 1}, kDown), 1.0);      // vertex
    CHECK_T(hit(tri, {0, 0, 1}, kDown), 1.0);      // vertex
    CHECK_FALSE(hit(tri, {0.5, -std::ldexp(1.0, -30), 1}, kDown));
    CHECK_FALSE(hit(tri, {0.5, up(0.5), 1}, kDown));
    CHECK_FALSE(hit(tri, {0.25, 0.25, 1}, {0, 0, 1}));       // behind
    CHECK_FALSE(hit(tri, {-1, 0.25, 0}, {1, 0, 0}));        // in its plane: det = 0
    CHECK_T(hit(tri, {0.25, 0.25, -1}, {0, 0, 1}), 1.0);    // back side: no culling
    // Oblique non-unit d = 2*(0.125,0.125,-1) from (0,0,2): lands on (0.25,0.25,0) at t=1.
    CHECK_T(hit(tri, {0, 0, 2}, {0.25, 0.25, -2}), 1.0);
    // Normal: (v1-v0)x(v2-v0) = (1,0,0)x(0,1,0) = (0,0,1).
    CHECK_VEC(geometric_normal(tri, {0.2, 0.2, 0}), Vec3d(0, 0, 1));
    // (0,1,0)x(0,0,1) = (1,0,0).
    CHECK_VEC(geometric_normal(Triangle{{0, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 0.2, 0.2}), Vec3d(1, 0, 0));
}

TEST_CASE("triangle: watertight across a shared edge") {
    // Two triangles sharing the diagonal from (1,0,0) to (0,1,0). Rays aimed at points
    // of the diagonal (not exactly representable, so they fall to either side by
    // rounding) from several directions must hit at least one of the two.
    const Triangle t1{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const Triangle t2{{1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const Vec3d dirs[] = {{0, 0, -1}, {0.3, -0.7, -1}, {-0.11, 0.37, -0.9}, {1e-3, 2e-3, -1}};
    int misses = 0;
    for (const Vec3d& d : dirs)
        for (int k = 1; k < 997; ++k) {
            const double x = k / 997.0;
            const Vec3d target{x, 1.0 - x, 0};
            const Vec3d o = target - d * 3.0;  // 3 units back along the ray
            if (!hit(t1, o, d) && !hit(t2, o, d)) ++misses;
        }
    CHECK(misses == 0);
}

// ----------------------------------------------------- trace: nearest, ties, faces ----

TEST_CASE("trace: nearest hit, ties keep the lower index, face-forward normals") {
    Scene s;
    s.materials.push_back({});
    s.objects.push_back({Sphere{{0, 0, -3}, 1}, 0});  // farther, listed first
    s.objects.push_back({Sphere{{0, 0, 0}, 1}, 0});
    Hit h = trace(s, kPoleRay);
    CHECK(h.object == 1);
    CHECK(h.t == near(4.0));
    CHECK_VEC(h.point, Vec3d(0, 0, 1));
    CHECK_VEC(h.normal, Vec3d(0, 0, 1));

    // Identical spheres: equal t, the lower index wins (both orders of insertion).
    Scene twin;
    twin.materials.push_back({});
    twin.objects.push_back({Sphere{{0, 0, 0}, 1}, 0});
    twin.objects.push_back({Sphere{{0, 0, 0}, 1}, 0});
    CHECK(trace(twin, kPoleRay).object == 0);
    // Tie between a plane and a disk in the same place: plane first -> 0; disk first -> 0 too.
    Scene pd;
    pd.materials.push_back({});
    pd.objects.push_back({Plane{{0, 0, 0}, {0, 0, 1}}, 0});
    pd.objects.push_back({Disk{{0, 0, 0}, {0, 0, 1}, 1}, 0});
    CHECK(trace(pd, kPoleRay).object == 0);
    std::swap(pd.objects[0], pd.objects[1]);
    CHECK(trace(pd, kPoleRay).object == 0);
    CHECK(std::holds_alternative<Disk>(pd.objects[0].shape));

    // Face-forward: plane normal +y seen from below becomes -y.
    Scene pl;
    pl.materials.push_back({});
    pl.objects.push_back({Plane{{0, 0, 0}, {0, 1, 0}}, 0});
    h = trace(pl, {{0, -2, 0}, {0, 1, 0}});
    CHECK_VEC(h.normal, Vec3d(0, -1, 0));
    CHECK(dot(h.normal, Vec3d(0, 1, 0)) <= 0.0);
    // Sphere from inside: hit (0,0,1), geometric n=(0,0,1), faced back to (0,0,-1).
    h = trace(twin, {{0, 0, 0}, {0, 0, 1}});
    CHECK_VEC(h.normal, Vec3d(0, 0, -1));
    // Triangle from behind: (0,0,1) flipped to (0,0,-1).
    Scene tr;
    tr.materials.push_back({});
    tr.objects.push_back({Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 0});
    CHECK_VEC(trace(tr, {{0.2, 0.2, -1}, {0, 0, 1}}).normal, Vec3d(0, 0, -1));

    // Miss, and degenerate (zero / NaN direction) rays: object -1.
    CHECK(trace(s, {{0, 5, 5}, kDown}).object == -1);
    CHECK(trace(s, {{0, 0, 5}, {0, 0, 0}}).object == -1);
    CHECK(trace(s, {{0, 0, 5}, {kNaN, 0, -1}}).object == -1);
}
