// dispatch/threads.cpp — resolve_threads (octray/threads.hpp).
#include <octray/threads.hpp>

#ifdef _OPENMP
#include <omp.h>
#else
#include <thread>
#endif

namespace octray {

int resolve_threads(int requested) {
    if (requested > 0) return requested;
#ifdef _OPENMP
    return omp_get_max_threads();
#else
    const unsigned cores = std::thread::hardware_concurrency();
    return cores > 0 ? int(cores) : 1;
#endif
}

}  // namespace octray
