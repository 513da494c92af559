#include "core/mosaic/frame_pipeline.h"

#include <cmath>
#include <sstream>

#include "core/image/image_header.h"
#include "core/mosaic/mosaic_plan.h"
#include "core/util/error.h"

namespace seamap {
namespace {

const char* kNoSeabed = "the camera does not see the seabed in this attitude";

}  // namespace

std::optional<std::string> TooLargeToPaint(const SeabedProjection& projection, const VehiclePose& pose, int channels,
                                           double max_paint_bytes) {
  const auto outline = projection.Outline(pose);
  if (!outline) return std::nullopt;
  const auto& box = outline->box;
  const double bytes =
      FramePaintBytes(static_cast<double>(box[2]), static_cast<double>(box[3]), projection.tile_size(), channels);
  if (bytes <= max_paint_bytes) return std::nullopt;
  std::ostringstream s;
  s.precision(0);
  s << std::fixed << "frame too large for the map: at altitude " << pose.altitude_m << " m it covers " << box[2] << "x"
    << box[3] << " map pixels and would need " << bytes / (1 << 20) << " MB of tiles, over the limit of "
    << max_paint_bytes / (1 << 20) << " MB (memory_cap_mb, or 8 times a frame at the survey's median altitude)";
  return s.str();
}

std::optional<std::string> TooSteep(const CameraModel& camera, const VehiclePose& pose,
                                    const std::array<LocalXY, 4>& corners, double max_ratio) {
  // Nearly horizontal views smear one frame over a huge area: refuse them.
  const double nadir_area =
      (camera.width * pose.altitude_m / camera.fx) * (camera.height * pose.altitude_m / camera.fy);
  double area = 0;  // shoelace formula over the corners in local metres
  for (int i = 0; i < 4; ++i) {
    const LocalXY& a = corners[i];
    const LocalXY& b = corners[(i + 1) % 4];
    area += a.east * b.north - b.east * a.north;
  }
  area = std::fabs(area) / 2;
  if (area <= max_ratio * nadir_area) return std::nullopt;
  std::ostringstream s;
  s << "footprint is " << std::lround(area / nadir_area) << "x the nadir footprint (limit " << max_ratio
    << "): attitude too steep";
  return s.str();
}

FramePipeline::FramePipeline(const FrameWarper* warper, ThreadPool* pool, FramePipelineOptions options, Deliver deliver)
    : warper_(warper), pool_(pool), options_(std::move(options)), deliver_(std::move(deliver)) {}

FramePipeline::~FramePipeline() {
  // Jobs in flight use this object: let them finish (errors were already reported).
  for (auto& f : loading_)
    if (f.valid()) f.wait();
  for (auto& q : queued_)
    if (q->warp.valid()) q->warp.wait();
}

bool UsesDecoded(const ImageHeader& header, const cv::Mat& decoded, int channels) {
  if (decoded.empty() || decoded.cols != header.width || decoded.rows != header.height) return false;
  // libjpeg-turbo decodes a JPEG the same for both, but to gray it gives the
  // luma where cv::imread gives colour (then converted by other weights).
  return header.format != "jpeg" || decoded.channels() == channels;
}

FramePipeline::Loaded FramePipeline::Load(const FrameSpec& spec, const cv::Mat& decoded) const {
  Loaded l;
  PlacedFrame& p = l.placed;
  p.spec = spec;
  const SeabedProjection& projection = warper_->projection();
  const auto corners = projection.GroundCorners(spec.pose);
  if (corners) p.footprint = projection.Footprint(spec.pose);
  auto reject = [&](std::string field, std::string reason) {
    p.reject_field = std::move(field);
    p.reject_reason = std::move(reason);
    return std::move(l);
  };
  const CameraModel& camera = projection.camera();
  auto wrong_size = [&](int64_t width, int64_t height) {
    std::ostringstream s;
    s << "image is " << width << "x" << height << ", the camera model expects " << camera.width << "x" << camera.height;
    return reject("image", s.str());
  };
  // The header first: a frame of the wrong size is refused before it is decoded.
  std::string problem;
  const auto header = ReadImageHeader(spec.image_path, &problem);
  if (!header) return reject("image", problem);
  if (header->width > 0 && header->pixels() <= options_.max_image_pixels &&
      (header->width != camera.width || header->height != camera.height))
    return wrong_size(header->width, header->height);
  std::optional<FrameImage> image;
  if (!TooLargeToDecode(*header, options_.max_image_pixels) && UsesDecoded(*header, decoded, options_.channels))
    image = FrameImage::FromMat(decoded, options_.channels, options_.sixteen_bit_white);
  else
    image = FrameImage::Read(spec.image_path, *header, options_.channels, options_.sixteen_bit_white, &problem,
                             options_.max_image_pixels);
  if (!image) return reject("image", problem);
  if (image->width() != camera.width || image->height() != camera.height)
    return wrong_size(image->width(), image->height());
  if (!corners) return reject("pitch_deg/roll_deg", kNoSeabed);
  if (auto steep = TooSteep(camera, spec.pose, *corners, options_.max_footprint_ratio))
    return reject("pitch_deg/roll_deg", *steep);
  if (!projection.SeesSeabed(spec.pose)) return reject("pitch_deg/roll_deg", kNoSeabed);
  if (auto too_large = TooLargeToPaint(projection, spec.pose, options_.channels, options_.max_paint_bytes))
    return reject("altitude_m", *too_large);
  l.image = std::move(*image);
  if (options_.preprocess) {  // the enhancement chain works on whole frames
    try {
      l.image = FrameImage::FromMat(options_.preprocess(l.image.Full()), options_.channels, options_.sixteen_bit_white);
    } catch (const InputError& e) {
      l.image = FrameImage();
      return reject("image", e.detail());
    }
  }
  return l;
}

void FramePipeline::Push(const FrameSpec& spec, const cv::Mat& decoded) {
  loading_.push_back(pool_->Submit([this, spec, decoded] { return Load(spec, decoded); }));
  // Keep the pool busy: take finished loads (starting their neighbours'
  // warps) and deliver finished warps as they come; block only when the
  // pipeline is full, on its oldest frame.
  while (true) {
    while (!loading_.empty() && IsReady(loading_.front())) TakeLoaded();
    DeliverReady(false);
    if (loading_.size() + queued_.size() <= options_.depth) return;
    if (!queued_.empty() && queued_.front()->warp.valid())
      DeliverReady(true);
    else if (!loading_.empty())
      TakeLoaded();
    else
      return;  // only the last usable frame waits, for its next neighbour
  }
}

void FramePipeline::Finish() {
  while (!loading_.empty()) TakeLoaded();
  if (awaiting_next_) {
    StartWarp(awaiting_next_);  // the last usable frame has no next neighbour
    awaiting_next_.reset();
  }
  while (!queued_.empty()) DeliverReady(true);
}

void FramePipeline::TakeLoaded() {
  auto q = std::make_shared<Queued>();
  q->loaded = loading_.front().get();
  loading_.pop_front();
  if (q->Usable()) {
    if (awaiting_next_) {
      awaiting_next_->neighbours.push_back(q->loaded.placed.spec.pose);
      q->neighbours.push_back(awaiting_next_->loaded.placed.spec.pose);
      StartWarp(awaiting_next_);
    }
    awaiting_next_ = q;
  }
  queued_.push_back(std::move(q));
}

void FramePipeline::StartWarp(const std::shared_ptr<Queued>& q) {
  // The job owns q until it is done; nothing else touches q's frame meanwhile.
  q->warp = pool_->Submit([this, q]() -> std::optional<WarpedFrame> {
    FrameImage& image = q->loaded.image;
    try {
      return warper_->Warp([&image](int first, int last) -> const cv::Mat& { return image.Rows(first, last); },
                           q->loaded.placed.spec.pose, q->neighbours);
    } catch (const InputError& e) {  // JPEG data broken past its header: this frame is rejected
      q->problem = e.detail();
      return std::nullopt;
    }
  });
}

void FramePipeline::DeliverReady(bool wait_for_one) {
  while (!queued_.empty()) {
    Queued& q = *queued_.front();
    const bool usable = q.Usable();
    if (usable && !q.warp.valid()) return;  // waits for its next neighbour
    if (usable && !wait_for_one && !IsReady(q.warp)) return;
    wait_for_one = false;
    PlacedFrame p = std::move(q.loaded.placed);
    p.handover = usable;
    if (usable) {
      p.warped = q.warp.get();
      q.loaded.image.Release();
      if (!p.warped) {
        p.reject_field = q.problem.empty() ? "pitch_deg/roll_deg" : "image";
        p.reject_reason = q.problem.empty() ? kNoSeabed : q.problem;
      }
    }
    queued_.pop_front();
    deliver_(std::move(p));
  }
}

}  // namespace seamap
