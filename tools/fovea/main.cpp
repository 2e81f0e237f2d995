#include <algorithm>
#include <cstdio>
#include <exception>

#include "command.hpp"

namespace fovea::cli {

GlobalOptions& global_options() {
    static GlobalOptions options;
    return options;
}

std::vector<CommandEntry>& command_registry() {
    static std::vector<CommandEntry> commands;
    return commands;
}

Command::Command(const char* name, const char* description, SetupFn setup) {
    command_registry().push_back({name, description, setup});
}

}  // namespace fovea::cli

int main(int argc, char** argv) {
    using namespace fovea::cli;
    CLI::App app{"fovea: talk to fovead, record, evaluate, render and benchmark"};
    app.require_subcommand(1);
    app.option_defaults()->always_capture_default();
    app.add_option("--instance", global_options().instance,
                   "Daemon instance (ring and control socket names)");
    auto& commands = command_registry();
    std::sort(commands.begin(), commands.end(), [](const CommandEntry& a, const CommandEntry& b) {
        return std::string_view(a.name) < b.name;
    });
    for (const auto& c : commands) c.setup(*app.add_subcommand(c.name, c.description));
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) { return app.exit(e); } catch (const std::exception& e) {
        std::fprintf(stderr, "fovea: %s\n", e.what());
        return 1;
    }
    return 0;
}
