// Every scene of scenes/ in every precision mode, on every ISA unit of both
// paths this CPU runs (each with the scene's own variant, as select_kernel
// picks it), within the mode's `octray errtime` bound (scene_bounds.hpp).
#include "scene_bounds.hpp"

#include "dispatch/isa_kernels.hpp"

#include <set>

using namespace octray;
using namespace octray::scene_bounds;

TEST_CASE("every scene in every precision mode and path renders within the mode's errtime bound") {
    std::set<Path> paths;
    std::set<Precision> modes;
    for (const auto& s : small_scenes()) {
        const unsigned bits = s->packet.features().bits;
        for (int i = 0; i < kernels::kUnitCount; ++i) {
            const kernels::Unit& u = kernels::kUnits[i];
            if (!u.supported()) continue;
            for (Precision p : kPrecisions) {
                if ((u.modes & kernels::mode_bit(p)) == 0) continue;
                const Kernel k = u.kernel(p, bits & kAllPrimitives, bits & ~kAllPrimitives);
                check_within(*s, k, p, std::string(path_name(u.path)) + "/" + u.isa + "/" + precision_name(p));
                paths.insert(u.path);
                modes.insert(p);
            }
        }
    }
    CHECK(paths.size() == 2);
    CHECK(modes.size() >= 4);  // fast14 and approx14 where the CPU has AVX-512
}
