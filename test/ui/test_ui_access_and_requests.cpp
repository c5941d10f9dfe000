// The calibration UI's access policy and request checks (no server, no ROS).
#include <gtest/gtest.h>

#include "soccer_vision/ui/ui_access.h"
#include "soccer_vision/ui/ui_requests.h"

namespace soccer_vision {
namespace {

TEST(UiAccess, LoopbackAddressesAreRecognised) {
  EXPECT_TRUE(isLoopbackAddress("127.0.0.1"));
  EXPECT_TRUE(isLoopbackAddress("127.1.2.3"));
  EXPECT_TRUE(isLoopbackAddress("::1"));
  EXPECT_TRUE(isLoopbackAddress("localhost"));
  EXPECT_FALSE(isLoopbackAddress("0.0.0.0"));
  EXPECT_FALSE(isLoopbackAddress("::"));
  EXPECT_FALSE(isLoopbackAddress("192.168.1.10"));
  EXPECT_FALSE(isLoopbackAddress("vision-pc"));
}

TEST(UiAccess, LoopbackWithoutTokenAllowsChanges) {
  const UiAccess access("127.0.0.1", "");
  EXPECT_TRUE(access.changesEnabled());
  EXPECT_FALSE(access.tokenRequired());
  EXPECT_TRUE(access.mayChange(""));
}

TEST(UiAccess, BeyondLoopbackWithoutTokenRefusesEveryChange) {
  const UiAccess access("0.0.0.0", "");
  EXPECT_FALSE(access.changesEnabled());
  EXPECT_FALSE(access.mayChange(""));
  EXPECT_FALSE(access.mayChange("anything"));
  EXPECT_NE(access.readOnlyReason().find("ui_token"), std::string::npos) << access.readOnlyReason();
}

TEST(UiAccess, ATokenIsRequiredExactlyWhereverTheServerListens) {
  for (const char* address : {"127.0.0.1", "0.0.0.0"}) {
    const UiAccess access(address, "s3cret");
    EXPECT_TRUE(access.changesEnabled()) << address;
    EXPECT_TRUE(access.mayChange("s3cret")) << address;
    EXPECT_FALSE(access.mayChange("")) << address;
    EXPECT_FALSE(access.mayChange("s3cre")) << address;
    EXPECT_FALSE(access.mayChange("s3cret!")) << address;
    EXPECT_FALSE(access.mayChange("S3cret")) << address;
  }
}

int statusOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const UiRequestError& e) {
    return e.status;
  }
  return 200;
}

TEST(UiRequests, BodiesMustBeSmallJsonObjects) {
  UiRequestLimits limits;
  limits.max_body_bytes = 20;
  EXPECT_EQ(statusOf([&] { parseJsonBody("{\"a\": 1}", limits); }), 200);
  EXPECT_EQ(statusOf([&] { parseJsonBody("{\"a\": 1", limits); }), 400);
  EXPECT_EQ(statusOf([&] { parseJsonBody("[1, 2]", limits); }), 400);
  EXPECT_EQ(statusOf([&] { parseJsonBody("{\"a\": \"" + std::string(30, 'x') + "\"}", limits); }), 413);
}

TEST(UiRequests, SamplesBecomePolygonsPerClass) {
  const auto body = nlohmann::json::parse(
      R"({"samples": {"blue": [[[10, 10], [20, 10], [20, 20]]], "carpet": [[[0, 0], [5, 0], [5, 5]], [[-0.5, -0.5], [1, 0], [0, 1]]]}})");
  const ColorSamples samples = parseSamplesRequest(body, 640, 480, UiRequestLimits());
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_EQ(samples.at(ColorClass::Blue).size(), 1u);
  EXPECT_EQ(samples.at(ColorClass::Carpet).size(), 2u);
  EXPECT_DOUBLE_EQ(samples.at(ColorClass::Blue)[0][1].x(), 20.0);
}

TEST(UiRequests, BadSamplesAreRefusedNamingTheField) {
  auto message = [](const std::string& json, int width = 640, int height = 480) {
    try {
      parseSamplesRequest(nlohmann::json::parse(json), width, height, UiRequestLimits());
    } catch (const UiRequestError& e) {
      EXPECT_EQ(e.status, 400);
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(R"({})").find("samples"), std::string::npos);
  EXPECT_NE(message(R"({"samples": {"magenta": [[[1, 1], [2, 1], [2, 2]]]}})").find("magenta"),
            std::string::npos);
  EXPECT_NE(message(R"({"samples": {"blue": [[[1, 1], [2, 1]]]}})").find("samples.blue[0]"),
            std::string::npos);
  EXPECT_NE(message(R"({"samples": {"blue": [[[1, 1], [2, 1], [2, "x"]]]}})").find("samples.blue[0][2][1]"),
            std::string::npos);
  EXPECT_NE(message(R"({"samples": {"blue": [[[1, 1], [700, 1], [2, 2]]]}})").find("outside"),
            std::string::npos);
  EXPECT_NE(message(R"({"samples": {}})").find("no class"), std::string::npos);
  UiRequestLimits few;
  few.max_polygons = 1;
  EXPECT_EQ(statusOf([&] {
              parseSamplesRequest(
                  nlohmann::json::parse(
                      R"({"samples": {"blue": [[[1, 1], [2, 1], [2, 2]], [[1, 1], [2, 1], [2, 2]]]}})"),
                  640, 480, few);
            }),
            400);
}

TEST(UiRequests, CorrespondencesNeedFourToSixtyFourFinitePoints) {
  nlohmann::json body = {{"points", nlohmann::json::array()}};
  for (int i = 0; i < 4; ++i)
    body["points"].push_back({{"pixel", {100.0 + i, 200.0}}, {"field", {-4.5 + i, 3.0, 0.0}}});
  const auto points = parseCorrespondencesRequest(body, 640, 480, UiRequestLimits());
  ASSERT_EQ(points.size(), 4u);
  EXPECT_DOUBLE_EQ(points[3].pixel.x(), 103.0);
  EXPECT_DOUBLE_EQ(points[3].field.x(), -1.5);

  nlohmann::json three = body;
  three["points"].erase(3);
  EXPECT_EQ(statusOf([&] { parseCorrespondencesRequest(three, 640, 480, UiRequestLimits()); }), 400);
  nlohmann::json far = body;
  far["points"][0]["field"][0] = 1e9;
  EXPECT_EQ(statusOf([&] { parseCorrespondencesRequest(far, 640, 480, UiRequestLimits()); }), 400);
  nlohmann::json outside = body;
  outside["points"][1]["pixel"][1] = 480.0;
  EXPECT_EQ(statusOf([&] { parseCorrespondencesRequest(outside, 640, 480, UiRequestLimits()); }), 400);
}

TEST(UiRequests, CameraIdsAreSmallNumbers) {
  EXPECT_EQ(parseCameraId("0"), 0);
  EXPECT_EQ(parseCameraId("12"), 12);
  EXPECT_EQ(statusOf([] { parseCameraId("256"); }), 404);
  EXPECT_EQ(statusOf([] { parseCameraId("-1"); }), 404);
  EXPECT_EQ(statusOf([] { parseCameraId("0x1"); }), 404);
  EXPECT_EQ(statusOf([] { parseCameraId(""); }), 404);
}

}  // namespace
}  // namespace soccer_vision
