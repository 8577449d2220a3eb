// tools/plot_script.hpp — runs tools/plot.py, whose text is built into the
// binary (cmake/octrayPlot.cmake says why), with python3.
#pragma once

#include <string>
#include <vector>

namespace octray::cli {

// Runs `PYTHON - ARGS...` with tools/plot.py's text on standard input, where
// PYTHON is $OCTRAY_PYTHON when set, else the python3 with matplotlib that the
// build found when it is still there, else python3 on PATH. The script's
// standard output (its "wrote ..." line) is ours. Throws std::runtime_error,
// one line starting with `context`, when python3 cannot be run or the script
// fails (matplotlib missing, a file it cannot write): the script's own last
// line says which.
void run_plot_script(const std::vector<std::string>& args, const std::string& context);

}  // namespace octray::cli
