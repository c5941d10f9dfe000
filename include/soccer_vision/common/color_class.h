// The colour classes the whole pipeline speaks about (docs/formats.md).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace soccer_vision {

// Values are stable: they appear in messages, label images and colour-table files.
enum class ColorClass : std::uint8_t {
  None = 0,  // unlabelled / background without samples
  Blue,      // team
  Yellow,    // team
  Pink,      // role id 0 (two-tag pattern); "1" bit of the SSL pattern
  Purple,    // role id 1
  SkyBlue,   // role id 2
  Green,     // role id 3; "0" bit of the SSL pattern
  Red,       // role id 4
  Orange,    // ball
  Carpet,    // background classes, present when the table has samples for them
  Line,
  RobotTop,
  Count
};

constexpr int kNumColorClasses = static_cast<int>(ColorClass::Count);

// Name used in YAML/JSON files ("sky_blue", "robot_top", ...).
std::string_view colorClassName(ColorClass c);
// Their names joined by ", " in the order given ("pink, purple"), for messages.
std::string colorClassNames(const std::vector<ColorClass>& classes);
// Parses a name as written by colorClassName; nullopt for unknown names.
std::optional<ColorClass> parseColorClass(std::string_view name);

// A marker colour is one a robot pattern or the ball uses (Blue..Orange).
constexpr bool isMarkerColor(ColorClass c) { return c >= ColorClass::Blue && c <= ColorClass::Orange; }
// A colour a robot pattern uses (Blue..Red): a marker colour but the ball's.
constexpr bool isRobotMarkerColor(ColorClass c) { return isMarkerColor(c) && c != ColorClass::Orange; }
// A team's colour (Blue, Yellow).
constexpr bool isTeamColor(ColorClass c) { return c == ColorClass::Blue || c == ColorClass::Yellow; }

enum class Team : std::uint8_t { Blue = 0, Yellow = 1 };
std::string_view teamName(Team t);
std::optional<Team> parseTeam(std::string_view name);
constexpr ColorClass teamColor(Team t) { return t == Team::Blue ? ColorClass::Blue : ColorClass::Yellow; }

}  // namespace soccer_vision
