#include "core/mosaic/build_config.h"

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;
using testing::WriteFile;

TEST(BuildConfig, ReadsEveryKey) {
  TempDir dir;
  auto path = WriteFile(dir / "c.json", R"({"name":"m","tile_size":512,"base_zoom":24,"min_zoom":14,
    "tile_format":"webp","webp_quality":90,"feather_power":2,"linger_frames":3,"lookahead_frames":50,"memory_cap_mb":64,
    "batch_frames":10,"threads":2,"background":"#102030",
    "navigation":{"columns":{"altitude_m":"alt2"},"utm_zone":52,"origin":[43.1,131.9]}})");
  BuildConfig c = LoadBuildConfig(path.string());
  EXPECT_EQ(c.name, "m");
  EXPECT_EQ(c.tile_size, 512);
  EXPECT_EQ(*c.base_zoom, 24);
  EXPECT_EQ(*c.min_zoom, 14);
  EXPECT_EQ(c.encoding.format, TileFormat::kWebp);
  EXPECT_EQ(c.encoding.webp_quality, 90);
  EXPECT_EQ(c.linger_frames, 3);
  EXPECT_EQ(c.lookahead_frames, 50);
  EXPECT_EQ(c.encoding.background, cv::Scalar(0x30, 0x20, 0x10));
  EXPECT_EQ(c.nav.columns.at("altitude_m"), "alt2");
  EXPECT_EQ(*c.nav.utm_zone, 52);
  EXPECT_DOUBLE_EQ(c.nav.origin->lon, 131.9);
}

TEST(BuildConfig, KeepsTheServerObjectForTheServerToRead) {
  BuildConfig c;
  EXPECT_FALSE(c.server.has_value());
  const auto server = nlohmann::json::parse(R"({"port": 9000, "tokn": "x"})");
  ApplyBuildConfig(nlohmann::json{{"server", server}}, "cfg.json", &c);
  ASSERT_TRUE(c.server.has_value());
  EXPECT_EQ(*c.server, server) << "checked by server::ServerOptions::FromJson, not here";
}

TEST(BuildConfig, ErrorsNameFileAndKey) {
  TempDir dir;
  auto expect_error = [&](const std::string& text, const std::string& key) {
    auto path = WriteFile(dir / "bad.json", text);
    try {
      LoadBuildConfig(path.string());
      FAIL() << "accepted " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path.string());
      EXPECT_EQ(e.field(), key) << e.what();
    }
  };
  expect_error(R"({"tile_size":300})", "tile_size");
  expect_error(R"({"tile_sise":256})", "tile_sise");
  expect_error(R"({"png_level":"fast"})", "png_level");
  expect_error(R"({"lookahead_frames":-1})", "lookahead_frames");
  expect_error(R"({"background":"red"})", "background");
  expect_error(R"({"navigation":{"colums":{}}})", "navigation.colums");
  expect_error(R"({"base_zoom":10,"min_zoom":12})", "min_zoom");
  auto path = WriteFile(dir / "broken.json", "{\"name\": ");
  EXPECT_THROW(LoadBuildConfig(path.string()), InputError);
  EXPECT_THROW(LoadBuildConfig((dir / "missing.json").string()), InputError);
}

}  // namespace
}  // namespace seamap
