// hybrid-station: the operator's program.
#include <exception>
#include <iostream>

#include "station/app/command.h"

namespace hd::station {
std::vector<CommandFactory>& command_factories() {
  static std::vector<CommandFactory> factories;
  return factories;
}
}  // namespace hd::station

int main(int argc, char** argv) {
  CLI::App app{"hybrid-station: the Hybrid Display operator station (video / hybrid / synthetic)"};
  app.require_subcommand(1);
  int exit_code = 0;
  for (auto& factory : hd::station::command_factories()) factory(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "hybrid-station: " << e.what() << "\n";
    return 1;
  }
  return exit_code;
}
