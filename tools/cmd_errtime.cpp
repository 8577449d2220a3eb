// tools/cmd_errtime.cpp — `octray errtime SCENE [--csv F] [--plot F.svg]`:
// error against run time for every path x precision mode this CPU runs;
// exit 1 when a mode is over its bound (harness/verify.hpp, mode_tolerance).
// The plot is tools/plot.py's (matplotlib), drawn from the CSV.
#include "commands.hpp"
#include "errtime.hpp"
#include "plot_script.hpp"
#include "scene_loader.hpp"

#include <octray/threads.hpp>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace octray::cli {
namespace {

void write_text(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary);
    if (!f || !(f << text) || !(f.flush()))
        throw std::runtime_error(path + ": cannot write");
}

// The CSV the plot is drawn from when --csv names none: removed when done.
class TempCsv {
public:
    TempCsv() {
        const char* dir = std::getenv("TMPDIR");
        path_ = std::string(dir && *dir ? dir : "/tmp") + "/octray-errtime-XXXXXX.csv";
        const int fd = mkstemps(path_.data(), 4);
        if (fd < 0) throw std::runtime_error(path_ + ": cannot create a temporary file: " + std::strerror(errno));
        close(fd);
    }
    ~TempCsv() { std::remove(path_.c_str()); }
    TempCsv(const TempCsv&) = delete;
    TempCsv& operator=(const TempCsv&) = delete;
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

}  // namespace

int run_errtime(const ErrtimeArgs& args) {
    const Scene scene = load_scene(args.scene);
    ErrtimeOptions options;
    options.threads = resolve_threads(args.threads);
    std::printf("scene %s: %s, %d thread%s\n", args.scene.c_str(), scene_contents(scene).c_str(), options.threads,
                options.threads == 1 ? "" : "s");
    std::fflush(stdout);
    const ErrtimeReport report = measure_errtime(scene, options, stderr);
    print_errtime_table(stdout, report);
    const std::string csv = errtime_csv(report);
    if (!args.csv.empty()) {
        write_text(args.csv, csv);
        std::printf("wrote %s\n", args.csv.c_str());
    }
    if (!args.plot.empty()) {
        std::optional<TempCsv> temp;
        if (args.csv.empty()) write_text(temp.emplace().path(), csv);
        run_plot_script({"errtime", temp ? temp->path() : args.csv, args.plot, "--title", "octray errtime: " + args.scene},
                        "--plot " + args.plot);
    }
    // Written first, then judged: a failing run still leaves its CSV and plot.
    if (!report.all_within()) {
        std::printf("OVER BOUND: a mode's error is over its bound (verdict column)\n");
        return kExitFailed;
    }
    return kExitOk;
}

}  // namespace octray::cli
