#include "tool_command_line.h"

#include <iostream>
#include <vector>

namespace soccer_vision {

std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);  // the help text on stdout, status 0
  } catch (const CLI::ParseError& error) {
    return usageError(app, error.what());
  }
}

std::optional<int> parseLaunchedCommandLine(CLI::App& app, int argc, char** argv) {
  std::vector<char*> kept;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    const bool remapping = i > 0 && a.find(":=") != std::string::npos;
    const bool empty_value = i > 0 && a.rfind("--", 0) == 0 && a.size() > 3 && a.back() == '=';
    if (!remapping && !empty_value) kept.push_back(argv[i]);
  }
  return parseCommandLine(app, static_cast<int>(kept.size()), kept.data());
}

int usageError(const CLI::App& app, const std::string& message) {
  std::cerr << app.get_name() << ": " << message << "\n"
            << "run '" << app.get_name() << " --help' for the options\n";
  return 2;
}

}  // namespace soccer_vision
