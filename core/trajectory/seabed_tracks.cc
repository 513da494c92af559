#include "core/trajectory/seabed_tracks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

#include <Eigen/Dense>

#include "core/camera/frame_projector.h"
#include "core/util/error.h"

namespace seamap {
namespace {

constexpr double kRadToDeg = 180 / M_PI;
// An 8-bit SIFT descriptor has a norm of about 512; a lone candidate on the
// epipolar segment (no second for the ratio test) must be at least this close.
constexpr int kMaxLoneDescriptorDistance = 250;
constexpr int kGridCellPx = 24;         // keypoint grid of a held frame
constexpr int kFinishEveryFrames = 32;  // how often finished tracks are collected

uint64_t NodeKey(int frame, int feature) {
  return (static_cast<uint64_t>(frame) << 32) | static_cast<uint32_t>(feature);
}
int NodeFrame(uint64_t key) {
  return static_cast<int>(key >> 32);
}
int NodeFeature(uint64_t key) {
  return static_cast<int>(key & 0xffffffffu);
}

// A frame whose features are held, with its keypoints bucketed on a grid.
struct HeldFrame {
  FrameFeatures features;
  int grid_cols = 0, grid_rows = 0;
  std::vector<int> cell_start;  // grid_cols * grid_rows + 1 offsets into `order`
  std::vector<int> order;       // keypoint indices by cell
  std::vector<int> stamp;       // per cell: the last query that visited it
  int query = 0;

  void BuildGrid(const CameraModel& camera) {
    grid_cols = std::max(1, (camera.width + kGridCellPx - 1) / kGridCellPx);
    grid_rows = std::max(1, (camera.height + kGridCellPx - 1) / kGridCellPx);
    const int cells = grid_cols * grid_rows;
    std::vector<int> cell_of(features.ideal_px.size());
    cell_start.assign(cells + 1, 0);
    for (size_t k = 0; k < cell_of.size(); ++k) {
      const cv::Point2f& p = features.ideal_px[k];
      const int cx = std::clamp(static_cast<int>(std::floor(p.x / kGridCellPx)), 0, grid_cols - 1);
      const int cy = std::clamp(static_cast<int>(std::floor(p.y / kGridCellPx)), 0, grid_rows - 1);
      cell_of[k] = cy * grid_cols + cx;
      ++cell_start[cell_of[k] + 1];
    }
    for (int c = 0; c < cells; ++c) cell_start[c + 1] += cell_start[c];
    order.resize(cell_of.size());
    std::vector<int> fill(cell_start.begin(), cell_start.end() - 1);
    for (size_t k = 0; k < cell_of.size(); ++k) order[fill[cell_of[k]]++] = static_cast<int>(k);
    stamp.assign(cells, -1);
  }
  size_t Bytes() const { return features.Bytes() + (cell_start.size() + order.size() + stamp.size()) * sizeof(int); }
};

int DescriptorDistance(const cv::Mat& a, int ra, const cv::Mat& b, int rb) {
  const uint8_t* pa = a.ptr<uint8_t>(ra);
  const uint8_t* pb = b.ptr<uint8_t>(rb);
  int sum = 0;
  for (int k = 0; k < a.cols; ++k) {
    const int d = static_cast<int>(pa[k]) - static_cast<int>(pb[k]);
    sum += d * d;
  }
  return static_cast<int>(std::lround(std::sqrt(static_cast<double>(sum))));
}

double DistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Liang-Barsky: clips the segment a-b to [x0, x1] x [y0, y1]; false when outside.
bool ClipSegment(Eigen::Vector2d* a, Eigen::Vector2d* b, double x0, double y0, double x1, double y1) {
  double t0 = 0, t1 = 1;
  const Eigen::Vector2d d = *b - *a;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a->x() - x0, x1 - a->x(), a->y() - y0, y1 - a->y()};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;
    } else {
      const double t = q[k] / p[k];
      if (p[k] < 0)
        t0 = std::max(t0, t);
      else
        t1 = std::min(t1, t);
    }
  }
  if (t0 > t1) return false;
  const Eigen::Vector2d start = *a;
  *a = start + t0 * d;
  *b = start + t1 * d;
  return true;
}

Eigen::Vector3d RayOf(const CameraModel& camera, const TrackCamera& view, const cv::Point2f& ideal_px) {
  const Eigen::Vector3d in_camera((ideal_px.x - camera.cx) / camera.fx, (ideal_px.y - camera.cy) / camera.fy, 1);
  return (view.world_from_camera * in_camera).normalized();
}

struct Match {
  int newer = 0, older = 0;  // feature indices
};

// Features of `newer` looked for along their epipolar segments in `older`.
std::vector<Match> MatchGuided(const CameraModel& camera, const TrackCamera& newer_view, const HeldFrame& newer,
                               const TrackCamera& older_view, HeldFrame* older, const TrackOptions& options) {
  const double seabed_low = std::min(newer_view.seabed_up_m, older_view.seabed_up_m) - options.max_relief_m;
  // The top of the search: the relief allowed, but a quarter of the altitude below either camera.
  const double lowest_camera = std::min(newer_view.centre_m.z(), older_view.centre_m.z());
  const double altitude = lowest_camera - std::max(newer_view.seabed_up_m, older_view.seabed_up_m);
  const double seabed_high = std::min(std::max(newer_view.seabed_up_m, older_view.seabed_up_m) + options.max_relief_m,
                                      lowest_camera - 0.25 * std::max(altitude, 0.0));
  const double gate = options.epipolar_px;
  std::unordered_map<int, std::pair<int, int>> best_for_older;  // older feature -> (distance, newer feature)
  const auto& pixels = newer.features.ideal_px;
  for (size_t a = 0; a < pixels.size(); ++a) {
    const Eigen::Vector3d ray = RayOf(camera, newer_view, pixels[a]);
    if (!(ray.z() < -1e-3)) continue;  // must point down
    const double t_high = (seabed_high - newer_view.centre_m.z()) / ray.z();
    const double t_low = (seabed_low - newer_view.centre_m.z()) / ray.z();
    if (!(t_high > 0) || !(t_low > t_high)) continue;
    Eigen::Vector2d s0, s1;
    if (!ProjectToIdeal(camera, older_view, newer_view.centre_m + t_high * ray, &s0) ||
        !ProjectToIdeal(camera, older_view, newer_view.centre_m + t_low * ray, &s1))
      continue;
    if (!ClipSegment(&s0, &s1, -gate, -gate, camera.width - 1 + gate, camera.height - 1 + gate)) continue;
    // Visit the grid cells within `gate` of the segment.
    const int query = ++older->query;
    int best = std::numeric_limits<int>::max(), second = best, best_k = -1;
    const double length = (s1 - s0).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(length / (kGridCellPx / 2.0))));
    for (int s = 0; s <= steps; ++s) {
      const Eigen::Vector2d p = s0 + (s1 - s0) * (static_cast<double>(s) / steps);
      const int x0 = std::max(0, static_cast<int>(std::floor((p.x() - gate) / kGridCellPx)));
      const int x1 = std::min(older->grid_cols - 1, static_cast<int>(std::floor((p.x() + gate) / kGridCellPx)));
      const int y0 = std::max(0, static_cast<int>(std::floor((p.y() - gate) / kGridCellPx)));
      const int y1 = std::min(older->grid_rows - 1, static_cast<int>(std::floor((p.y() + gate) / kGridCellPx)));
      for (int cy = y0; cy <= y1; ++cy)
        for (int cx = x0; cx <= x1; ++cx) {
          const int cell = cy * older->grid_cols + cx;
          if (older->stamp[cell] == query) continue;
          older->stamp[cell] = query;
          for (int o = older->cell_start[cell]; o < older->cell_start[cell + 1]; ++o) {
            const int k = older->order[o];
            const cv::Point2f& q = older->features.ideal_px[k];
            if (DistanceToSegment({q.x, q.y}, s0, s1) > gate) continue;
            const int d =
                DescriptorDistance(newer.features.descriptors, static_cast<int>(a), older->features.descriptors, k);
            if (d < best) {
              second = best;
              best = d;
              best_k = k;
            } else if (d < second) {
              second = d;
            }
          }
        }
    }
    if (best_k < 0) continue;
    const bool lone = second == std::numeric_limits<int>::max();
    if (lone ? best > kMaxLoneDescriptorDistance : best >= options.ratio * second) continue;
    auto it = best_for_older.find(best_k);
    if (it == best_for_older.end() || best < it->second.first) best_for_older[best_k] = {best, static_cast<int>(a)};
  }
  std::vector<Match> matches;
  matches.reserve(best_for_older.size());
  for (const auto& [older_k, value] : best_for_older) matches.push_back({value.second, older_k});
  return matches;
}

// Union-find over matched features, keyed by (frame, feature).
class TrackForest {
 public:
  struct Node {
    uint64_t parent;
    cv::Point2f ideal_px;
    int done_after;  // the root's: the last frame that may still add to the track
  };

  void Union(uint64_t a, cv::Point2f pa, int done_a, uint64_t b, cv::Point2f pb, int done_b) {
    const uint64_t ra = Find(Add(a, pa, done_a)), rb = Find(Add(b, pb, done_b));
    if (ra == rb) return;
    Node& na = nodes_.at(ra);
    Node& nb = nodes_.at(rb);
    nb.done_after = std::max(na.done_after, nb.done_after);
    na.parent = rb;
  }

  // Takes out the tracks none of whose frames can be matched again (all
  // when `all`), as lists of (key, pixel).
  std::vector<std::vector<std::pair<uint64_t, cv::Point2f>>> TakeFinished(int frame_done, bool all) {
    std::unordered_map<uint64_t, size_t> index_of_root;
    std::vector<std::vector<std::pair<uint64_t, cv::Point2f>>> finished;
    std::vector<uint64_t> taken;
    for (auto& [key, node] : nodes_) {
      const uint64_t root = Find(key);
      if (!all && nodes_.at(root).done_after > frame_done) continue;
      auto [it, fresh] = index_of_root.emplace(root, finished.size());
      if (fresh) finished.emplace_back();
      finished[it->second].push_back({key, node.ideal_px});
      taken.push_back(key);
    }
    for (uint64_t key : taken) nodes_.erase(key);
    return finished;
  }
  size_t size() const { return nodes_.size(); }

 private:
  uint64_t Add(uint64_t key, cv::Point2f p, int done_after) {
    nodes_.emplace(key, Node{key, p, done_after});
    return key;
  }
  uint64_t Find(uint64_t key) {
    uint64_t root = key;
    while (nodes_.at(root).parent != root) root = nodes_.at(root).parent;
    while (key != root) {  // path compression
      Node& n = nodes_.at(key);
      key = n.parent;
      n.parent = root;
    }
    return root;
  }
  std::unordered_map<uint64_t, Node> nodes_;
};

struct FootprintDisc {
  bool usable = false;
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  double min_side_m = 0;
};

int64_t CellKey(int x, int y) {
  return (static_cast<int64_t>(x) << 32) ^ static_cast<uint32_t>(y);
}

// Older partners per frame, through a hash grid of footprint centres.
std::vector<std::vector<int>> FindPartners(const std::vector<FootprintDisc>& discs, const TrackOptions& options) {
  const int n = static_cast<int>(discs.size());
  std::vector<double> sides;
  for (const auto& d : discs)
    if (d.usable) sides.push_back(d.min_side_m);
  std::vector<std::vector<int>> partners(n);
  if (sides.empty()) return partners;
  std::nth_element(sides.begin(), sides.begin() + sides.size() / 2, sides.end());
  const double cell_m = std::max(sides[sides.size() / 2], 1e-3);
  std::unordered_map<int64_t, std::vector<int>> grid;
  auto cell_of = [&](const Eigen::Vector2d& p, int* x, int* y) {
    *x = static_cast<int>(std::floor(p.x() / cell_m));
    *y = static_cast<int>(std::floor(p.y() / cell_m));
  };
  std::vector<std::pair<double, int>> near;
  for (int j = 0; j < n; ++j) {
    if (!discs[j].usable) continue;
    int x = 0, y = 0;
    cell_of(discs[j].centre_m, &x, &y);
    near.clear();
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        auto it = grid.find(CellKey(x + dx, y + dy));
        if (it == grid.end()) continue;
        for (int i : it->second) {
          const double reach = (1 - options.min_overlap) * std::min(discs[i].min_side_m, discs[j].min_side_m);
          const double d = (discs[i].centre_m - discs[j].centre_m).norm();
          if (d < reach) near.push_back({d, i});
        }
      }
    grid[CellKey(x, y)].push_back(j);
    std::sort(near.begin(), near.end());
    const int m = static_cast<int>(near.size()), keep = std::min(m, options.max_partners_per_frame);
    // Spread over the baselines, nearest to widest.
    for (int k = 0; k < keep; ++k) {
      const int pick = keep == 1 ? 0 : static_cast<int>(std::lround(static_cast<double>(k) * (m - 1) / (keep - 1)));
      partners[j].push_back(near[pick].second);
    }
    std::sort(partners[j].begin(), partners[j].end());
    partners[j].erase(std::unique(partners[j].begin(), partners[j].end()), partners[j].end());
  }
  return partners;
}

}  // namespace

void TrackOptions::Check() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(max_relief_m) || max_relief_m > 1000)
    throw InputError("", 0, "--max-relief", "expected metres in (0, 1000]");
  if (!positive(epipolar_px) || epipolar_px > 100)
    throw InputError("", 0, "epipolar_px", "expected pixels in (0, 100]");
  if (!positive(ratio) || ratio > 1) throw InputError("", 0, "ratio", "expected a ratio in (0, 1]");
  if (!(min_overlap >= 0 && min_overlap < 1)) throw InputError("", 0, "min_overlap", "expected a share in [0, 1)");
  if (max_partners_per_frame < 1 || max_partners_per_frame > 1000)
    throw InputError("", 0, "max_partners_per_frame", "expected 1..1000");
  if (min_views < 2 || min_views > 1000) throw InputError("", 0, "min_views", "expected 2..1000");
  if (!positive(max_reprojection_px)) throw InputError("", 0, "max_reprojection_px", "expected pixels > 0");
  if (!(min_ray_angle_deg >= 0 && min_ray_angle_deg < 90))
    throw InputError("", 0, "min_ray_angle_deg", "expected degrees in [0, 90)");
  if (!positive(pixel_sigma_px)) throw InputError("", 0, "pixel_sigma_px", "expected pixels > 0");
}

TrackCamera TrackCameraOf(const CameraModel& camera, const VehiclePose& pose) {
  Eigen::Matrix3d enu_from_ned;
  enu_from_ned << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  TrackCamera v;
  v.world_from_camera = enu_from_ned * NedFromCamera(camera, pose);
  const Eigen::Vector3d offset_ned = NedFromBody(pose) * camera.mount_offset_m;
  v.centre_m = {pose.east_m + offset_ned.y(), pose.north_m + offset_ned.x(), -pose.depth_m - offset_ned.z()};
  v.seabed_up_m = -(pose.depth_m + pose.altitude_m);
  return v;
}

bool ProjectToIdeal(const CameraModel& camera, const TrackCamera& view, const Eigen::Vector3d& point_m,
                    Eigen::Vector2d* ideal_px) {
  const Eigen::Vector3d c = view.world_from_camera.transpose() * (point_m - view.centre_m);
  if (!(c.z() > 1e-6)) return false;
  *ideal_px = {camera.fx * c.x() / c.z() + camera.cx, camera.fy * c.y() / c.z() + camera.cy};
  return true;
}

bool TriangulateTrack(const CameraModel& camera, const std::vector<TrackCamera>& views, const TrackOptions& options,
                      SeabedTrack* track, std::string* why) {
  std::vector<TrackObservation>& obs = track->observations;
  std::vector<TrackCamera> cams = views;
  while (true) {
    const int n = static_cast<int>(obs.size());
    if (n < std::max(2, options.min_views)) {
      *why = n < static_cast<int>(views.size()) ? "reprojection" : "views";
      return false;
    }
    // Least squares on the rays: the point nearest all of them.
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> rays(n);
    for (int k = 0; k < n; ++k) {
      rays[k] = RayOf(camera, cams[k], obs[k].ideal_px);
      const Eigen::Matrix3d m = Eigen::Matrix3d::Identity() - rays[k] * rays[k].transpose();
      a += m;
      b += m * cams[k].centre_m;
    }
    double widest = 0;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) widest = std::max(widest, std::acos(std::clamp(rays[p].dot(rays[q]), -1.0, 1.0)));
    track->ray_angle_deg = widest * kRadToDeg;
    if (track->ray_angle_deg < options.min_ray_angle_deg) {
      *why = "ray angle";
      return false;
    }
    Eigen::Vector3d x = a.ldlt().solve(b);
    // Gauss-Newton on the reprojection error.
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    std::vector<double> residual(n);
    bool behind = false;
    for (int iteration = 0; iteration < 6; ++iteration) {
      jtj.setZero();
      Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
      behind = false;
      for (int k = 0; k < n; ++k) {
        const Eigen::Matrix3d rt = cams[k].world_from_camera.transpose();
        const Eigen::Vector3d c = rt * (x - cams[k].centre_m);
        if (!(c.z() > 1e-6)) {
          behind = true;
          break;
        }
        const Eigen::Vector2d r(camera.fx * c.x() / c.z() + camera.cx - obs[k].ideal_px.x,
                                camera.fy * c.y() / c.z() + camera.cy - obs[k].ideal_px.y);
        Eigen::Matrix<double, 2, 3> dproj;
        dproj << camera.fx / c.z(), 0, -camera.fx * c.x() / (c.z() * c.z()), 0, camera.fy / c.z(),
            -camera.fy * c.y() / (c.z() * c.z());
        const Eigen::Matrix<double, 2, 3> j = dproj * rt;
        jtj += j.transpose() * j;
        jtr += j.transpose() * r;
        residual[k] = r.norm();
      }
      if (behind) break;
      const Eigen::Vector3d step = jtj.ldlt().solve(-jtr);
      if (!step.allFinite()) break;
      x += step;
      if (step.norm() < 1e-7) break;
    }
    // Residuals at the final point.
    if (!behind) {
      for (int k = 0; k < n; ++k) {
        Eigen::Vector2d p;
        if (!ProjectToIdeal(camera, cams[k], x, &p)) {
          behind = true;
          break;
        }
        residual[k] = (p - Eigen::Vector2d(obs[k].ideal_px.x, obs[k].ideal_px.y)).norm();
      }
    }
    if (behind || !x.allFinite()) {
      *why = "behind";
      return false;
    }
    const int worst = static_cast<int>(std::max_element(residual.begin(), residual.end()) - residual.begin());
    if (residual[worst] > options.max_reprojection_px) {
      if (n <= std::max(2, options.min_views)) {
        *why = "reprojection";
        return false;
      }
      obs.erase(obs.begin() + worst);
      cams.erase(cams.begin() + worst);
      continue;
    }
    double expected_seabed = 0;
    for (const TrackCamera& c : cams) expected_seabed += c.seabed_up_m / n;
    if (std::fabs(x.z() - expected_seabed) > options.max_relief_m) {
      *why = "seabed";
      return false;
    }
    double sum_sq = 0;
    for (double r : residual) sum_sq += r * r;
    const double dof = std::max(1, 2 * n - 3);
    const double scale_sq = std::max(sum_sq / dof, options.pixel_sigma_px * options.pixel_sigma_px);
    const Eigen::Matrix3d covariance = scale_sq * jtj.inverse();
    track->east_north_up_m = x;
    track->sigma_up_m = std::sqrt(std::max(covariance(2, 2), 0.0));
    track->reprojection_rms_px = std::sqrt(sum_sq / n);
    if (!std::isfinite(track->sigma_up_m)) {
      *why = "ray angle";
      return false;
    }
    return true;
  }
}

SeabedTracks BuildSeabedTracks(const std::vector<VehiclePose>& poses, const CameraModel& camera,
                               const FeatureSource& features, const TrackOptions& options, TrackReport* report,
                               const TrackProgress& progress) {
  options.Check();
  TrackReport r;
  const int n = static_cast<int>(poses.size());
  r.frames = n;
  std::vector<TrackCamera> views(n);
  std::vector<FootprintDisc> discs(n);
  for (int i = 0; i < n; ++i) {
    views[i] = TrackCameraOf(camera, poses[i]);
    const auto corners = Footprint(camera, poses[i]);
    if (!corners) continue;
    FootprintDisc& d = discs[i];
    d.usable = true;
    double side = std::numeric_limits<double>::max();
    for (int k = 0; k < 4; ++k) {
      const LocalXY& p = (*corners)[k];
      const LocalXY& q = (*corners)[(k + 1) % 4];
      d.centre_m += Eigen::Vector2d(p.east, p.north) / 4;
      side = std::min(side, std::hypot(q.east - p.east, q.north - p.north));
    }
    d.min_side_m = side;
  }
  const std::vector<std::vector<int>> partners = FindPartners(discs, options);
  // The last frame matched with each frame: after it, its features can go.
  std::vector<int> last_needed(n);
  for (int j = 0; j < n; ++j) last_needed[j] = j;
  for (int j = 0; j < n; ++j)
    for (int i : partners[j]) last_needed[i] = std::max(last_needed[i], j);

  SeabedTracks out;
  TrackForest forest;
  std::map<int, HeldFrame> held;
  size_t held_bytes = 0;
  auto finish = [&](int frame_done, bool all) {
    for (auto& members : forest.TakeFinished(frame_done, all)) {
      ++r.tracks;
      std::sort(members.begin(), members.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      bool conflict = false;
      for (size_t k = 1; k < members.size(); ++k)
        conflict |= NodeFrame(members[k].first) == NodeFrame(members[k - 1].first);
      if (conflict) {
        ++r.rejected_conflict;
        continue;
      }
      SeabedTrack track;
      std::vector<TrackCamera> track_views;
      for (const auto& [key, px] : members) {
        track.observations.push_back({NodeFrame(key), NodeFeature(key), px});
        track_views.push_back(views[NodeFrame(key)]);
      }
      std::string why;
      if (!TriangulateTrack(camera, track_views, options, &track, &why)) {
        if (why == "views")
          ++r.rejected_views;
        else if (why == "ray angle")
          ++r.rejected_ray_angle;
        else if (why == "seabed")
          ++r.rejected_seabed;
        else
          ++r.rejected_reprojection;
        continue;
      }
      SeabedPoint p;
      p.east_north_up_m = track.east_north_up_m;
      p.sigma_up_m = track.sigma_up_m;
      p.views = static_cast<int>(track.observations.size());
      out.points.push_back(p);
      out.tracks.push_back(std::move(track));
    }
  };

  for (int j = 0; j < n; ++j) {
    HeldFrame frame;
    if (discs[j].usable) frame.features = features(j);
    if (frame.features.ideal_px.empty() ||
        frame.features.descriptors.rows != static_cast<int>(frame.features.ideal_px.size())) {
      ++r.frames_without_features;
      frame.features = FrameFeatures();
    }
    frame.BuildGrid(camera);
    for (int i : partners[j]) {
      auto it = held.find(i);
      if (it == held.end() || it->second.features.ideal_px.empty() || frame.features.ideal_px.empty()) continue;
      ++r.pairs;
      const std::vector<Match> matches = MatchGuided(camera, views[j], frame, views[i], &it->second, options);
      r.matches += static_cast<long>(matches.size());
      for (const Match& m : matches)
        forest.Union(NodeKey(j, m.newer), frame.features.ideal_px[m.newer], last_needed[j], NodeKey(i, m.older),
                     it->second.features.ideal_px[m.older], last_needed[i]);
    }
    held_bytes += frame.Bytes();
    held.emplace(j, std::move(frame));
    r.peak_frames_in_memory = std::max(r.peak_frames_in_memory, static_cast<int>(held.size()));
    r.peak_feature_bytes = std::max(r.peak_feature_bytes, held_bytes);
    for (auto it = held.begin(); it != held.end();) {
      if (last_needed[it->first] <= j) {
        held_bytes -= it->second.Bytes();
        it = held.erase(it);
      } else {
        ++it;
      }
    }
    if ((j + 1) % kFinishEveryFrames == 0) finish(j, false);
    if (progress) progress(j + 1, n);
  }
  finish(n, true);
  r.points = static_cast<long>(out.points.size());
  if (report) *report = r;
  return out;
}

}  // namespace seamap
