#pragma once
// The frames on their way to the map. Each frame is loaded and checked
// (image readable and of the camera's size, attitude that sees the seabed,
// footprint not too stretched), passed through the enhancement chain when
// there is one, and warped — on the thread pool, several frames at a time —
// and handed back in acquisition order. A frame's warp starts once the next
// usable frame is loaded: the two hand pixels over to each other
// (blend_rule.h). JPEG frames stay compressed until the warp knows which rows
// it samples (FrameImage).
#include <array>
#include <deque>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/geo/lat_lon.h"
#include "core/mosaic/frame_image.h"
#include "core/mosaic/frame_warper.h"
#include "core/nav/frame_list.h"
#include "core/util/thread_pool.h"

namespace seamap {

// A frame that went through the pipeline: warped, or rejected with a reason.
struct PlacedFrame {
  FrameSpec spec;
  std::optional<WarpedFrame> warped;               // nullopt when rejected
  std::optional<std::array<LatLon, 4>> footprint;  // where its corners land, when they do
  std::string reject_field, reject_reason;
  bool handover = false;  // it reached the warp: its pose was its neighbours' handover partner
};

struct FramePipelineOptions {
  int channels = 1;                                   // of the map: frames are converted to it
  int sixteen_bit_white = 65535;                      // 16-bit frames are scaled to 8 bits by 255/white
  double max_footprint_ratio = 25;                    // see TooSteep
  int64_t max_image_pixels = kDefaultMaxImagePixels;  // larger frames are refused unread
  // Frames whose painting (FramePaintBytes) would take more are refused: a
  // frame far above the survey covers thousands of tiles at the base zoom.
  double max_paint_bytes = std::numeric_limits<double>::infinity();
  size_t depth = 8;  // frames loading or waiting before Push blocks
  // Applied to every 8-bit frame before warping (the enhancement chain); thread-safe.
  std::function<cv::Mat(const cv::Mat&)> preprocess;
};

// Why a frame's attitude is too steep to map: its footprint (corners in
// local metres) is over `max_ratio` times the nadir one; nullopt when it is not.
std::optional<std::string> TooSteep(const CameraModel& camera, const VehiclePose& pose,
                                    const std::array<LocalXY, 4>& corners, double max_ratio);

// Why painting a frame in this pose would take more than max_paint_bytes
// (FramePaintBytes of its box at the base zoom); nullopt when it would not.
std::optional<std::string> TooLargeToPaint(const SeabedProjection& projection, const VehiclePose& pose, int channels,
                                           double max_paint_bytes);

// Whether a photo with this header, decoded whole by cv::imread as
// `decoded`, gives the pixels FrameImage::Read would for a map of `channels`:
// not for a JPEG whose colour a gray map takes as libjpeg's luma (FrameImage
// decodes JPEGs itself, by rows), nor for an empty or mis-sized image.
bool UsesDecoded(const ImageHeader& header, const cv::Mat& decoded, int channels);

class FramePipeline {
 public:
  using Deliver = std::function<void(PlacedFrame)>;
  // deliver: called on the caller's thread (in Push and Finish), in acquisition order.
  FramePipeline(const FrameWarper* warper, ThreadPool* pool, FramePipelineOptions options, Deliver deliver);
  ~FramePipeline();  // waits for the jobs in flight

  // Queues a frame (frames come in acquisition order) and delivers those
  // ready; blocks while the pipeline is full. `decoded`: the photo as
  // cv::imread decodes it unchanged, read already by the caller (the online
  // navigation filter): used instead of reading the file again where it
  // gives the very pixels the pipeline's own read would (UsesDecoded).
  void Push(const FrameSpec& frame, const cv::Mat& decoded = cv::Mat());
  // Delivers every frame still in the pipeline.
  void Finish();

 private:
  struct Loaded {
    PlacedFrame placed;
    FrameImage image;  // until it is warped; empty when rejected at loading
  };
  // A loaded frame waiting for its turn. A usable frame's warp starts once
  // the next usable frame is known (its neighbour for the handover).
  struct Queued {
    Loaded loaded;
    std::vector<VehiclePose> neighbours;
    std::string problem;  // set by the warp job when the image cannot be decoded
    std::future<std::optional<WarpedFrame>> warp;
    bool Usable() const { return !loaded.image.empty(); }
  };

  Loaded Load(const FrameSpec& spec, const cv::Mat& decoded) const;
  void TakeLoaded();  // oldest load -> queued_ (waits for it); starts the previous usable frame's warp
  void StartWarp(const std::shared_ptr<Queued>& q);
  // Delivers queued frames, oldest first, while their warps are done; with
  // wait_for_one it first waits for the oldest.
  void DeliverReady(bool wait_for_one);

  const FrameWarper* warper_;
  ThreadPool* pool_;
  FramePipelineOptions options_;
  Deliver deliver_;
  std::deque<std::future<Loaded>> loading_;
  std::deque<std::shared_ptr<Queued>> queued_;  // loaded, in acquisition order
  std::shared_ptr<Queued> awaiting_next_;       // last usable frame, warp not started yet
};

}  // namespace seamap
