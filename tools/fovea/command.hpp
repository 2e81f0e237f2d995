// Subcommands of the `fovea` CLI register themselves: one file per command, no central list.
//   static const fovea::cli::Command kStatus{"status", "Print the daemon's status JSON", &setup};
// `setup` adds the subcommand's options to the CLI11 app it is given and sets its callback.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace fovea::cli {

// Options every subcommand may read (parsed before the subcommand).
struct GlobalOptions {
    std::string instance = "default";
};
GlobalOptions& global_options();

using SetupFn = void (*)(CLI::App& subcommand);

struct Command {
    Command(const char* name, const char* description, SetupFn setup);
};

struct CommandEntry {
    const char* name;
    const char* description;
    SetupFn setup;
};
std::vector<CommandEntry>& command_registry();

}  // namespace fovea::cli
