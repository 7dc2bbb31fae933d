#pragma once
// hybrid-station is one program with subcommands; each lives in its own *_command.cpp file and
// registers itself here, so adding one touches no other file.

#include <CLI/CLI.hpp>
#include <functional>
#include <vector>

namespace hd::station {

/// Adds a subcommand to the program. The callback set on the subcommand returns through
/// `exit_code`, which main() returns.
using CommandFactory = std::function<void(CLI::App& app, int& exit_code)>;

std::vector<CommandFactory>& command_factories();

/// Register with a file-scope `static const CommandRegistrar r{[](CLI::App& app, int& rc){...}};`
struct CommandRegistrar {
  explicit CommandRegistrar(CommandFactory f) { command_factories().push_back(std::move(f)); }
};

}  // namespace hd::station
