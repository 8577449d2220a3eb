// The bounds on every CPU: kernels whose every estimate (rcpps, rsqrtps,
// rcp14, rsqrt14) is the IEEE result moved to the limit of the instruction's
// specification (perturbed_estimates.hpp, perturbed_units.hpp): +limit,
// -limit and a seeded mix. Any CPU's estimate tables lie within those limits,
// so the scene bounds (scene_bounds.hpp) and the stability catalogue, which
// hold with this CPU's tables, must hold at the limits too.
#include "scene_bounds.hpp"

#include "perturbed_estimates.hpp"
#include "perturbed_units.hpp"
#include "stability_cases.hpp"
#include "stability_check.hpp"

#include <map>
#include <random>
#include <utility>

using namespace octray;
using namespace octray::scene_bounds;

namespace {

struct PerturbedUnit {
    Path path;
    const char* name;
    Kernel (*kernel)(Precision);
};
const PerturbedUnit kPerturbedUnits[] = {{Path::simd, "perturbed-avx2", &kernels::perturbed_avx2_simd_kernel},
                                         {Path::scalar, "perturbed-avx2", &kernels::perturbed_avx2_scalar_kernel}};
const Precision kEstimateModes[] = {Precision::fast, Precision::approx, Precision::fast14, Precision::approx14};
const perturbed::Setting kSettings[] = {
    {perturbed::Edge::up, 0}, {perturbed::Edge::down, 0}, {perturbed::Edge::mix, 0x5eed}, {perturbed::Edge::mix, 42}};

// The setting for one scope; the default again after it.
struct Use {
    explicit Use(perturbed::Setting s) { perturbed::setting = s; }
    ~Use() { perturbed::setting = {}; }
};

// "perturbed-avx2 +limit", "perturbed-avx2 mix seed 42": a Tracer's label.
std::string setting_name(const PerturbedUnit& u, perturbed::Setting s) {
    return std::string(u.name) + " " + perturbed::edge_name(s.edge) +
           (s.edge == perturbed::Edge::mix ? " seed " + std::to_string(s.seed) : "");
}
std::string label(const PerturbedUnit& u, Precision p, perturbed::Setting s) {
    return std::string(path_name(u.path)) + "/" + precision_name(p) + " " + setting_name(u, s);
}

}  // namespace

TEST_CASE("perturbed estimates sit at the limits of the instructions' specification") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> exponent(-120, 120);
    for (double limit : {rcp_bound(Precision::approx), rcp_bound(Precision::approx14)})
        for (const perturbed::Setting& s : kSettings) {
            CAPTURE(limit);
            CAPTURE(perturbed::edge_name(s.edge));
            const Use use(s);
            double lo = 1, hi = -1;
            for (int i = 0; i < 20000; ++i) {
                const float x = float(std::exp2(exponent(rng)));
                const double e_rcp = double(perturbed::rcp(i % 2 ? -x : x, limit)) * double(i % 2 ? -x : x) - 1;
                const double e_rsqrt = double(perturbed::rsqrt(x, limit)) * std::sqrt(double(x)) - 1;
                for (double e : {e_rcp, e_rsqrt}) {
                    REQUIRE(std::fabs(e) <= limit);
                    lo = std::min(lo, e), hi = std::max(hi, e);
                }
            }
            // At the limit to a float's spacing (2^-23 relative), or spread across it.
            if (s.edge != perturbed::Edge::down) CHECK(hi >= limit - 0x1p-23);
            if (s.edge != perturbed::Edge::up) CHECK(lo <= -limit + 0x1p-23);
            if (s.edge == perturbed::Edge::up) CHECK(lo >= limit - 0x1p-23);
            if (s.edge == perturbed::Edge::down) CHECK(hi <= -limit + 0x1p-23);
        }
    const float inf = std::numeric_limits<float>::infinity(), e = float(rcp_bound(Precision::approx));
    CHECK(perturbed::rcp(0.0f, e) == inf);
    CHECK(perturbed::rcp(-0.0f, e) == -inf);
    CHECK(perturbed::rcp(1e-40f, e) == inf);  // subnormal: read as 0, as rcpps does
    CHECK(perturbed::rcp(inf, e) == 0.0f);
    CHECK(perturbed::rcp(0x1p127f, e) == 0.0f);  // 2^-127 is below the normal range
    CHECK(perturbed::rsqrt(0.0f, e) == inf);
    CHECK(std::isnan(perturbed::rsqrt(-1.0f, e)));
    CHECK(perturbed::rsqrt(inf, e) == 0.0f);
}

TEST_CASE("every scene renders within its mode's errtime bound with estimates at their limits") {
    std::map<Precision, double> worst;  // max L/S over scenes, paths and settings
    std::map<Precision, std::string> where;
    for (const auto& s : small_scenes())
        for (const PerturbedUnit& u : kPerturbedUnits)
            for (Precision p : kEstimateModes)
                for (const perturbed::Setting& setting : kSettings) {
                    const Use use(setting);
                    const Agreement a = check_within(*s, u.kernel(p), p, label(u, p, setting));
                    if (a.max_scaled > worst[p]) worst[p] = a.max_scaled, where[p] = s->name + " " + label(u, p, setting);
                }
    for (Precision p : kEstimateModes)
        MESSAGE(std::string(precision_name(p)) << ": worst max L/S " << worst[p] << " (" << where[p] << ") of bound "
                                               << mode_tolerance(p).scaled_error);
    // The perturbation bites: a point light's n.l moves by the whole limit.
    CHECK(worst[Precision::approx] >= 0.5 * rsqrt_bound(Precision::approx));
    CHECK(worst[Precision::approx14] >= 0.5 * rsqrt_bound(Precision::approx14));
}

TEST_CASE("every stability case meets its bound with estimates at their limits") {
    REQUIRE(!stability::catalogue().empty());
    for (const stability::Case& c : stability::catalogue()) {
        SUBCASE(c.name.c_str()) {
            for (const PerturbedUnit& u : kPerturbedUnits)
                for (Precision p : kEstimateModes)
                    for (const perturbed::Setting& setting : kSettings) {
                        const Use use(setting);
                        stability::Tracer t{u.path, p, false, u.kernel, setting_name(u, setting)};
                        const stability::Measure m = c.run(t);
                        INFO(c.name << " [" << label(u, p, setting) << "]: error " << m.error << " (bound " << c.bound
                                    << ") " << m.note);
                        CHECK(m.pass);
                        CHECK(m.error <= c.bound);
                    }
        }
    }
}

TEST_CASE("a point light just below a ceiling lights the floor: the shadow segment ends at the light") {
    // 1e-3 past each light is the ceiling. The segment's end, r^2 * (1/|v|)
    // with an estimate's 1/|v|, would lie (1 + e)^2 from the light's t: up to
    // 2^-11 |v| (7e-3 at 10) past it, where the ceiling would shadow the floor.
    using namespace stability;
    using namespace stability::detail;
    Scene s = scene_of({Plane{{0, 0, 0}, {0, 0, 1}}, Plane{{0, 0, 10}, {0, 0, -1}}});
    s.materials[0] = matte("m", {1, 0.5, 0.25}, 0.0, 0.65);
    s.point_lights.push_back({{0, 0, fl(10 - 1e-3)}, {1, 1, 1}, 1.0, Attenuation::none, true});
    s.point_lights.push_back({{fl(1.5), 0, fl(10 - 2e-3)}, {1, 0.5, 1}, 4.0, Attenuation::inverse_square, true});
    const std::vector<Lane> lanes = down_onto({{0, 0}, {1, 0}, {3, 2}, {-4, 1}, {0.5, -6}, {7, 7}, {-9, -3}}, 5);
    std::vector<std::pair<Tracer, perturbed::Setting>> runs;
    for (const Tracer& t : kernel_tracers()) runs.push_back({t, perturbed::Setting{}});
    for (const PerturbedUnit& u : kPerturbedUnits)
        for (Precision p : kEstimateModes)
            for (const perturbed::Setting& setting : kSettings)
                runs.push_back({Tracer{u.path, p, false, u.kernel, setting_name(u, setting)}, setting});
    for (const auto& run : runs) {
        const Tracer& t = run.first;  // not a structured binding: INFO captures it
        const Use use(run.second);
        const Measure m = measure_all(t, s, lanes);
        INFO(t.name() << ": error " << m.error << " " << m.note);
        CHECK(m.pass);
        CHECK(m.error <= 16);  // dL/(eps L + u sum F g), the catalogue's lighting bound
    }
}
