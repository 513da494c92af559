#include "core/mosaic/build_config.h"

#include <gtest/gtest.h>

#include <functional>

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
  EXPECT_EQ(c.map.name, "m");
  EXPECT_EQ(c.map.tile_size, 512);
  EXPECT_EQ(*c.map.base_zoom, 24);
  EXPECT_EQ(*c.map.min_zoom, 14);
  EXPECT_EQ(c.map.encoding.format, TileFormat::kWebp);
  EXPECT_EQ(c.map.encoding.webp_quality, 90);
  EXPECT_EQ(c.buffer.linger_frames, 3);
  EXPECT_EQ(c.buffer.lookahead_frames, 50);
  EXPECT_EQ(c.map.encoding.background, cv::Scalar(0x30, 0x20, 0x10));
  EXPECT_EQ(c.nav.columns.at("altitude_m"), "alt2");
  EXPECT_EQ(*c.nav.utm_zone, 52);
  EXPECT_DOUBLE_EQ(c.nav.origin->lon, 131.9);
}

TEST(BuildConfig, TerrainIsTrueOrAHeightModelsFile) {
  BuildConfig c;
  EXPECT_FALSE(c.terrain.enabled());
  ApplyBuildConfig(nlohmann::json{{"terrain", true}}, "cfg.json", &c);
  EXPECT_TRUE(c.terrain.estimate);
  ApplyBuildConfig(nlohmann::json{{"terrain", "dem.tif"}}, "cfg.json", &c);
  EXPECT_FALSE(c.terrain.estimate);
  EXPECT_EQ(c.terrain.file, "dem.tif");
  ApplyBuildConfig(nlohmann::json{{"terrain", false}}, "cfg.json", &c);
  EXPECT_FALSE(c.terrain.enabled());
  for (const auto& bad : {nlohmann::json(3), nlohmann::json(""), nlohmann::json::object()}) {
    try {
      ApplyBuildConfig(nlohmann::json{{"terrain", bad}}, "cfg.json", &c);
      FAIL() << bad.dump();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("terrain"), std::string::npos) << e.what();
    }
  }
}

TEST(BuildConfig, KeepsTheServerObjectForTheServerToRead) {
  BuildConfig c;
  EXPECT_FALSE(c.server.has_value());
  const auto server = nlohmann::json::parse(R"({"port": 9000, "tokn": "x"})");
  ApplyBuildConfig(nlohmann::json{{"server", server}}, "cfg.json", &c);
  ASSERT_TRUE(c.server.has_value());
  EXPECT_EQ(*c.server, server) << "checked by server::ServerOptions::FromJson, not here";
}

TEST(BuildConfig, CheckNamesTheKeyOfEachConcern) {
  // Each option struct checks its own values; ApplyBuildConfig runs them all.
  auto key_of = [](const std::function<void(BuildConfig&)>& change) {
    BuildConfig c;
    change(c);
    try {
      c.Check("cfg.json");
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "cfg.json");
      return e.field();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(key_of([](BuildConfig&) {}), "accepted");
  EXPECT_EQ(key_of([](BuildConfig& c) { c.map.tile_size = 300; }), "tile_size");
  EXPECT_EQ(key_of([](BuildConfig& c) { c.map.encoding.jpeg_quality = 0; }), "jpeg_quality");
  EXPECT_EQ(key_of([](BuildConfig& c) { c.blend.seam_band = 1.5; }), "seam_band");
  EXPECT_EQ(key_of([](BuildConfig& c) { c.blend.feather_power = 0; }), "feather_power");
  EXPECT_EQ(key_of([](BuildConfig& c) { c.buffer.memory_cap_mb = 4; }), "memory_cap_mb");
  EXPECT_EQ(key_of([](BuildConfig& c) { c.buffer.batch_seconds = -1; }), "batch_seconds");
  EXPECT_EQ(key_of([](BuildConfig& c) { c.buffer.checkpoint_seconds = -1; }), "checkpoint_seconds");
  EXPECT_EQ(key_of([](BuildConfig& c) { c.frames.sixteen_bit_white = 0; }), "sixteen_bit_white");
  EXPECT_EQ(key_of([](BuildConfig& c) { c.threads = -2; }), "threads");
  EXPECT_EQ(key_of([](BuildConfig& c) { c.layers = "all"; }), "layers");
}

TEST(MemoryBudget, SharesAddUpToTheCap) {
  for (int cap_mb : {16, 100, 512, 4096}) {
    const MemoryBudget b = MemoryBudget::Of(cap_mb);
    const size_t cap = static_cast<size_t>(cap_mb) << 20;
    EXPECT_EQ(b.frames_bytes + b.tile_buffer_bytes + b.overview_bytes + b.finished_weights_bytes, cap) << cap_mb;
    EXPECT_GT(b.tile_buffer_bytes, cap / 2);
  }
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
