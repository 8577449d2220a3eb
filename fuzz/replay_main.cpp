// fuzz/replay_main.cpp — main() for a fuzz target built without libFuzzer
// (any compiler): runs LLVMFuzzerTestOneInput once on every file named on the
// command line or found under a named directory. CTest's fuzz.replay.* tests
// run each target's seed corpus and regression inputs this way in every
// build, sanitizers included. A bad input aborts (the harness's checks, a
// sanitizer report); otherwise the exit status is 0.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

void run_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::fprintf(stderr, "replay: cannot read %s\n", path.c_str());
        std::exit(2);
    }
    const std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    std::fprintf(stderr, "replay: %s (%zu bytes)\n", path.c_str(), bytes.size());
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

}  // namespace

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    int inputs = 0;
    for (int a = 1; a < argc; ++a) {
        const fs::path arg(argv[a]);
        if (!fs::is_directory(arg)) {
            run_file(arg), ++inputs;
            continue;
        }
        std::vector<fs::path> files;
        for (const fs::directory_entry& e : fs::recursive_directory_iterator(arg))
            if (e.is_regular_file()) files.push_back(e.path());
        std::sort(files.begin(), files.end());
        for (const fs::path& f : files) run_file(f), ++inputs;
    }
    std::printf("replayed %d inputs, all passed\n", inputs);
    return inputs > 0 ? 0 : 1;
}
