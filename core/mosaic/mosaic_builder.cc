#include "core/mosaic/mosaic_builder.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/camera/frame_projector.h"
#include "core/mosaic/frame_tail.h"
#include "core/util/error.h"

namespace seamap {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Rounds towards minus infinity (global pixels may lie left of or above the map).
int64_t FloorDiv(int64_t v, int64_t d) {
  return v >= 0 ? v / d : -((-v + d - 1) / d);
}

}  // namespace

namespace {
rusage SelfUsage() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage;
}
}  // namespace

int64_t PeakRssBytes() {
  return static_cast<int64_t>(SelfUsage().ru_maxrss) * 1024;
}

double ProcessCpuSeconds() {
  const rusage usage = SelfUsage();
  auto seconds = [](const timeval& t) { return t.tv_sec + t.tv_usec / 1e6; };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

MosaicPlan PlanMosaic(const BuildConfig& config, const CameraModel& camera, const LocalFrame& frame,
                      const std::vector<FrameSpec>& frames, int channels) {
  MosaicPlan plan;
  plan.channels = channels;
  std::vector<double> altitudes, easts, norths;
  double max_alt = 0;
  for (const auto& f : frames) {
    altitudes.push_back(f.pose.altitude_m);
    easts.push_back(f.pose.east_m);
    norths.push_back(f.pose.north_m);
    max_alt = std::max(max_alt, f.pose.altitude_m);
  }
  const double median_alt = frames.empty() ? 2.0 : Median(altitudes);
  plan.gsd_m = GroundSampleDistance(camera, median_alt);
  LatLon centre = frame.ToLatLon({Median(easts), Median(norths)});
  plan.latitude = centre.lat;
  plan.base_zoom =
      config.base_zoom ? *config.base_zoom : ZoomForGroundSampleDistance(plan.gsd_m, plan.latitude, config.tile_size);
  plan.base_zoom = std::clamp(plan.base_zoom, 0, 30);
  if (config.min_zoom) {
    plan.min_zoom = std::min(*config.min_zoom, plan.base_zoom);
  } else {
    // The zoom at which the whole survey (positions plus the largest
    // footprint radius) spans at most one tile.
    double extent = 0;
    if (!frames.empty()) {
      auto [e0, e1] = std::minmax_element(easts.begin(), easts.end());
      auto [n0, n1] = std::minmax_element(norths.begin(), norths.end());
      const double radius = max_alt * std::hypot(camera.width / camera.fx, camera.height / camera.fy) / 2;
      extent = std::max(*e1 - *e0, *n1 - *n0) + 2 * radius;
    }
    int z = plan.base_zoom;
    while (z > 0 && extent > MetersPerPixel(plan.latitude, z, config.tile_size) * config.tile_size) --z;
    plan.min_zoom = z;
  }
  return plan;
}

MosaicBuilder::MosaicBuilder(const BuildConfig& config, const CameraModel& camera, const LocalFrame& frame,
                             const MosaicPlan& plan, TileStore* store, BuildHooks hooks)
    : config_(config),
      camera_(camera),
      frame_(frame),
      plan_(plan),
      store_(store),
      hooks_(std::move(hooks)),
      warper_(camera, frame, plan.base_zoom, config.tile_size, plan.channels, config.feather_power,
              config.blend_all_overlaps ? 0.0 : config.seam_band),
      pool_(std::make_unique<ThreadPool>(config.threads)),
      start_(std::chrono::steady_clock::now()),
      last_flush_(start_),
      start_cpu_(ProcessCpuSeconds()) {
  // We parallelise across frames and tiles; OpenCV's own threads inside each
  // call would only compete with ours on a small on-board CPU.
  cv::setNumThreads(1);
  // Up to eight frames in flight per pool thread: frames finish out of order
  // and tile encodes come in bursts, and with two per thread plus four the
  // cores sat idle for a fifth of a build. A queued frame may hold its
  // decoded image (not JPEG, or enhanced), so the depth also stays within a
  // quarter of the memory cap (but not below two per thread plus four).
  const size_t frame_bytes = static_cast<size_t>(camera_.width) * camera_.height * plan_.channels + 1;
  const size_t by_memory = (static_cast<size_t>(config_.memory_cap_mb) << 20) / 4 / frame_bytes;
  const size_t threads = static_cast<size_t>(pool_->size());
  pipeline_depth_ = std::clamp(by_memory, 2 * threads + 4, 8 * threads);
  writer_ = std::make_unique<TileWriter>(store, pool_.get(), config.encoding, hooks_.on_tile_written);
  const size_t cap = static_cast<size_t>(config.memory_cap_mb) << 20;
  pyramid_ = std::make_unique<OverviewPyramid>(writer_.get(), config.tile_size, plan.channels, plan.min_zoom,
                                               plan.base_zoom, cap / 4);
  // Continuing a mission (--append): new frames and track points follow the
  // stored ones instead of overwriting them.
  for (const FrameRecord& f : store_->Frames()) frame_id_offset_ = std::max(frame_id_offset_, f.id + 1);
  for (const TrackPoint& p : store_->Track()) track_seq_ = std::max(track_seq_, p.seq + 1);
  WriteMetadata(false);
  store_->Flush();
}

MosaicBuilder::~MosaicBuilder() {
  // Let queued work drain before members go away (errors were already
  // reported), and stop the pool while the writer its jobs use still exists.
  for (auto& f : loading_)
    if (f.valid()) f.wait();
  for (auto& q : queued_)
    if (q->warp.valid()) q->warp.wait();
  pool_.reset();
}

void MosaicBuilder::Foresee(const std::vector<FrameSpec>& frames) {
  foreseen_.clear();
  if (config_.lookahead_frames <= 0) return;
  // Tiles then stay open until the next survey line has painted them, so
  // side-edge tails can wait to see whether it covers them.
  defer_tails_ = config_.defer_edge_tails;
  // Outlines on the pool (each is a few dozen projections), tiles in order.
  using Seen = std::optional<FrameWarper::MapOutline>;
  std::vector<std::future<Seen>> outlines;
  outlines.reserve(frames.size());
  // Frames Load will refuse (too steep: their box can span thousands of
  // tiles) are left out.
  for (const FrameSpec& f : frames)
    outlines.push_back(pool_->Submit([this, &f]() -> Seen {
      const auto corners = warper_.GroundCorners(f.pose);
      if (!corners || TooSteep(f.pose, *corners)) return std::nullopt;
      return warper_.Outline(f.pose);
    }));
  foreseen_frames_.clear();
  for (size_t i = 0; i < frames.size(); ++i) {
    const Seen outline = outlines[i].get();
    if (!outline) continue;
    const int index = frames[i].index;
    if (index >= static_cast<int>(foreseen_frames_.size())) foreseen_frames_.resize(index + 1);
    const auto& b = outline->box;
    foreseen_frames_[index].emplace(ForeseenFrame{MapFootprint(outline->corners), TilesUnder(b[0], b[1], b[2], b[3])});
    const auto& t = foreseen_frames_[index]->tiles;
    for (int64_t ty = t[1]; ty <= t[3]; ++ty)
      for (int64_t tx = t[0]; tx <= t[2]; ++tx)
        foreseen_[TileId{plan_.base_zoom, static_cast<int>(tx), static_cast<int>(ty)}].push_back(index);
  }
  for (auto& [id, indices] : foreseen_) std::sort(indices.begin(), indices.end());
}

bool MosaicBuilder::OverSoon(const TileId& id) const {
  auto it = foreseen_.find(id);
  if (it == foreseen_.end()) return false;
  auto next = std::upper_bound(it->second.begin(), it->second.end(), last_index_);
  return next != it->second.end() && *next <= last_index_ + config_.lookahead_frames;
}

std::array<int64_t, 4> MosaicBuilder::TilesUnder(int64_t x0, int64_t y0, int64_t width, int64_t height) const {
  const int64_t ts = config_.tile_size;
  // Tiles that exist at this zoom (frames may reach past the antimeridian or
  // the Mercator limits; those parts are not mapped).
  const int64_t last = (int64_t{1} << plan_.base_zoom) - 1;
  return {std::max<int64_t>(0, FloorDiv(x0, ts)), std::max<int64_t>(0, FloorDiv(y0, ts)),
          std::min(last, FloorDiv(x0 + width - 1, ts)), std::min(last, FloorDiv(y0 + height - 1, ts))};
}

void MosaicBuilder::Push(const FrameSpec& spec) {
  loading_.push_back(pool_->Submit([this, spec] { return Load(spec); }));
  // Keep the pool busy: take finished loads (starting their neighbours'
  // warps) and blend finished warps as they come; block only when the
  // pipeline is full (pipeline_depth_), on its oldest frame.
  while (true) {
    while (!loading_.empty() && IsReady(loading_.front())) TakeLoaded();
    ConsumeReady(false);
    if (loading_.size() + queued_.size() <= pipeline_depth_) return;
    if (!queued_.empty() && queued_.front()->warp.valid())
      ConsumeReady(true);
    else if (!loading_.empty())
      TakeLoaded();
    else
      return;  // only the last usable frame waits, for its next neighbour
  }
}

void MosaicBuilder::TakeLoaded() {
  auto q = std::make_shared<Queued>();
  q->prepared = loading_.front().get();
  loading_.pop_front();
  if (q->Usable()) {
    if (awaiting_next_) {
      awaiting_next_->neighbours.push_back(q->prepared.spec.pose);
      q->neighbours.push_back(awaiting_next_->prepared.spec.pose);
      StartWarp(awaiting_next_);
    }
    awaiting_next_ = q;
  }
  queued_.push_back(std::move(q));
}

void MosaicBuilder::StartWarp(const std::shared_ptr<Queued>& q) {
  // The job owns q until it is done; nothing else touches q's frame meanwhile.
  q->warp = pool_->Submit([this, q]() -> std::optional<WarpedFrame> {
    FrameImage& image = q->prepared.image;
    const unsigned tail_sides = defer_tails_ && image.DecodesByRows() ? TailSides(q->prepared.spec) : 0;
    try {
      return warper_.Warp([&image](int first, int last) -> const cv::Mat& { return image.Rows(first, last); },
                          q->prepared.spec.pose, q->neighbours, tail_sides ? &q->tail : nullptr, tail_sides);
    } catch (const InputError& e) {  // JPEG data broken past its header: this frame is rejected
      q->problem = e.detail();
      return std::nullopt;
    }
  });
}

void MosaicBuilder::ConsumeReady(bool wait_for_one) {
  while (!queued_.empty()) {
    Queued& q = *queued_.front();
    const bool usable = q.Usable();
    if (usable && !q.warp.valid()) return;  // waits for its next neighbour
    if (usable && !wait_for_one && !IsReady(q.warp)) return;
    wait_for_one = false;
    std::optional<WarpedFrame> warped;
    if (usable) warped = q.warp.get();  // before touching the frame the job reads
    Prepared p = std::move(q.prepared);
    if (usable) {
      p.warped = std::move(warped);
      if (p.warped && !q.tail.empty()) {
        p.tail = std::move(q.tail);
        p.image.ReleasePixels();  // the compressed frame stays for its tail
      } else {
        p.image.Release();
      }
      if (!p.warped && !q.problem.empty()) {
        p.reject_field = "image";
        p.reject_reason = q.problem;
      } else if (!p.warped) {
        p.reject_field = "pitch_deg/roll_deg";
        p.reject_reason = "the camera does not see the seabed in this attitude";
      }
    }
    queued_.pop_front();
    Consume(std::move(p));
  }
}

void MosaicBuilder::Reject(const Rejection& rejection) {
  ++stats_.frames_seen;
  stats_.rejections.push_back(rejection);
}

std::optional<std::string> MosaicBuilder::TooSteep(const VehiclePose& pose,
                                                   const std::array<LocalXY, 4>& corners) const {
  // Nearly horizontal views smear one frame over a huge area: refuse them.
  const double nadir_area =
      (camera_.width * pose.altitude_m / camera_.fx) * (camera_.height * pose.altitude_m / camera_.fy);
  double area = 0;  // shoelace formula over the corners in local metres
  for (int i = 0; i < 4; ++i) {
    const LocalXY& a = corners[i];
    const LocalXY& b = corners[(i + 1) % 4];
    area += a.east * b.north - b.east * a.north;
  }
  area = std::fabs(area) / 2;
  if (area <= config_.max_footprint_ratio * nadir_area) return std::nullopt;
  std::ostringstream s;
  s << "footprint is " << std::lround(area / nadir_area) << "x the nadir footprint (limit "
    << config_.max_footprint_ratio << "): attitude too steep";
  return s.str();
}

MosaicBuilder::Prepared MosaicBuilder::Load(const FrameSpec& spec) const {
  Prepared p;
  p.spec = spec;
  const auto corners = warper_.GroundCorners(spec.pose);
  if (corners) {
    p.footprint.emplace();
    for (int i = 0; i < 4; ++i) (*p.footprint)[i] = frame_.ToLatLon((*corners)[i]);
  }
  auto reject = [&](std::string field, std::string reason) {
    p.reject_field = std::move(field);
    p.reject_reason = std::move(reason);
    return p;
  };
  std::string problem;
  auto image = FrameImage::Read(spec.image_path, plan_.channels, config_.sixteen_bit_white, &problem);
  if (!image) return reject("image", problem);
  if (image->width() != camera_.width || image->height() != camera_.height) {
    std::ostringstream s;
    s << "image is " << image->width() << "x" << image->height() << ", the camera model expects " << camera_.width
      << "x" << camera_.height;
    return reject("image", s.str());
  }
  if (!p.footprint) return reject("pitch_deg/roll_deg", "the camera does not see the seabed in this attitude");
  if (auto steep = TooSteep(spec.pose, *corners)) return reject("pitch_deg/roll_deg", *steep);
  if (!warper_.SeesSeabed(spec.pose))
    return reject("pitch_deg/roll_deg", "the camera does not see the seabed in this attitude");
  p.image = std::move(*image);
  if (hooks_.preprocess) {  // the enhancement chain works on whole frames
    try {
      p.image = FrameImage::FromMat(hooks_.preprocess(p.image.Full()), plan_.channels, config_.sixteen_bit_white);
    } catch (const InputError& e) {
      p.image = FrameImage();
      return reject("image", e.detail());
    }
  }
  return p;
}

void MosaicBuilder::Consume(Prepared p) {
  ++stats_.frames_seen;
  ++consumed_;  // this frame's number: tiles it paints are stamped with it
  last_index_ = p.spec.index;
  FrameRecord record;
  record.id = frame_id_offset_ + p.spec.index;
  record.image = p.spec.image;
  record.image_path = p.spec.image_path;
  record.time_s = p.spec.time_s;
  record.position = frame_.ToLatLon({p.spec.pose.east_m, p.spec.pose.north_m});
  record.altitude_m = p.spec.pose.altitude_m;
  record.depth_m = p.spec.pose.depth_m;
  record.heading_deg = p.spec.pose.heading_deg;
  record.pitch_deg = p.spec.pose.pitch_deg;
  record.roll_deg = p.spec.pose.roll_deg;
  if (p.footprint) record.footprint = *p.footprint;

  if (p.warped) {
    Paint(*p.warped);
    if (!p.tail.empty()) {
      tails_.Add(consumed_, std::move(p.image), std::move(p.tail));
      ++stats_.tail_frames;
    }
    ++stats_.frames_used;
    record.status = "used";
    LatLonBounds fb{180, 90, -180, -90};
    for (const auto& c : *p.footprint) {
      fb.west = std::min(fb.west, c.lon);
      fb.east = std::max(fb.east, c.lon);
      fb.south = std::min(fb.south, c.lat);
      fb.north = std::max(fb.north, c.lat);
    }
    if (!stats_.bounds)
      stats_.bounds = fb;
    else {
      stats_.bounds->west = std::min(stats_.bounds->west, fb.west);
      stats_.bounds->east = std::max(stats_.bounds->east, fb.east);
      stats_.bounds->south = std::min(stats_.bounds->south, fb.south);
      stats_.bounds->north = std::max(stats_.bounds->north, fb.north);
    }
  } else {
    record.status = p.reject_reason;
    stats_.rejections.push_back({p.spec.image_path, p.spec.nav_line, p.reject_field, p.reject_reason});
  }
  store_->PutFrame(record);
  TrackPoint point;
  point.seq = track_seq_++;
  point.time_s = p.spec.time_s;
  point.position = record.position;
  point.altitude_m = record.altitude_m;
  point.depth_m = record.depth_m;
  point.heading_deg = record.heading_deg;
  store_->PutTrackPoint(point);
  if (hooks_.on_frame) hooks_.on_frame(record, point);

  SettleDueTails();
  FinishTiles(false);
  const auto now = std::chrono::steady_clock::now();
  if (consumed_ - last_flush_frame_ >= config_.batch_frames &&
      std::chrono::duration<double>(now - last_flush_).count() >= config_.batch_seconds) {
    FlushBatch();
    last_flush_frame_ = consumed_;
    last_flush_ = now;
  }
}

void MosaicBuilder::Paint(const WarpedFrame& warped) {
  const int ts = config_.tile_size;
  // Tiles the frame is over but leaves to its neighbours are still being
  // painted: keep them (finishing them now would only read them back a
  // frame later).
  const auto over = TilesUnder(warped.box_x0, warped.box_y0, warped.box_width, warped.box_height);
  for (int64_t ty = over[1]; ty <= over[3]; ++ty)
    for (int64_t tx = over[0]; tx <= over[2]; ++tx) {
      auto it = buffer_.find(TileId{plan_.base_zoom, static_cast<int>(tx), static_cast<int>(ty)});
      if (it != buffer_.end()) it->second.last_frame = consumed_;
    }
  const auto painted = TilesUnder(warped.x0, warped.y0, warped.pixels.cols, warped.pixels.rows);
  for (int64_t ty = painted[1]; ty <= painted[3]; ++ty) {
    for (int64_t tx = painted[0]; tx <= painted[2]; ++tx) {
      // Tiles inside the painted box that the frame leaves empty (it is
      // rotated, or hands them to a neighbour) are not started.
      const int64_t x_begin = std::max(tx * ts, warped.x0), y_begin = std::max(ty * ts, warped.y0);
      const int64_t x_end = std::min((tx + 1) * ts, warped.x0 + warped.pixels.cols);
      const int64_t y_end = std::min((ty + 1) * ts, warped.y0 + warped.pixels.rows);
      const cv::Rect roi(static_cast<int>(x_begin - warped.x0), static_cast<int>(y_begin - warped.y0),
                         static_cast<int>(x_end - x_begin), static_cast<int>(y_end - y_begin));
      if (!PaintsAny(warped, roi)) continue;
      TileId id{plan_.base_zoom, static_cast<int>(tx), static_cast<int>(ty)};
      auto it = buffer_.find(id);
      if (it == buffer_.end()) {
        Slot slot;
        slot.accumulator = std::make_unique<TileAccumulator>(ts, plan_.channels, tx * ts, ty * ts);
        cv::Mat previous = ReadBack(id);
        if (!previous.empty()) {
          auto kept = finished_weights_.find(id);
          slot.accumulator->Seed(previous, kept != finished_weights_.end() ? kept->second.weights : cv::Mat());
          ++stats_.readbacks;
        }
        if (auto kept = finished_weights_.find(id); kept != finished_weights_.end()) {
          finished_weights_bytes_ -= kept->second.weights.total() * kept->second.weights.elemSize();
          finished_weights_.erase(kept);  // the accumulator has them now
        }
        buffer_bytes_ += slot.accumulator->Bytes();
        it = buffer_.emplace(id, std::move(slot)).first;
      }
      it->second.accumulator->Blend(warped);
      it->second.last_frame = consumed_;
    }
  }
}

cv::Mat MosaicBuilder::ReadBack(const TileId& id) {
  auto tile = writer_->Read(id);
  if (!tile || tile->rows != config_.tile_size) return {};
  cv::Mat t = WithColourChannels(*tile, plan_.channels);
  if (config_.encoding.format == TileFormat::kJpeg) {
    // JPEG has no alpha: pixels that still show the background colour are empty.
    const cv::Scalar& bg = config_.encoding.background;
    for (int y = 0; y < t.rows; ++y) {
      uint8_t* p = t.ptr<uint8_t>(y);
      for (int x = 0; x < t.cols; ++x, p += t.channels()) {
        bool is_bg = true;
        for (int c = 0; c < plan_.channels; ++c)
          is_bg &= std::abs(p[c] - static_cast<int>(plan_.channels == 1 ? bg[0] : bg[c])) <= 3;
        if (is_bg) p[plan_.channels] = 0;
      }
    }
  }
  return t;
}

void MosaicBuilder::FinishTiles(bool all) {
  std::vector<TileId> done;
  std::vector<std::pair<int, TileId>> by_age;  // the tiles kept
  for (const auto& [id, slot] : buffer_) {
    if (all || (consumed_ - slot.last_frame >= config_.linger_frames && !OverSoon(id)))
      done.push_back(id);
    else
      by_age.push_back({slot.last_frame, id});
  }
  // Memory cap: finish the least recently painted tiles first.
  const size_t cap = (static_cast<size_t>(config_.memory_cap_mb) << 20) * 3 / 4;
  size_t bytes = buffer_bytes_;  // what stays once `done` is written
  for (const TileId& id : done) bytes -= buffer_.at(id).accumulator->Bytes();
  if (!all && bytes > cap) {
    std::sort(by_age.begin(), by_age.end());
    for (const auto& [age, id] : by_age) {
      if (bytes <= cap) break;
      bytes -= buffer_.at(id).accumulator->Bytes();
      done.push_back(id);
    }
  }
  std::sort(done.begin(), done.end());
  // Tails waiting over these tiles go in first (pixels in them only: no tile is added).
  const int64_t ts = config_.tile_size;
  std::vector<PendingTails::Taken> tails;
  for (const TileId& id : done)
    for (PendingTails::Taken& t : tails_.TakeIn(id.x * ts, id.y * ts, (id.x + 1) * ts, (id.y + 1) * ts))
      tails.push_back(std::move(t));
  if (!tails.empty()) SettleTails(std::move(tails));
  for (const TileId& id : done) FinishTile(id);
}

TileId MosaicBuilder::BaseTileOf(int64_t x, int64_t y) const {
  const int64_t ts = config_.tile_size;
  return {plan_.base_zoom, static_cast<int>(FloorDiv(x, ts)), static_cast<int>(FloorDiv(y, ts))};
}

std::vector<TailPixel> MosaicBuilder::Unpainted(const std::vector<TailPixel>& pixels) const {
  const int64_t ts = config_.tile_size, world = (int64_t{1} << plan_.base_zoom) * ts;
  std::vector<TailPixel> open;
  for (const TailPixel& p : pixels) {
    if (p.x < 0 || p.y < 0 || p.x >= world || p.y >= world) continue;  // off the map: not painted either way
    const TileId id = BaseTileOf(p.x, p.y);
    bool covered = false;
    if (auto it = buffer_.find(id); it != buffer_.end()) {
      covered = it->second.accumulator->Covers(p.x, p.y);
    } else if (auto kept = finished_weights_.find(id); kept != finished_weights_.end()) {
      covered =
          kept->second.weights.at<uint16_t>(static_cast<int>(p.y - id.y * ts), static_cast<int>(p.x - id.x * ts)) > 0;
    }  // else not known: painted (a written tile is read back)
    if (!covered) open.push_back(p);
  }
  return open;
}

void MosaicBuilder::SettleTails(std::vector<PendingTails::Taken> taken) {
  // Which pixels are unpainted is decided first, in order, so the map does
  // not depend on timing; then one decoding job per frame, painted in order.
  std::vector<std::shared_ptr<FrameImage>> images;
  std::vector<std::vector<TailPixel>> open;
  for (PendingTails::Taken& t : taken) {
    std::vector<TailPixel> pixels = Unpainted(t.pixels);
    if (pixels.empty()) continue;
    const auto at = std::find(images.begin(), images.end(), t.image);
    if (at == images.end()) {
      images.push_back(t.image);
      open.push_back(std::move(pixels));
    } else {
      std::vector<TailPixel>& more = open[static_cast<size_t>(at - images.begin())];
      more.insert(more.end(), pixels.begin(), pixels.end());
    }
  }
  // A frame decoded now paints its tail's other unpainted pixels too (judged
  // now, before their own tiles are finished) rather than decoding again.
  for (size_t i = 0; i < images.size(); ++i) {
    const std::vector<TailPixel> rest = Unpainted(tails_.TakeFrame(images[i]));
    open[i].insert(open[i].end(), rest.begin(), rest.end());
  }
  // A few jobs in flight at a time: each holds a decoded frame.
  const size_t in_flight = 2 * static_cast<size_t>(pool_->size());
  std::deque<std::future<WarpedFrame>> jobs;
  auto submit = [&](size_t i) {
    jobs.push_back(
        pool_->Submit([image = images[i], pixels = std::move(open[i])] { return DecodeTail(*image, pixels); }));
  };
  size_t next = 0;
  for (; next < images.size() && next < in_flight; ++next) submit(next);
  for (size_t done = 0; done < images.size(); ++done) {
    ++stats_.tail_decodes;
    try {
      Paint(jobs.front().get());
    } catch (const InputError&) {
      // JPEG data broken beyond the rows the warp decoded (libjpeg's memory
      // source only warns about most breakage): the frame's other pixels
      // are painted; its tail is not, and is counted.
      ++stats_.tail_failures;
    }
    jobs.pop_front();
    if (next < images.size()) submit(next++);
  }
}

unsigned MosaicBuilder::TailSides(const FrameSpec& spec) const {
  if (spec.index >= static_cast<int>(foreseen_frames_.size()) || !foreseen_frames_[spec.index]) return 0;
  const ForeseenFrame& own = *foreseen_frames_[spec.index];
  // The other frames over its tiles, close enough in time that the tiles are
  // still being painted when they come (the look-ahead keeps them).
  std::vector<int> near;
  for (int64_t ty = own.tiles[1]; ty <= own.tiles[3]; ++ty)
    for (int64_t tx = own.tiles[0]; tx <= own.tiles[2]; ++tx)
      for (int j : foreseen_.at(TileId{plan_.base_zoom, static_cast<int>(tx), static_cast<int>(ty)}))
        if (j != spec.index && std::abs(j - spec.index) <= config_.lookahead_frames) near.push_back(j);
  std::sort(near.begin(), near.end());
  near.erase(std::unique(near.begin(), near.end()), near.end());
  std::vector<const MapFootprint*> others;
  for (int j : near) others.push_back(&foreseen_frames_[j]->footprint);
  // Inside the others by more than their side-edge strips (kTailEdge raw
  // pixels, at this frame's scale) and two map pixels.
  const auto& c = own.footprint.corners;
  const double map_per_raw = std::hypot(c[1].x - c[0].x, c[1].y - c[0].y) / camera_.width;
  return CoveredSides(own.footprint, others, 2 + FrameWarper::kTailEdge * map_per_raw);
}

void MosaicBuilder::SettleDueTails() {
  // Those that waited the look-ahead (a tile that no frame paints is never
  // finished), and the oldest while they hold more than their memory share.
  std::vector<PendingTails::Taken> taken = tails_.TakeUpTo(consumed_ - config_.lookahead_frames);
  const size_t cap = (static_cast<size_t>(config_.memory_cap_mb) << 20) / 16;
  while (tails_.bytes() > cap)
    for (PendingTails::Taken& t : tails_.TakeOldest()) taken.push_back(std::move(t));
  if (!taken.empty()) SettleTails(std::move(taken));
}

void MosaicBuilder::FinishTile(const TileId& id) {
  auto it = buffer_.find(id);
  cv::Mat tile = it->second.accumulator->Finalize();
  cv::Mat weights = it->second.accumulator->Weights();
  buffer_bytes_ -= it->second.accumulator->Bytes();
  const size_t weights_cap = (static_cast<size_t>(config_.memory_cap_mb) << 20) / 16;
  if (auto old = finished_weights_.find(id); old != finished_weights_.end())
    finished_weights_bytes_ -= old->second.weights.total() * old->second.weights.elemSize();
  finished_weights_bytes_ += weights.total() * weights.elemSize();
  finished_weights_[id] = {std::move(weights), ++finished_stamp_};
  finished_order_.push_back({id, finished_stamp_});
  while (finished_weights_bytes_ > weights_cap && !finished_order_.empty()) {
    const auto [oldest_id, stamp] = finished_order_.front();
    finished_order_.pop_front();
    auto oldest = finished_weights_.find(oldest_id);
    if (oldest == finished_weights_.end() || oldest->second.stamp != stamp) continue;  // superseded
    finished_weights_bytes_ -= oldest->second.weights.total() * oldest->second.weights.elemSize();
    finished_weights_.erase(oldest);
  }
  buffer_.erase(it);
  writer_->Submit(id, tile);
  pyramid_->UpdateChild(id, tile);
}

void MosaicBuilder::FlushBatch() {
  if (config_.live_tiles) {
    // The unfinished tiles as painted so far; their final version replaces
    // them (and their overview quadrants) when they are finished.
    for (const auto& [id, slot] : buffer_) {
      cv::Mat tile = slot.accumulator->Finalize();
      writer_->Submit(id, tile);
      pyramid_->UpdateChild(id, tile);
    }
  }
  pyramid_->Flush();
  WriteMetadata(false);
  writer_->Flush();
  stats_.tiles_written = writer_->tiles_written();  // live progress for a replay
  stats_.tile_bytes = writer_->bytes_written();
}

void MosaicBuilder::Finish() {
  if (finished_) return;
  while (!loading_.empty()) TakeLoaded();
  if (awaiting_next_) {
    StartWarp(awaiting_next_);  // the last usable frame has no next neighbour
    awaiting_next_.reset();
  }
  while (!queued_.empty()) ConsumeReady(true);
  SettleTails(tails_.TakeAll());  // the tails still waiting
  FinishTiles(true);
  pyramid_->Flush();
  writer_->Flush();
  stats_.tiles_written = writer_->tiles_written();
  stats_.tile_bytes = writer_->bytes_written();
  stats_.tiles_per_zoom = writer_->distinct_tiles_per_zoom();
  WriteMetadata(true);
  store_->Flush();
  stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  stats_.cpu_seconds = ProcessCpuSeconds() - start_cpu_;
  finished_ = true;
}

void MosaicBuilder::WriteMetadata(bool complete) {
  auto num = [](double v) {
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
  };
  store_->SetMetadata("name", config_.name);
  store_->SetMetadata("format", TileExtension(config_.encoding.format));
  store_->SetMetadata("type", "overlay");
  store_->SetMetadata("version", "1");
  store_->SetMetadata("description", "Seabed photo map built by SeaMap");
  store_->SetMetadata("attribution", config_.attribution);
  store_->SetMetadata("minzoom", std::to_string(plan_.min_zoom));
  store_->SetMetadata("maxzoom", std::to_string(plan_.base_zoom));
  store_->SetMetadata("seamap_tile_size", std::to_string(config_.tile_size));
  store_->SetMetadata("seamap_gsd_m", num(plan_.gsd_m));
  store_->SetMetadata("seamap_channels", std::to_string(plan_.channels));
  store_->SetMetadata("seamap_origin", num(frame_.origin().lat) + "," + num(frame_.origin().lon));
  store_->SetMetadata("seamap_state", complete ? "complete" : "building");
  store_->SetMetadata("seamap_frames_used", std::to_string(stats_.frames_used));
  store_->SetMetadata("seamap_frames_rejected", std::to_string(stats_.rejections.size()));
  if (stats_.bounds) {
    const auto& b = *stats_.bounds;
    store_->SetMetadata("bounds", num(b.west) + "," + num(b.south) + "," + num(b.east) + "," + num(b.north));
    const int centre_zoom = std::max(plan_.min_zoom, std::min(plan_.base_zoom, plan_.min_zoom + 2));
    store_->SetMetadata(
        "center", num((b.west + b.east) / 2) + "," + num((b.south + b.north) / 2) + "," + std::to_string(centre_zoom));
  }
}

}  // namespace seamap
