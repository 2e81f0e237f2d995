// `fovea simulate osc`: added to the `simulate` command (cmd_simulate.cpp).
#pragma once

#include <CLI/CLI.hpp>

namespace fovea::cli {

void add_simulate_osc(CLI::App& simulate);

}  // namespace fovea::cli
