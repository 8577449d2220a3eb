// octray/threads.hpp — the one rule for a thread count, wherever octray takes
// one (CompileOptions::threads, render_packet, the CLI's --threads).
#pragma once

namespace octray {

// The threads a request means: `requested` when > 0; 0 (or less) means every
// core: OpenMP's count (which OMP_NUM_THREADS may set) where octray was built
// with OpenMP, else the hardware's.
int resolve_threads(int requested);

}  // namespace octray
