// The tools' command lines: flags and their values read in order, numbers parsed whole
// ("12abc" and "" are errors, not 12 and 0), every error a std::invalid_argument naming
// the flag, so that each tool reports bad arguments the same way (usage, exit status 2).
//
//   for (CommandLine args(argc, argv); args.next();) {
//     if (args.flag() == "--out") o.out = args.value();
//     else if (args.flag() == "--frames") o.frames = args.integer(1);
//     else throw std::invalid_argument("unknown argument '" + args.flag() + "'");
//   }
#pragma once

#include <climits>
#include <string>
#include <vector>

namespace soccer_vision {

double parseNumber(const std::string& flag, const std::string& text);  // finite numbers only
int parseInteger(const std::string& flag, const std::string& text, int min = INT_MIN, int max = INT_MAX);
// "a,b,,c" -> {a, b, c}
std::vector<std::string> splitList(const std::string& text, char separator = ',');

class CommandLine {
 public:
  CommandLine(int argc, char** argv) : argc_(argc), argv_(argv) {}
  bool next();  // moves to the next flag; false after the last
  const std::string& flag() const { return flag_; }
  std::string value();  // the argument after the flag; throws when there is none
  double number() { return parseNumber(flag_, value()); }
  int integer(int min = INT_MIN, int max = INT_MAX) { return parseInteger(flag_, value(), min, max); }
  std::vector<std::string> list() { return splitList(value()); }

 private:
  int argc_;
  char** argv_;
  int index_ = 0;
  std::string flag_;
};

}  // namespace soccer_vision
