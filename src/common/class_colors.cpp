#include "soccer_vision/common/class_colors.h"

namespace soccer_vision {

namespace {
constexpr float kAlbedoScale = 1 / 1.25f;  // headroom: white at unit gain stays < 255
}  // namespace

cv::Vec3f albedoFromRgb(float r, float g, float b) { return cv::Vec3f(b, g, r) * kAlbedoScale; }

cv::Vec3f classAlbedo(ColorClass c) {
  switch (c) {
    case ColorClass::Blue:
      return albedoFromRgb(20, 80, 200);
    case ColorClass::Yellow:
      return albedoFromRgb(240, 220, 30);
    case ColorClass::Pink:
      return albedoFromRgb(255, 80, 180);
    case ColorClass::Purple:
      return albedoFromRgb(140, 40, 180);
    case ColorClass::SkyBlue:
      return albedoFromRgb(80, 200, 240);
    case ColorClass::Green:
      return albedoFromRgb(40, 220, 60);
    case ColorClass::Red:
      return albedoFromRgb(230, 30, 30);
    case ColorClass::Orange:
      return albedoFromRgb(255, 120, 0);
    case ColorClass::Carpet:
      return albedoFromRgb(50, 120, 45);
    case ColorClass::Line:
      return albedoFromRgb(235, 235, 235);
    case ColorClass::RobotTop:
      return albedoFromRgb(25, 25, 25);
    case ColorClass::None:  // the grey hall floor around the carpet
    case ColorClass::Count:
      break;
  }
  return albedoFromRgb(110, 105, 100);
}

}  // namespace soccer_vision
