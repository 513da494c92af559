// Issue 33, rows 3 and 5: what a broken or hostile model outputs never
// reaches the map: inf/NaN boxes are dropped and counted, a window's boxes
// are capped, and a min score that is no probability is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/detect/merge.h"
#include "core/detect/yolo_decoder.h"
#include "core/detect/yolo_model.h"
#include "core/util/error.h"
#include "tests/testing/onnx_builder.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// A YOLOv8 output [1, 6, N] (two classes) from rows {cx, cy, w, h, p0, p1}.
cv::Mat V8Blob(const std::vector<std::vector<float>>& rows) {
  const int sizes[] = {1, 6, static_cast<int>(rows.size())};
  cv::Mat out(3, sizes, CV_32F, cv::Scalar(0));
  const std::vector<float> values = testing::V8Values(rows);
  std::copy(values.begin(), values.end(), out.ptr<float>());
  return out;
}

TEST(HostileDetect, NonFiniteBoxesAreDroppedAndCounted) {
  const cv::Mat out = V8Blob({{20, 24, 10, 8, 0.1f, 0.8f},
                              {kInf, 24, 10, 8, 0.9f, 0.1f},
                              {20, kNaN, 10, 8, 0.9f, 0.1f},
                              {20, 24, kInf, 8, 0.9f, 0.1f},
                              {20, 24, 10, 8, kInf, 0.1f},
                              {20, 24, 10, 8, kNaN, 0.1f},
                              {-kInf, -kInf, kInf, kInf, 0.9f, 0.1f}});
  YoloDropped dropped;
  const auto boxes = DecodeYolo(out, YoloLayout::kV8, 2, 0.4f, &dropped);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_FLOAT_EQ(boxes[0].x0, 15);
  EXPECT_EQ(dropped.non_finite, 6);
  EXPECT_EQ(dropped.capped, 0);
}

TEST(HostileDetect, WindowProposalsAreCappedToTheBestScores) {
  // 5000 boxes on a grid, scores rising with the index: the best 3000 go into
  // NMS (no two overlap), the best 300 come out.
  std::vector<std::vector<float>> rows;
  for (int i = 0; i < 5000; ++i)
    rows.push_back({4.0f + (i % 100) * 8, 4.0f + (i / 100) * 8, 4, 4, 0.5f + 0.4f * i / 5000, 0});
  YoloDropped dropped;
  const auto candidates = DecodeYolo(V8Blob(rows), YoloLayout::kV8, 2, 0.4f, &dropped);
  EXPECT_EQ(candidates.size(), static_cast<size_t>(kMaxYoloCandidates));
  EXPECT_EQ(dropped.capped, 5000 - kMaxYoloCandidates);
  for (const YoloBox& b : candidates) EXPECT_GE(b.score, 0.5f + 0.4f * 1999 / 5000);
  const auto kept = KeepBestBoxes(NmsPerClass(candidates, 0.5f), kMaxYoloBoxes, &dropped);
  EXPECT_EQ(kept.size(), static_cast<size_t>(kMaxYoloBoxes));
  EXPECT_EQ(dropped.capped, 5000 - kMaxYoloBoxes);
  for (const YoloBox& b : kept) EXPECT_GE(b.score, 0.5f + 0.4f * 4699 / 5000);
  // Under the cap nothing changes, order included.
  const auto few = DecodeYolo(V8Blob({rows[0], rows[1]}), YoloLayout::kV8, 2, 0.4f);
  EXPECT_EQ(KeepBestBoxes(few, 300, nullptr).size(), 2u);
}

TEST(HostileDetect, MergeOfWindowSizedBoxesStaysBounded) {
  // 1000 same-class boxes, each ~5 km a side at zoom 14: with 5 m cells each
  // would fill ~10^6 cells; the merge must still end with one object.
  std::vector<RawDetection> raw;
  for (int i = 0; i < 1000; ++i) {
    RawDetection r;
    r.window = {14, 14194, 6020};
    r.index = i;
    r.score = 0.5f + i * 1e-4f;
    const double x = 14194.0 * 256 + (i % 7), y = 6020.0 * 256 + (i % 5);
    r.box = {x, y, x + 700, y + 700};
    raw.push_back(r);
  }
  const auto objects = MergeDetections(raw, {"tyre"}, 256, LocalFrame(LatLon{43.1, 131.9}));
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_NEAR(objects[0].score, 0.5f + 999 * 1e-4f, 1e-6);
}

TEST(HostileDetect, MinScoreInTheMetadataMustBeAProbability) {
  testing::TempDir dir;
  const auto model = [&](const std::string& min_score) {
    auto spec = testing::PlantedYoloModel({1, 6, 1}, {20, 24, 10, 8, 0.1f, 0.8f},
                                          {{"names", R"(["tyre", "crate"])"}, {"seamap.min_score", min_score}});
    return testing::WriteFile(dir / "m.onnx", testing::OnnxModelBytes(spec)).string();
  };
  EXPECT_FLOAT_EQ(YoloModel::Inspect(model("0.001"), "")->min_score, 0.001f);
  EXPECT_FLOAT_EQ(YoloModel::Inspect(model("1"), "")->min_score, 1.0f);
  for (const std::string& bad :
       std::vector<std::string>{"1e-300", "0", "0.0009", "1.5", "nan", std::string(10 << 20, '7')}) {
    try {
      YoloModel::Inspect(model(bad), "");
      ADD_FAILURE() << "min_score " << bad.substr(0, 20) << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "seamap.min_score");
      EXPECT_NE(std::string(e.what()).find("m.onnx"), std::string::npos);
      EXPECT_LT(std::string(e.what()).size(), 300u) << "the 10 MB value is echoed";
    }
  }
}

}  // namespace
}  // namespace seamap
