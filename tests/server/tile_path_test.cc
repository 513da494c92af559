// ParseTilePath: the tile a path names, or a 400 that says what is wrong.
#include "server/tile_path.h"

#include <random>

#include <gtest/gtest.h>

#include "server/api_error.h"

namespace seamap::server {
namespace {

TEST(TilePath, ReadsZxyTheExtensionAndALayer) {
  TilePath t = ParseTilePath("3/4/2.png");
  EXPECT_EQ(t.layer, "");
  EXPECT_EQ(t.id, (TileId{3, 4, 2}));
  EXPECT_EQ(t.ext, "png");
  t = ParseTilePath("enhanced/17/65535/131071.jpeg");
  EXPECT_EQ(t.layer, "enhanced");
  EXPECT_EQ(t.id, (TileId{17, 65535, 131071}));
  EXPECT_EQ(t.ext, "jpeg");
  t = ParseTilePath("30/1073741823/0.webp");
  EXPECT_EQ(t.id, (TileId{30, 1073741823, 0}));
  EXPECT_EQ(ParseTilePath("0/0/0.").ext, "") << "the extension is the caller's to judge";
  EXPECT_EQ(ParseTilePath("3/4/2.tar.gz").ext, "tar.gz");
}

TEST(TilePath, BadPathsAre400sThatSayWhatIsWrong) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "tile path: expected /tiles/{z}/{x}/{y}"},
      {"/", "tile path: expected /tiles/{z}/{x}/{y}"},
      {"3", "tile path: expected"},
      {"3/4", "tile path: expected"},
      {"3/4/2", "{y}.{ext}"},
      {"3/4/2.png/", "tile path: expected"},
      {"a/b/3/4/2.png", "tile path: expected"},
      {"3/4/2/1/0.png", "tile path: expected"},
      {"/3/4/2.png", "empty layer"},
      {"3//2.png", "non-negative integers, got ''"},
      {"3/4/.png", "non-negative integers, got ''"},
      {"31/0/0.png", "zoom 31 is out of range 0..30"},
      {"3/8/0.png", "below 2^z = 8 at zoom 3"},
      {"3/0/8.png", "below 2^z = 8"},
      {"30/1073741824/0.png", "below 2^z"},
      {"-1/0/0.png", "got '-1'"},
      {"+1/0/0.png", "got '+1'"},
      {" 3/4/2.png", "got ' 3'"},
      {"3/4/2 .png", "got '2 '"},
      {"3/4/0x2.png", "got '0x2'"},
      {"3/4e0/2.png", "got '4e0'"},
      {"99999999999/0/0.png", "got '99999999999'"},
      {std::string("3/4/2\0.png", 10), "non-negative integers"},
  };
  for (const auto& [path, needle] : cases) {
    try {
      ParseTilePath(path);
      ADD_FAILURE() << "accepted '" << path << "'";
    } catch (const ApiError& e) {
      EXPECT_EQ(e.status(), 400) << path;
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << path << ": " << e.what();
    }
  }
}

// Random strings over the characters of tile paths: either a tile in range
// or a 400, never anything else.
TEST(TilePath, RandomPathsAreATileInRangeOrA400) {
  std::mt19937 random(7);
  const std::string alphabet = "0123456789/./.-pngx";
  for (int i = 0; i < 20000; ++i) {
    std::string path(random() % 24, ' ');
    for (char& c : path) c = alphabet[random() % alphabet.size()];
    try {
      const TilePath t = ParseTilePath(path);
      ASSERT_TRUE(t.id.z >= 0 && t.id.z <= 30) << path;
      ASSERT_TRUE(t.id.x >= 0 && t.id.y >= 0 && t.id.x < (int64_t{1} << t.id.z) && t.id.y < (int64_t{1} << t.id.z))
          << path;
    } catch (const ApiError& e) {
      ASSERT_EQ(e.status(), 400) << path;
    }
  }
}

TEST(TilePath, EveryTileInRangeReadsBack) {
  std::mt19937 random(11);
  for (int i = 0; i < 2000; ++i) {
    const int z = static_cast<int>(random() % 31);
    const TileId id{z, static_cast<int>(random() % (uint32_t{1} << z)),
                    static_cast<int>(random() % (uint32_t{1} << z))};
    const std::string path = std::to_string(id.z) + "/" + std::to_string(id.x) + "/" + std::to_string(id.y) + ".png";
    EXPECT_EQ(ParseTilePath(path).id, id) << path;
  }
}

}  // namespace
}  // namespace seamap::server
