// Every tool's command line through CLI11 in one style: --help prints the options to stdout
// and ends with status 0; bad usage (an unknown option, "12abc" for a number, a value out of
// range, a missing required option) prints "<tool>: <what is wrong>" and a pointer to --help
// to stderr and ends with status 2.
//
//   CLI::App app{"make_scenario: renders a scenario preset into a rosbag", "make_scenario"};
//   app.add_option("--frames", o.frames, "frames to render")->required()->check(CLI::Range(1, 1000000));
//   if (const auto status = parseCommandLine(app, argc, argv)) return *status;
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace soccer_vision {

// The exit status to end with now (after --help or bad usage), or nullopt to go on.
std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv);

// The same for a tool that roslaunch starts: roslaunch's remappings (__name:=, __log:=) are
// not the tool's, and an empty --key= value (an empty launch argument, the only form that
// survives roslaunch's argument splitting) leaves the option at its default.
std::optional<int> parseLaunchedCommandLine(CLI::App& app, int argc, char** argv);

// Bad usage found after parsing (options that do not go together): the same message style;
// returns 2, the status to end with.
int usageError(const CLI::App& app, const std::string& message);

}  // namespace soccer_vision
