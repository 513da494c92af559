// Issue 32 over HTTP: an operator's mark with a box and a class the model
// does not know is stored with both; bad boxes get a 400 naming the property.
#include "tests/server/http_test_fixture.h"

namespace seamap::server::http_test {
namespace {

// A closed ring NW, SW, SE, NE, NW around (lon, lat), `d` degrees each way.
json Ring(double lon, double lat, double d) {
  return {{lon - d, lat + d}, {lon - d, lat - d}, {lon + d, lat - d}, {lon + d, lat + d}, {lon - d, lat + d}};
}

TEST_F(HttpServerTest, AMarkWithABoxAndANewClassIsStored) {
  Start();
  auto client = Client();
  json body = Mark(5.002, 43.002, "drum");
  body["properties"]["box"] = Ring(5.002, 43.002, 0.000004);
  auto created = client->Post("/api/detections", body.dump(), "application/geo+json");
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201) << created->body;
  const json mark = json::parse(created->body);
  EXPECT_EQ(mark["properties"]["class"], "drum");
  ASSERT_EQ(mark["properties"]["box"].size(), 5u);
  EXPECT_NEAR(mark["properties"]["box"][0][0].get<double>(), 5.002 - 0.000004, 1e-12);
  // 8e-6 degrees: 0.89 m of latitude, 0.65 m of longitude at 43 N.
  EXPECT_NEAR(mark["properties"]["size_m"][1].get<double>(), 0.89, 0.01);
  EXPECT_NEAR(mark["properties"]["size_m"][0].get<double>(), 0.65, 0.01);
  const int64_t id = mark["id"];
  ASSERT_TRUE(StoredDetections().count(id));
  EXPECT_EQ(StoredDetections().at(id).box.size(), 5u) << "written through to the file";
  const json status = GetJson("/api/status");
  const auto& classes = status["classes"];
  EXPECT_NE(std::find(classes.begin(), classes.end(), "drum"), classes.end()) << status.dump();

  // PATCH a size instead; then a bad box is refused and nothing changes.
  auto resized = client->Patch("/api/detections/" + std::to_string(id),
                               json{{"box", nullptr}, {"size_m", {1.2, 0.5}}}.dump(), "application/json");
  ASSERT_TRUE(resized);
  ASSERT_EQ(resized->status, 200) << resized->body;
  EXPECT_NEAR(json::parse(resized->body)["properties"]["size_m"][0].get<double>(), 1.2, 1e-3);
  ExpectError(
      client->Patch("/api/detections/" + std::to_string(id), json{{"size_m", {0, 1}}}.dump(), "application/json"), 400,
      "properties.size_m", "zero size");
  json outside = Mark(5.002, 43.002, "drum");
  outside["properties"]["box"] = Ring(5.1, 43.1, 0.000004);
  ExpectError(client->Post("/api/detections", outside.dump(), "application/json"), 400, "properties.box",
              "point outside its box");
  json open = Mark(5.002, 43.002, "drum");
  open["properties"]["box"] = json::array({{5.0, 43.0}, {5.1, 43.1}});
  ExpectError(client->Post("/api/detections", open.dump(), "application/json"), 400, "properties.box", "two points");
  EXPECT_NEAR(StoredDetections().at(id).size_m->at(0), 1.2, 1e-3);
  // A recogniser's box is not the operator's to change.
  ExpectError(client->Patch("/api/detections/1", json{{"size_m", {2, 2}}}.dump(), "application/json"), 403, "size_m",
              "recogniser's box");
}

}  // namespace
}  // namespace seamap::server::http_test
