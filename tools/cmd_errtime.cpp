// tools/cmd_errtime.cpp — `octray errtime SCENE [--csv F] [--plot F.svg]`:
// error against run time for every path x precision mode this CPU runs.
#include "commands.hpp"
#include "errtime.hpp"
#include "scene_loader.hpp"

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

namespace octray::cli {
namespace {

void write_text(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary);
    if (!f || !(f << text) || !(f.flush()))
        throw std::runtime_error(path + ": cannot write");
}

}  // namespace

int run_errtime(const ErrtimeArgs& args) {
    const Scene scene = load_scene(args.scene);
    ErrtimeOptions options;
    options.threads = args.threads > 0 ? args.threads : 1;
    std::printf("scene %s: %zu objects, %zu lights, %d thread%s\n", args.scene.c_str(), scene.objects.size(),
                scene.directional_lights.size() + scene.point_lights.size(), options.threads,
                options.threads == 1 ? "" : "s");
    std::fflush(stdout);
    const ErrtimeReport report = measure_errtime(scene, options, stderr);
    print_errtime_table(stdout, report);
    if (!args.csv.empty()) {
        write_text(args.csv, errtime_csv(report));
        std::printf("wrote %s\n", args.csv.c_str());
    }
    if (!args.plot.empty()) {
        write_text(args.plot, errtime_svg(report, "octray errtime: " + args.scene));
        std::printf("wrote %s\n", args.plot.c_str());
    }
    return kExitOk;
}

}  // namespace octray::cli
