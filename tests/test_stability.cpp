// The stability catalogue (harness/stability_cases.hpp): every case meets its
// bound on every path × precision mode. One SUBCASE per case; the same list
// `octray stability` prints.
#include <doctest/doctest.h>

#include "stability_cases.hpp"

#include <set>
#include <string>

using namespace octray;
using namespace octray::stability;

TEST_CASE("the stability catalogue has every required stiff and extreme case, once") {
    const auto& cases = catalogue();
    CHECK(cases.size() >= 24);
    std::set<std::string> names;
    for (const Case& c : cases) {
        CHECK_MESSAGE(names.insert(c.name).second, "duplicate case " << c.name);
        CHECK(!c.expectation.empty());
        CHECK(!c.bound_text.empty());
    }
    for (const char* required :
         {"planet_1e6_from_1_above", "sphere_r1e-4_at_1", "sphere_r1_at_1e4", "sphere_r1_at_t1e7", "sphere_tangent_rays",
          "grazing_light_1e-7", "plane_ray_parallel", "plane_ray_in_plane", "box_origin_on_face", "mesh_shared_edges",
          "mesh_shared_vertices", "disk_rim_hits", "rectangle_edge_hits", "camera_inside_sphere", "lights_1e30_and_1e-30",
          "lights_64_over_12_decades", "point_light_1e-6_inv_square", "zero_direction", "nan_direction", "inf_direction",
          "subnormals_ftz_daz_off", "subnormals_ftz_daz_on", "coordinates_near_1e19"})
        CHECK_MESSAGE(names.count(required) == 1, "missing case " << required);
}

TEST_CASE("every stability case meets its bound on every path and precision mode") {
    REQUIRE(!catalogue().empty());
    REQUIRE(!kernel_tracers().empty());
    for (const Case& c : catalogue()) {
        SUBCASE(c.name.c_str()) {
            for (const Tracer& t : kernel_tracers()) {
                const Measure m = c.run(t);
                INFO(c.name << " [" << t.name() << "]: error " << m.error << " (bound " << c.bound << ") " << m.note);
                CHECK(m.pass);
                CHECK(m.error <= c.bound);
            }
        }
    }
}

TEST_CASE("the textbook formulation fails some cases: the catalogue discriminates") {
    REQUIRE(!catalogue().empty());
    int failed = 0;
    for (const Case& c : catalogue()) failed += c.run(naive_tracer()).pass ? 0 : 1;
    MESSAGE("textbook formulation fails " << failed << " of " << catalogue().size() << " cases");
    CHECK(failed >= 12);
}
