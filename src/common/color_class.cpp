#include "soccer_vision/common/color_class.h"

namespace soccer_vision {
namespace {
constexpr std::array<std::string_view, kNumColorClasses> kNames = {
    "none",  "blue", "yellow", "pink",   "purple", "sky_blue",
    "green", "red",  "orange", "carpet", "line",   "robot_top"};
}  // namespace

std::string_view colorClassName(ColorClass c) {
  const auto i = static_cast<std::size_t>(c);
  return i < kNames.size() ? kNames[i] : std::string_view("invalid");
}

std::string colorClassNames(const std::vector<ColorClass>& classes) {
  std::string names;
  for (const ColorClass c : classes) names += (names.empty() ? "" : ", ") + std::string(colorClassName(c));
  return names;
}

std::optional<ColorClass> parseColorClass(std::string_view name) {
  for (std::size_t i = 0; i < kNames.size(); ++i) {
    if (kNames[i] == name) return static_cast<ColorClass>(i);
  }
  return std::nullopt;
}

std::string_view teamName(Team t) { return t == Team::Blue ? "blue" : "yellow"; }

std::optional<Team> parseTeam(std::string_view name) {
  if (name == "blue") return Team::Blue;
  if (name == "yellow") return Team::Yellow;
  return std::nullopt;
}

}  // namespace soccer_vision
