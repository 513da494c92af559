#include "core/detect/yolo_decoder.h"

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace seamap {
namespace {

cv::Mat Blob(int a, int b) {
  int sizes[] = {1, a, b};
  return cv::Mat(3, sizes, CV_32F, cv::Scalar(0));
}

TEST(YoloDecoder, RecognisesV5AndV8ByTheClassCount) {
  EXPECT_EQ(RecogniseYoloLayout({1, 25200, 7}, 2, "m", "s"), YoloLayout::kV5);
  EXPECT_EQ(RecogniseYoloLayout({1, 6, 8400}, 2, "m", "s"), YoloLayout::kV8);
}

TEST(YoloDecoder, ErrorsQuoteShapeClassCountAndNameSource) {
  const auto message = [](std::vector<int> shape, int c) {
    try {
      RecogniseYoloLayout(shape, c, "model.onnx", "--classes names.txt");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string rank = message({1, 10}, 2);
  EXPECT_NE(rank.find("[1, 10]"), std::string::npos) << rank;
  EXPECT_NE(rank.find("model.onnx"), std::string::npos) << rank;
  // A transposed v8 [1, N, 4+C] with C names known fits neither.
  const std::string transposed = message({1, 8400, 6}, 2);
  EXPECT_NE(transposed.find("[1, 8400, 6]"), std::string::npos) << transposed;
  EXPECT_NE(transposed.find("2 classes"), std::string::npos) << transposed;
  EXPECT_NE(transposed.find("--classes names.txt"), std::string::npos) << transposed;
  // One name too many: the count no longer fits.
  EXPECT_NE(message({1, 6, 8400}, 3).find("fits neither"), std::string::npos);
  EXPECT_NE(message({2, 6, 8400}, 2).find("[2, 6, 8400]"), std::string::npos);
}

TEST(YoloDecoder, DecodesPlantedV5Rows) {
  cv::Mat out = Blob(3, 7);
  float* d = out.ptr<float>();
  const float rows[3][7] = {
      {100, 50, 20, 10, 0.9f, 0.1f, 0.8f}, {10, 10, 4, 4, 0.3f, 0.9f, 0.9f}, {300, 200, 40, 60, 1, 0.6f, 0.5f}};
  std::copy(&rows[0][0], &rows[0][0] + 21, d);
  const auto boxes = DecodeYolo(out, YoloLayout::kV5, 2, 0.4f);
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_EQ(boxes[0].class_id, 1);
  EXPECT_NEAR(boxes[0].score, 0.72f, 1e-6);
  EXPECT_FLOAT_EQ(boxes[0].x0, 90);
  EXPECT_FLOAT_EQ(boxes[0].y1, 55);
  EXPECT_EQ(boxes[1].class_id, 0);
  EXPECT_FLOAT_EQ(boxes[1].y0, 170);
}

TEST(YoloDecoder, DecodesPlantedV8Columns) {
  cv::Mat out = Blob(6, 4);
  float* d = out.ptr<float>();
  // column 2: cx 200, cy 100, w 30, h 20, p0 0.2, p1 0.95; others empty.
  d[0 * 4 + 2] = 200, d[1 * 4 + 2] = 100, d[2 * 4 + 2] = 30, d[3 * 4 + 2] = 20, d[4 * 4 + 2] = 0.2f,
            d[5 * 4 + 2] = 0.95f;
  const auto boxes = DecodeYolo(out, YoloLayout::kV8, 2, 0.4f);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].class_id, 1);
  EXPECT_FLOAT_EQ(boxes[0].score, 0.95f);
  EXPECT_FLOAT_EQ(boxes[0].x0, 185);
  EXPECT_FLOAT_EQ(boxes[0].x1, 215);
  EXPECT_FLOAT_EQ(boxes[0].y0, 90);
}

TEST(YoloDecoder, NmsIsPerClass) {
  std::vector<YoloBox> boxes = {
      {0, 0, 10, 10, 0.9f, 0}, {1, 0, 11, 10, 0.8f, 0}, {1, 0, 11, 10, 0.7f, 1}, {50, 50, 60, 60, 0.6f, 0}};
  const auto kept = NmsPerClass(boxes, 0.5f);
  ASSERT_EQ(kept.size(), 3u);  // the 0.8 box of class 0 goes; class 1 keeps its own
  EXPECT_FLOAT_EQ(kept[0].score, 0.9f);
  EXPECT_FLOAT_EQ(kept[1].score, 0.6f);
  EXPECT_EQ(kept[2].class_id, 1);
}

TEST(YoloDecoder, LetterboxSquareHasNoPads) {
  const Letterbox lb = MakeLetterbox({768, 768}, {640, 640});
  EXPECT_NEAR(lb.scale, 640.0 / 768, 1e-12);
  EXPECT_EQ(lb.pad_x, 0);
  EXPECT_EQ(lb.pad_y, 0);
  const YoloBox back = UndoLetterbox({100, 200, 300, 400, 1, 0}, lb);
  EXPECT_NEAR(back.x0, 120, 1e-3);
  EXPECT_NEAR(back.y1, 480, 1e-3);
}

TEST(YoloDecoder, LetterboxWideInputPadsLeftAndRight) {
  // A 768 window into 640 x 384: scale 0.5, 384 x 384 image, 128 px pads left and right.
  const Letterbox lb = MakeLetterbox({768, 768}, {640, 384});
  EXPECT_NEAR(lb.scale, 0.5, 1e-12);
  EXPECT_EQ(lb.pad_x, 128);
  EXPECT_EQ(lb.pad_y, 0);
  cv::Mat img(768, 768, CV_8UC3, cv::Scalar(10, 20, 30));
  cv::Mat boxed = ApplyLetterbox(img, lb);
  EXPECT_EQ(boxed.size(), cv::Size(640, 384));
  EXPECT_EQ(boxed.at<cv::Vec3b>(10, 5), cv::Vec3b(114, 114, 114));
  EXPECT_EQ(boxed.at<cv::Vec3b>(10, 200), cv::Vec3b(10, 20, 30));
  const YoloBox back = UndoLetterbox({128 + 50, 20, 128 + 60, 40, 1, 0}, lb);
  EXPECT_NEAR(back.x0, 100, 1e-3);
  EXPECT_NEAR(back.x1, 120, 1e-3);
  EXPECT_NEAR(back.y1, 80, 1e-3);
  // Boxes in the pad are clipped to the image.
  EXPECT_NEAR(UndoLetterbox({0, 0, 10, 10, 1, 0}, lb).x1, 0, 1e-6);
}

}  // namespace
}  // namespace seamap
