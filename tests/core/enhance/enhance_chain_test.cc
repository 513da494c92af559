#include "core/enhance/enhance_chain.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "core/util/error.h"
#include "tests/core/enhance/synthetic_images.h"

namespace seamap {
namespace {
using nlohmann::json;

std::string FieldOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.field();
  }
  return "no error";
}

TEST(EnhanceChain, ParsesOpListWithInlineParameters) {
  EnhanceChain c = EnhanceChain::FromOpList("flatfield, clahe:clip_limit=3:tile_grid=4,dehaze:gate=false", "--ops");
  ASSERT_EQ(c.ops().size(), 3u);
  EXPECT_EQ(c.Names(), "flatfield,clahe:clip_limit=3:tile_grid=4,dehaze:gate=false");  // non-defaults only
  EXPECT_EQ(EnhanceChain::FromOpList(c.Names(), "names").Describe(), c.Describe());
  EXPECT_EQ(c.ops()[1]->params()["clip_limit"], 3.0);
  EXPECT_EQ(c.ops()[1]->params()["tile_grid"], 4);
  EXPECT_EQ(c.ops()[2]->params()["gate"], false);
  EXPECT_NE(c.Describe().find("clahe(clip_limit=3, tile_grid=4)"), std::string::npos) << c.Describe();
  EXPECT_TRUE(EnhanceChain::FromOpList("none", "--ops").empty());
  EXPECT_TRUE(EnhanceChain::FromOpList("", "--ops").empty());
  EXPECT_EQ(EnhanceChain::FromOpList("default", "--ops").Names(), EnhanceChain::Default().Names());
}

TEST(EnhanceChain, OpListErrorsNameTheOpAndParameter) {
  EXPECT_EQ(FieldOf([] { EnhanceChain::FromOpList("clahe,sharpen", "--ops"); }), "sharpen");
  EXPECT_EQ(FieldOf([] { EnhanceChain::FromOpList("clahe:clip=2", "--ops"); }), "clahe.clip");
  EXPECT_EQ(FieldOf([] { EnhanceChain::FromOpList("clahe:clip_limit=-2", "--ops"); }), "clahe.clip_limit");
  EXPECT_EQ(FieldOf([] { EnhanceChain::FromOpList("clahe:tile_grid=2.5", "--ops"); }), "clahe.tile_grid");
  EXPECT_EQ(FieldOf([] { EnhanceChain::FromOpList("dehaze:gate=maybe", "--ops"); }), "dehaze.gate");
  EXPECT_EQ(FieldOf([] { EnhanceChain::FromOpList("clahe:3", "--ops"); }), "clahe");
  try {
    EnhanceChain::FromOpList("sharpen", "--ops");
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "--ops");
    EXPECT_NE(std::string(e.what()).find("flatfield"), std::string::npos) << "lists known ops: " << e.what();
  }
}

TEST(EnhanceChain, ParsesJsonConfigAndRoundTrips) {
  json config = json::parse(R"({"ops": [{"op": "flatfield", "seed_frames": 5},
                                        {"op": "clahe", "clip_limit": 2.5, "tile_grid": 6},
                                        {"op": "gamma", "gamma": 0.7}]})");
  EnhanceChain c = EnhanceChain::FromJson(config, "enhance.json");
  EXPECT_EQ(c.Names(), "flatfield:seed_frames=5,clahe:clip_limit=2.5:tile_grid=6,gamma:gamma=0.7");
  EXPECT_EQ(c.SeedFrames(), 5);
  EnhanceChain again = EnhanceChain::FromJson(c.ToJson(), "round trip");
  EXPECT_EQ(again.Describe(), c.Describe());
}

TEST(EnhanceChain, JsonErrorsNameFileOpAndParameter) {
  auto parse = [](const char* text) { return [text] { EnhanceChain::FromJson(json::parse(text), "enhance.json"); }; };
  EXPECT_EQ(FieldOf(parse(R"({"ops": [{"op": "clahe", "clip_limt": 2}]})")), "clahe.clip_limt");
  EXPECT_EQ(FieldOf(parse(R"({"ops": [{"op": "clahe", "clip_limit": "high"}]})")), "clahe.clip_limit");
  EXPECT_EQ(FieldOf(parse(R"({"ops": [{"op": "blur"}]})")), "blur");
  EXPECT_EQ(FieldOf(parse(R"({"ops": [{"clip_limit": 2}]})")), "ops[0]");
  EXPECT_EQ(FieldOf(parse(R"({"ops": {"op": "clahe"}})")), "ops");
  EXPECT_EQ(FieldOf(parse(R"({"ops": [], "extra": 1})")), "extra");
  EXPECT_EQ(FieldOf(parse(R"({"_note": "ok", "ops": [{"op": "clahe", "comment": "ok"}]})")), "no error");
  EXPECT_EQ(FieldOf(parse(R"({"ops": [{"op": "dehaze", "t0": 0}]})")), "dehaze.t0");
  try {
    parse(R"({"ops": [{"op": "dehaze", "t0": 0}]})")();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "enhance.json");
  }
}

TEST(EnhanceChain, EveryOpKeepsTypeAndSizeForAllSupportedTypes) {
  std::string all;
  for (const auto& name : EnhanceOpNames()) all += (all.empty() ? "" : ",") + name;
  all += ",dehaze:gate=false";
  cv::Mat gray = testing::Texture({160, 120}, 20), colour = testing::ColorTexture({160, 120}, 21);
  for (const cv::Mat& unit : {gray, colour})
    for (int depth : {CV_8U, CV_16U}) {
      cv::Mat img = testing::ToType(unit, depth);
      EnhanceChain c = EnhanceChain::FromOpList(all, "test");  // one flat field per survey format
      cv::Mat out = c.Apply(img);
      EXPECT_EQ(out.type(), img.type());
      EXPECT_EQ(out.size(), img.size());
    }
}

TEST(EnhanceChain, RejectsUnsupportedImagesNamingTheOp) {
  EnhanceChain c = EnhanceChain::FromOpList("clahe", "test");
  EXPECT_EQ(FieldOf([&] { c.Apply(cv::Mat(10, 10, CV_32FC1, cv::Scalar(0.5))); }), "clahe");
  EXPECT_EQ(FieldOf([&] { c.Apply(cv::Mat(10, 10, CV_8UC4, cv::Scalar::all(5))); }), "clahe");
}

TEST(EnhanceChain, DefaultChainRaisesContrastOfDimUnevenFrame) {
  cv::Mat unit = testing::Multiply(testing::Texture({320, 240}, 22, 0.3, 0.5), testing::RadialFalloff({320, 240}, 0.6));
  cv::Mat img = testing::ToType(unit, CV_8U);
  cv::Mat out = EnhanceChain::Default().Apply(img);
  cv::Scalar m0, s0, m1, s1;
  cv::meanStdDev(img, m0, s0);
  cv::meanStdDev(out, m1, s1);
  EXPECT_GT(s1[0], 1.5 * s0[0]);
}

TEST(EnhanceChain, SeedAndApplyFromTwoThreads) {
  EnhanceChain c = EnhanceChain::FromOpList("flatfield:seed_frames=4,clahe", "test");
  cv::Mat lamp = testing::RadialFalloff({160, 120}, 0.5);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 12; ++i)
    frames.push_back(testing::ToType(testing::Multiply(testing::Texture({160, 120}, 30 + i), lamp), CV_8U));
  c.Seed(std::vector<cv::Mat>(frames.begin(), frames.begin() + c.SeedFrames()));
  std::vector<cv::Mat> out(frames.size());
  auto worker = [&](size_t start) {
    for (size_t i = start; i < frames.size(); i += 2) out[i] = c.Apply(frames[i]);
  };
  std::thread a(worker, 0), b(worker, 1);
  a.join();
  b.join();
  for (const auto& o : out) EXPECT_EQ(o.type(), CV_8UC1);
}

TEST(EnhanceChain, ShippedConfigIsTheDefaultChain) {
  auto path = std::filesystem::path(__FILE__).parent_path() / "../../../config/enhance.json";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  json config = json::parse(in);  // a build config: the chain sits under "enhance"
  EnhanceChain c = EnhanceChain::FromJson(config.at("enhance"), path.string());
  EXPECT_EQ(c.Describe(), EnhanceChain::Default().Describe());
}

TEST(EnhanceChain, EmptyChainIsIdentity) {
  cv::Mat img = testing::ToType(testing::Texture({40, 30}, 40), CV_16U);
  EXPECT_EQ(cv::norm(EnhanceChain().Apply(img), img, cv::NORM_INF), 0);
  EXPECT_EQ(EnhanceChain().Describe(), "none");
}

}  // namespace
}  // namespace seamap
