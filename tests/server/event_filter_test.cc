// Which live events one stream carries, and which a batch can drop.
#include "server/event_filter.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "server/api_error.h"

namespace seamap::server {
namespace {

Event TileEvent(uint64_t id, const std::string& layer, int z, int x, int y) {
  return {id, "tile", nlohmann::json{{"layer", layer}, {"z", z}, {"x", x}, {"y", y}, {"version", "v"}}.dump()};
}

TEST(EventFilter, NoParametersKeepEverything) {
  const EventFilter f = EventFilter::Parse(std::nullopt, std::nullopt, std::nullopt, std::nullopt);
  EXPECT_TRUE(f.Keep(TileEvent(1, "x", 30, 5, 5)));
  EXPECT_TRUE(f.Keep({2, "progress", "{}"}));
}

TEST(EventFilter, LayersZoomsAndAreaApplyToTilesOnly) {
  // The empty item of "layers" is the main map.
  const EventFilter f =
      EventFilter::Parse(std::nullopt, std::string(",enhanced"), std::string("17-18,20"), std::string("-1,-1,1,1"));
  // Zoom 18 tiles around (0, 0): x 131071/131072, y 131071/131072.
  EXPECT_TRUE(f.Keep(TileEvent(1, "", 18, 131072, 131071)));
  EXPECT_TRUE(f.Keep(TileEvent(2, "enhanced", 17, 65535, 65536)));
  EXPECT_FALSE(f.Keep(TileEvent(3, "raw", 18, 131072, 131071))) << "layer";
  EXPECT_FALSE(f.Keep(TileEvent(4, "", 19, 262144, 262143))) << "zoom";
  EXPECT_FALSE(f.Keep(TileEvent(5, "", 18, 0, 0))) << "area";
  EXPECT_TRUE(f.Keep({6, "pose", "{}"})) << "not a tile";
  EXPECT_FALSE(EventFilter::Parse(std::nullopt, std::string(""), std::nullopt, std::nullopt)
                   .Keep(TileEvent(7, "enhanced", 3, 1, 1)))
      << "layers= alone is the main map only";
}

TEST(EventFilter, TypesPickEventTypes) {
  const EventFilter f = EventFilter::Parse(std::string("pose,detection"), std::nullopt, std::nullopt, std::nullopt);
  EXPECT_TRUE(f.Keep({1, "pose", "{}"}));
  EXPECT_TRUE(f.Keep({2, "detection", "{}"}));
  EXPECT_FALSE(f.Keep({3, "track", "{}"}));
  EXPECT_FALSE(f.Keep(TileEvent(4, "", 3, 1, 1)));
}

TEST(EventFilter, BadParametersNameTheParameter) {
  const std::vector<std::array<std::optional<std::string>, 4>> cases = {
      {std::string("tiles"), std::nullopt, std::nullopt, std::nullopt},
      {std::nullopt, std::nullopt, std::string("31"), std::nullopt},
      {std::nullopt, std::nullopt, std::string("5-2"), std::nullopt},
      {std::nullopt, std::nullopt, std::string("a"), std::nullopt},
      {std::nullopt, std::nullopt, std::nullopt, std::string("1,2,3")},
      {std::nullopt, std::nullopt, std::nullopt, std::string("1,2,x,4")},
      {std::nullopt, std::nullopt, std::nullopt, std::string("3,0,1,1")},
  };
  const char* names[] = {"types", "zoom", "zoom", "zoom", "bbox", "bbox", "bbox"};
  for (size_t i = 0; i < cases.size(); ++i) {
    try {
      EventFilter::Parse(cases[i][0], cases[i][1], cases[i][2], cases[i][3]);
      ADD_FAILURE() << "case " << i << " accepted";
    } catch (const ApiError& e) {
      EXPECT_EQ(e.status(), 400);
      EXPECT_NE(std::string(e.what()).find(names[i]), std::string::npos) << e.what();
    }
  }
}

TEST(Coalesce, KeepsTheLastOfEachTileAndPoseAndEveryTrackPoint) {
  std::vector<Event> batch = {TileEvent(1, "", 5, 1, 1),   {2, "pose", "{\"frame\":1}"}, {3, "track", "{\"seq\":1}"},
                              TileEvent(4, "", 5, 1, 2),   TileEvent(5, "", 5, 1, 1),    {6, "pose", "{\"frame\":2}"},
                              {7, "track", "{\"seq\":2}"}, {8, "progress", "{}"},        {9, "detection", "{}"},
                              {10, "progress", "{}"}};
  std::vector<uint64_t> ids;
  for (const Event& e : Coalesce(batch)) ids.push_back(e.id);
  EXPECT_EQ(ids, (std::vector<uint64_t>{3, 4, 5, 6, 7, 9, 10}));
  EXPECT_TRUE(Coalesce({}).empty());
}

}  // namespace
}  // namespace seamap::server
