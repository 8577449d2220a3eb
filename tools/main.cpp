// tools/main.cpp — the `octray` command-line program (README, "Command line").
//
// Exit status: 0 success, 1 a verification that failed, 2 bad input or usage
// with exactly one line on standard error. Each subcommand is one function in
// its own file (commands.hpp); this file only parses arguments and reports errors.
#include "commands.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <exception>
#include <iostream>
#include <string>

namespace {

// The contract is one line on stderr; library messages may not be.
int report_error(std::string message) {
    std::replace(message.begin(), message.end(), '\n', ' ');
    std::cerr << "octray: " << message << "\n";
    return octray::cli::kExitBadInput;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace octray::cli;
    CLI::App app{"octray: SIMD ray-packet kernels for analytic primitives and Lambertian shading", "octray"};
    app.require_subcommand(1);

    RenderArgs render;
    auto* render_cmd = app.add_subcommand("render", "render a scene to PNG (and its HDR radiance to PFM)");
    render_cmd->add_option("scene", render.scene, "scene JSON file")->required();
    render_cmd->add_option("-o,--output", render.output, "PNG file to write")->required();
    render_cmd->add_option("--hdr", render.hdr, "also write the HDR radiance as PFM");
    render_cmd->add_option("--path", render.path, "which renderer")
        ->check(CLI::IsMember({path_name(octray::Path::simd), path_name(octray::Path::scalar), kReferencePathName}))
        ->capture_default_str();
    render_cmd->add_option("--threads", render.threads, "render threads (0 = all cores, 1 = single thread)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    render_cmd->add_option("--width", render.width, "image width instead of the scene's (same aspect ratio)")
        ->check(CLI::Range(1, 16384));

    VerifyArgs verify;
    auto* verify_cmd = app.add_subcommand("verify", "SIMD vs reference error table; exit 1 when over tolerance");
    verify_cmd->add_option("scene", verify.scene, "scene JSON file")->required();
    verify_cmd->add_option("--threads", verify.threads, "render threads (0 = all cores)")->check(CLI::Range(0, 1024));
    verify_cmd->add_flag("--packet-rays", verify.packet_rays,
                         "trace the reference along the packet path's camera rays as the kernels take them (float + residual)");

    ErrtimeArgs errtime;
    auto* errtime_cmd = app.add_subcommand("errtime", "error against run time, per precision mode");
    errtime_cmd->add_option("scene", errtime.scene, "scene JSON file")->required();
    errtime_cmd->add_option("--csv", errtime.csv, "write the table as CSV");
    errtime_cmd->add_option("--plot", errtime.plot,
                            "draw the plot (python3 with matplotlib): F.svg and F.png beside it");
    errtime_cmd->add_option("--threads", errtime.threads, "render threads while timing (0 = all cores)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();

    StabilityArgs stability;
    auto* stability_cmd = app.add_subcommand("stability", "the catalogue of stiff and extreme cases, as a table");
    stability_cmd->add_flag("--wide", stability.wide, "one column per path x precision mode, and each expectation");
    stability_cmd->add_option("--csv", stability.csv, "write every cell (case x path x mode, with notes) as CSV");

    InfoArgs info;
    auto* info_cmd = app.add_subcommand("info", "what the scene uses and which kernel runs it");
    info_cmd->add_option("scene", info.scene, "scene JSON file")->required();

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help: usage on stdout, exit 0
        // CLI11's own exit codes (106, ...) would break the "2 = usage" contract.
        // Point to the help that lists the option: the subcommand's, once one is named.
        std::string help = "octray --help";
        for (int i = 1; i < argc && help == "octray --help"; ++i)
            for (const CLI::App* sub : {render_cmd, verify_cmd, errtime_cmd, stability_cmd, info_cmd})
                if (sub->check_name(argv[i])) help = "octray " + sub->get_name() + " --help";
        return report_error(std::string(e.what()) + " (see " + help + ")");
    }

    try {
        if (render_cmd->parsed()) return run_render(render);
        if (verify_cmd->parsed()) return run_verify(verify);
        if (errtime_cmd->parsed()) return run_errtime(errtime);
        if (stability_cmd->parsed()) return run_stability(stability);
        if (info_cmd->parsed()) return run_info(info);
    } catch (const std::exception& e) {
        // SceneError already reads "FILE: JSON_PATH: problem".
        return report_error(e.what());
    }
    return report_error("no subcommand given (see octray --help)");
}
