#include "core/sim/seabed_objects.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

// The shipped model's five classes, the classes it does not know (drum), then the clutter kinds.
enum Class { kTyre = 0, kCrate, kPipe, kAnchor, kRock, kDrum, kRockRing, kPipePiece, kDarkRock, kKindCount };
constexpr int kShippedClasses = 5, kClassCount = 6;

// Body colours (BGR, luminance about 1) and albedos relative to full scale;
// the procedural seabed averages 0.5. Drums are rust brown; clutter looks like
// the rocks and pipes it imitates.
const cv::Vec3f kColour[kKindCount] = {{1.0f, 1.0f, 1.02f},   {0.62f, 0.92f, 1.25f}, {1.02f, 1.0f, 0.96f},
                                       {0.7f, 0.9f, 1.25f},   {0.95f, 1.03f, 0.98f}, {0.55f, 0.85f, 1.35f},
                                       {0.95f, 1.03f, 0.98f}, {1.02f, 1.0f, 0.96f},  {0.98f, 1.0f, 1.02f}};
const float kAlbedo[kKindCount] = {0.16f, 0.62f, 0.86f, 0.3f, 0.36f, 0.5f, 0.34f, 0.8f, 0.17f};

bool IsRock(int cls) {
  return cls == kRock || cls == kDarkRock;
}

struct V2 {
  double u, v;
};

double SegmentDistance(V2 p, V2 a, V2 b) {
  const double dx = b.u - a.u, dy = b.v - a.v;
  const double len2 = dx * dx + dy * dy;
  const double t = len2 > 0 ? std::clamp(((p.u - a.u) * dx + (p.v - a.v) * dy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(p.u - a.u - t * dx, p.v - a.v - t * dy);
}

struct Capsule {
  V2 a, b;
  double radius;
};

// An object's shape in its own frame (u along the axis, v across, metres):
// a height field made of primitives, each with an albedo factor.
struct Shape {
  int cls = 0;
  double length = 0, width = 0, height = 0;
  std::vector<Capsule> capsules;  // anchor shank, stock, arms
  std::vector<std::array<V2, 3>> flukes;
  double rock_coef[6][2] = {};  // rock outline harmonics (amplitude, phase)
  std::vector<Capsule> stones;  // rock ring: the stones (a = centre, radius)
  bool standing = false;        // drum on its end

  explicit Shape(const SeabedObject& o)
      : cls(o.class_id), length(o.length_m), width(o.width_m), height(o.height_m), standing(o.standing) {
    cv::RNG rng(o.shape_seed);
    if (cls == kRockRing) {  // 7-10 stones around a circle, each up to a fifth of the radius
      const double R = length / 2;
      const int n = rng.uniform(7, 11);
      const double phase = rng.uniform(0.0, 2 * M_PI);
      for (int k = 0; k < n; ++k) {
        const double a = phase + 2 * M_PI * (k + rng.uniform(-0.2, 0.2)) / n, mid = 0.78 * R;
        stones.push_back({{mid * std::cos(a), mid * std::sin(a)}, {}, 0.2 * R * rng.uniform(0.75, 1.0)});
      }
    }
    if (IsRock(cls)) {
      for (int k = 2; k < 6; ++k) {
        rock_coef[k][0] = rng.uniform(0.0, 0.22 / k);
        rock_coef[k][1] = rng.uniform(0.0, 2 * M_PI);
      }
    }
    if (cls == kAnchor) {
      const double L = length, r = 0.045 * L;
      capsules.push_back({{0, -0.44 * L}, {0, 0.42 * L}, r});                    // shank
      capsules.push_back({{-0.3 * L, 0.38 * L}, {0.3 * L, 0.38 * L}, 0.8 * r});  // stock
      capsules.push_back({{0, 0.42 * L}, {0, 0.5 * L - 0.6 * r}, 0.6 * r});      // ring stub
      for (int s = -1; s <= 1; s += 2) {  // curved arms from the crown, flukes at the tips
        V2 prev{0, -0.47 * L};
        for (int k = 1; k <= 6; ++k) {
          const double a = -M_PI / 2 + s * k * (M_PI * 0.38 / 6);
          const V2 p{0.3 * L * std::cos(a), -0.17 * L + 0.3 * L * std::sin(a)};
          capsules.push_back({prev, p, 0.85 * r});
          prev = p;
        }
        flukes.push_back({V2{prev.u, prev.v + 0.1 * L}, V2{prev.u - s * 0.11 * L, prev.v - 0.05 * L},
                          V2{prev.u + s * 0.05 * L, prev.v - 0.07 * L}});
      }
    }
  }

  double RockRadius(double phi) const {
    double f = 1;
    for (int k = 2; k < 6; ++k) f += rock_coef[k][0] * std::cos(k * phi + rock_coef[k][1]);
    return 0.5 * length * f / 1.0;
  }

  // Height above the seabed (negative outside) and albedo factor at (u, v).
  bool Sample(double u, double v, float* h, float* albedo) const {
    switch (cls) {
      case kTyre: {
        const double R = length / 2, tube = 0.21 * R, mid = R - tube;
        const double rho = std::hypot(u, v), d = std::abs(rho - mid);
        if (d >= tube) return false;
        *h = static_cast<float>(height * std::sqrt(1 - (d / tube) * (d / tube)));
        const double tread = std::cos(std::atan2(v, u) * std::round(R * 90));  // tread blocks on the outer band
        *albedo = static_cast<float>(rho > mid + 0.4 * tube ? 1 + 0.35 * tread : 1.0);
        return true;
      }
      case kCrate: {
        const double du = length / 2 - std::abs(u), dv = width / 2 - std::abs(v);
        if (du <= 0 || dv <= 0) return false;
        const double edge = std::min(du, dv), bevel = 0.02;
        *h = static_cast<float>(height * std::min(1.0, 0.3 + 0.7 * edge / bevel));
        const double plank = width / 5;
        const int index = static_cast<int>((v + width / 2) / plank);
        const double in_plank = std::fmod(v + width / 2, plank);
        float a = 1.0f + 0.12f * static_cast<float>(((index * 7919) % 5) - 2) / 2;  // plank to plank
        if (in_plank < 0.012 || in_plank > plank - 0.004) a *= 0.35f;               // gaps between planks
        if (edge < 0.05) a *= 0.8f;                                                 // frame battens
        *albedo = a;
        return true;
      }
      case kDrum: {
        if (standing) {  // the lid: a raised rim, a bung
          const double R = width / 2, rho = std::hypot(u, v);
          if (rho >= R) return false;
          const bool rim = rho > R - 0.035;
          *h = static_cast<float>(height * (rim ? 1.0 : 0.985));
          const bool bung = std::hypot(u - 0.6 * R, v) < 0.08 * R;
          *albedo = rim ? 0.72f : (bung ? 0.45f : 1.0f);
          return true;
        }
        const double r = width / 2;  // lying: a cylinder with two rolling hoops and rims
        if (std::abs(u) >= length / 2 || std::abs(v) >= r) return false;
        const bool hoop = std::abs(std::abs(u) - length / 6)<0.018, rim = std::abs(u)> length / 2 - 0.03;
        *h = static_cast<float>(r + std::sqrt(r * r - v * v) + (hoop || rim ? 0.008 : 0.0));
        *albedo = rim ? 0.6f : (hoop ? 0.68f : 1.0f);
        return true;
      }
      case kRockRing: {
        double best = -1;
        for (const Capsule& c : stones) {
          const double d = std::hypot(u - c.a.u, v - c.a.v);
          if (d < c.radius) best = std::max(best, height * std::sqrt(1 - (d / c.radius) * (d / c.radius)));
        }
        if (best <= 0) return false;
        *h = static_cast<float>(best);
        *albedo = 1.0f;
        return true;
      }
      case kPipe:
      case kPipePiece: {
        const double r = width / 2;
        if (std::abs(u) >= length / 2 || std::abs(v) >= r) return false;
        *h = static_cast<float>(r + std::sqrt(r * r - v * v));
        *albedo = std::abs(u) > length / 2 - 0.025 ? 0.6f : 1.0f;  // rims at the ends
        return true;
      }
      case kAnchor: {
        double best = -1;
        for (const Capsule& c : capsules) {
          const double d = SegmentDistance({u, v}, c.a, c.b);
          if (d < c.radius) best = std::max(best, std::sqrt(c.radius * c.radius - d * d));
        }
        for (const auto& t : flukes) {
          const std::vector<cv::Point2f> tri = {cv::Point2f(t[0].u, t[0].v), cv::Point2f(t[1].u, t[1].v),
                                                cv::Point2f(t[2].u, t[2].v)};
          if (cv::pointPolygonTest(tri, cv::Point2f(u, v), false) > 0) best = std::max(best, 0.012 * length);
        }
        if (best < 0) return false;
        *h = static_cast<float>(best);
        *albedo = 1.0f;
        return true;
      }
      default: {  // rock
        const double rho = std::hypot(u, v), R = RockRadius(std::atan2(v, u));
        if (rho >= R) return false;
        const double q = rho / R;
        *h = static_cast<float>(height * std::sqrt(1 - q * q) *
                                (1 + 0.08 * std::sin(23 * u / length + 3) * std::cos(19 * v / length)));
        *albedo = 1.0f;
        return true;
      }
    }
  }

  // Points whose convex hull holds the shape, in the object frame.
  std::vector<V2> OutlinePoints() const {
    std::vector<V2> pts;
    const int n = 96;
    switch (cls) {
      case kTyre:
      case kRockRing:
        for (int k = 0; k < n; ++k)
          pts.push_back({length / 2 * std::cos(2 * M_PI * k / n), length / 2 * std::sin(2 * M_PI * k / n)});
        break;
      case kDrum:
        if (standing) {
          for (int k = 0; k < n; ++k)
            pts.push_back({width / 2 * std::cos(2 * M_PI * k / n), width / 2 * std::sin(2 * M_PI * k / n)});
        } else {
          for (double su : {-1.0, 1.0})
            for (double sv : {-1.0, 1.0}) pts.push_back({su * length / 2, sv * width / 2});
        }
        break;
      case kRock:
      case kDarkRock:
        for (int k = 0; k < n; ++k) {
          const double phi = 2 * M_PI * k / n, R = RockRadius(phi);
          pts.push_back({R * std::cos(phi), R * std::sin(phi)});
        }
        break;
      case kAnchor:
        for (const Capsule& c : capsules)
          for (int k = 0; k < 16; ++k) {
            const double a = 2 * M_PI * k / 16;
            for (const V2& e : {c.a, c.b}) pts.push_back({e.u + c.radius * std::cos(a), e.v + c.radius * std::sin(a)});
          }
        for (const auto& t : flukes) pts.insert(pts.end(), t.begin(), t.end());
        break;
      default:  // crate, pipe: rectangles
        for (double su : {-1.0, 1.0})
          for (double sv : {-1.0, 1.0}) pts.push_back({su * length / 2, sv * width / 2});
    }
    return pts;
  }
};

// Fills footprint, box and centre from the shape, angle and reference point.
void Derive(SeabedObject* o) {
  const Shape shape(*o);
  const double c = std::cos(o->angle_rad), s = std::sin(o->angle_rad);
  // Hull of the rotated outline relative to the reference point (OpenCV wants floats: keep them small).
  std::vector<cv::Point2f> pts, hull;
  for (const V2& p : shape.OutlinePoints())
    pts.emplace_back(static_cast<float>(c * p.u - s * p.v), static_cast<float>(s * p.u + c * p.v));
  cv::convexHull(pts, hull, /*clockwise=*/false);  // counter-clockwise in east/north axes
  o->footprint_m.clear();
  double e0 = 1e300, e1 = -1e300, n0 = 1e300, n1 = -1e300;
  for (const cv::Point2f& p : hull) {
    const LocalXY q{o->ref_east_m + p.x, o->ref_north_m + p.y};
    o->footprint_m.push_back(q);
    e0 = std::min(e0, q.east), e1 = std::max(e1, q.east), n0 = std::min(n0, q.north), n1 = std::max(n1, q.north);
  }
  o->centre_east_m = (e0 + e1) / 2, o->centre_north_m = (n0 + n1) / 2;
  o->box_width_m = e1 - e0, o->box_height_m = n1 - n0;
}

bool SegmentsCross(const LocalXY& a, const LocalXY& b, const LocalXY& c, const LocalXY& d) {
  auto orient = [](const LocalXY& p, const LocalXY& q, const LocalXY& r) {
    return (q.east - p.east) * (r.north - p.north) - (q.north - p.north) * (r.east - p.east);
  };
  return orient(a, b, c) * orient(a, b, d) < 0 && orient(c, d, a) * orient(c, d, b) < 0;
}

bool Inside(const std::vector<LocalXY>& poly, const LocalXY& p) {
  for (size_t i = 0; i < poly.size(); ++i) {
    const LocalXY& a = poly[i];
    const LocalXY& b = poly[(i + 1) % poly.size()];
    if ((b.east - a.east) * (p.north - a.north) - (b.north - a.north) * (p.east - a.east) < 0) return false;
  }
  return true;
}

// Distance between two convex polygons (0 when they overlap).
double PolygonGap(const std::vector<LocalXY>& a, const std::vector<LocalXY>& b) {
  if (Inside(a, b[0]) || Inside(b, a[0])) return 0;
  double best = 1e300;
  for (int pass = 0; pass < 2; ++pass) {
    const auto& p = pass ? b : a;
    const auto& q = pass ? a : b;
    for (size_t i = 0; i < q.size(); ++i) {
      const LocalXY& s0 = q[i];
      const LocalXY& s1 = q[(i + 1) % q.size()];
      for (const LocalXY& v : p)
        best = std::min(best, SegmentDistance({v.east, v.north}, {s0.east, s0.north}, {s1.east, s1.north}));
      if (!pass)
        for (size_t j = 0; j < p.size(); ++j)
          if (SegmentsCross(s0, s1, p[j], p[(j + 1) % p.size()])) return 0;
    }
  }
  return best;
}

void RandomObject(int cls, cv::RNG& rng, SeabedObject* o) {
  o->class_id = cls;
  o->angle_rad = rng.uniform(0.0, 2 * M_PI);
  o->shape_seed = static_cast<uint64_t>(rng.next()) << 32 | rng.next();
  switch (cls) {
    case kTyre:
      o->length_m = o->width_m = rng.uniform(0.5, 1.0);
      o->height_m = 0.2 * o->length_m;
      break;
    case kCrate:
      o->length_m = rng.uniform(0.4, 1.2);
      o->width_m = o->length_m * rng.uniform(0.55, 1.0);
      o->height_m = 0.6 * o->width_m;
      break;
    case kPipe:
      o->length_m = rng.uniform(1.5, 3.0);
      o->width_m = rng.uniform(0.15, 0.4);
      o->height_m = o->width_m;
      break;
    case kAnchor:
      o->length_m = rng.uniform(0.5, 1.5);
      o->width_m = 0.62 * o->length_m;
      o->height_m = 0.06 * o->length_m;
      break;
    case kDrum: {  // a 200-litre drum: 0.6 m across, 0.9 m long
      o->standing = rng.uniform(0.0, 1.0) < 0.35;
      const double diameter = rng.uniform(0.57, 0.61), length = rng.uniform(0.86, 0.92);
      o->length_m = o->standing ? diameter : length;
      o->width_m = diameter;
      o->height_m = o->standing ? length : diameter;
      break;
    }
    case kRockRing:
      o->length_m = o->width_m = rng.uniform(0.5, 1.0);
      o->height_m = 0.12 * o->length_m;
      break;
    case kPipePiece:
      o->length_m = rng.uniform(0.25, 0.6);
      o->width_m = rng.uniform(0.15, 0.35);
      o->height_m = o->width_m;
      break;
    case kDarkRock:
      o->length_m = rng.uniform(0.4, 0.9) / 1.15;
      o->width_m = o->length_m;
      o->height_m = 0.4 * o->length_m;
      break;
    default:
      o->length_m = rng.uniform(0.2, 0.8) / 1.15;  // outline harmonics widen it by up to ~15 %
      o->width_m = o->length_m;
      o->height_m = 0.45 * o->length_m;
  }
}

// Three box blurs: a cheap Gaussian of about `sigma_px`, whatever its size.
void SoftBlur(cv::Mat1f& m, double sigma_px) {
  const int k = std::max(1, static_cast<int>(std::lround(sigma_px * 1.2))) * 2 + 1;
  for (int i = 0; i < 3; ++i) cv::blur(m, m, cv::Size(k, k));
}

void PaintOne(const SeabedObject& o, SeabedTexture* tex) {
  const Shape shape(o);
  const double res = tex->res_m;
  // Sediment hides the lowest `buried_fraction` of the object: the shadow falls from what shows.
  const double visible_m = o.height_m * (1 - o.buried_fraction);
  const double shadow_m = 0.8 * visible_m + 0.02, blur_m = 0.25 * visible_m + 0.01;
  const double margin_m = shadow_m + 3 * blur_m + 2 * res;
  const int c0 = static_cast<int>(std::floor(tex->Column(o.centre_east_m - o.box_width_m / 2 - margin_m)));
  const int c1 = static_cast<int>(std::ceil(tex->Column(o.centre_east_m + o.box_width_m / 2 + margin_m)));
  const int r0 = static_cast<int>(std::floor(tex->Row(o.centre_north_m + o.box_height_m / 2 + margin_m)));
  const int r1 = static_cast<int>(std::ceil(tex->Row(o.centre_north_m - o.box_height_m / 2 - margin_m)));
  const cv::Rect roi = cv::Rect(c0, r0, c1 - c0 + 1, r1 - r0 + 1) & cv::Rect(0, 0, tex->image.cols, tex->image.rows);
  if (roi.empty()) return;

  // Height, mask and albedo sampled at pixel centres in the object frame.
  cv::Mat1f height(roi.size(), 0.f), mask(roi.size(), 0.f), albedo(roi.size(), 0.f);
  const double ca = std::cos(o.angle_rad), sa = std::sin(o.angle_rad);
  cv::parallel_for_(cv::Range(0, roi.height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const double north = tex->north_max - (roi.y + y + 0.5) * res - o.ref_north_m;
      for (int x = 0; x < roi.width; ++x) {
        const double east = tex->east_min + (roi.x + x + 0.5) * res - o.ref_east_m;
        float h = 0, a = 0;
        if (shape.Sample(ca * east + sa * north, -sa * east + ca * north, &h, &a)) {
          height(y, x) = h;
          mask(y, x) = 1;
          albedo(y, x) = a;
        }
      }
    }
  });
  if (o.buried_fraction > 0) {
    // Of the body's own highest point (an anchor's shank stands lower than its height_m).
    double top = 0;
    cv::minMaxLoc(height, nullptr, &top);
    height -= static_cast<float>(o.buried_fraction * top);
    cv::max(height, 0.0, height);
    mask.setTo(0.f, height <= 0);
    albedo.setTo(0.f, height <= 0);
  }
  // Surface detail: fine grain and, for rocks, mottling.
  cv::RNG rng(o.shape_seed ^ 0xde7a11);
  cv::Mat1f grain(roi.size());
  const bool stony = IsRock(o.class_id) || o.class_id == kRockRing;
  rng.fill(grain, cv::RNG::NORMAL, 0, stony ? 0.22 : 0.1);
  cv::GaussianBlur(grain, grain, cv::Size(), std::max(1.0, 0.004 / res));
  if (stony || o.class_id == kDrum) {  // rocks mottled at 5 cm, drums with rust blotches at 8 cm
    const double cell_m = o.class_id == kDrum ? 0.08 : 0.05;
    cv::Mat1f coarse(std::max(2, static_cast<int>(roi.height * res / cell_m)),
                     std::max(2, static_cast<int>(roi.width * res / cell_m)));
    rng.fill(coarse, cv::RNG::NORMAL, 0, o.class_id == kDrum ? 0.3 : 0.25);
    cv::Mat1f up;
    cv::resize(coarse, up, roi.size(), 0, 0, cv::INTER_CUBIC);
    grain += up;
  }
  // Lambert shading, light from the north-west and above; x east, y south.
  cv::Mat1f smooth = height.clone(), hx, hy;
  cv::GaussianBlur(smooth, smooth, cv::Size(), 1.5);
  cv::Sobel(smooth, hx, CV_32F, 1, 0, 3, 1.0 / (8 * res));
  cv::Sobel(smooth, hy, CV_32F, 0, 1, 3, 1.0 / (8 * res));
  const cv::Vec3f light = cv::normalize(cv::Vec3f(-1.f, -1.f, 1.6f));
  // Soft shadow: the mask moved away from the light and blurred.
  cv::Mat1f shadow(roi.size(), 0.f);
  const int shift = static_cast<int>(std::lround(shadow_m / res / std::sqrt(2.0)));
  if (shift < roi.width && shift < roi.height)
    mask(cv::Rect(0, 0, roi.width - shift, roi.height - shift))
        .copyTo(shadow(cv::Rect(shift, shift, roi.width - shift, roi.height - shift)));
  SoftBlur(shadow, blur_m / res);
  cv::Mat1f soft_mask = mask.clone();
  cv::GaussianBlur(soft_mask, soft_mask, cv::Size(), 0.7);  // anti-aliased edges
  if (o.buried_fraction > 0) {
    // Sediment thins out up the body (over its lowest 15 % of height) and dusts the rest.
    double top = 0;
    cv::minMaxLoc(height, nullptr, &top);
    cv::Mat1f cover = height * static_cast<float>(1 / (0.15 * top + 0.005));
    cv::min(cover, 1.0, cover);
    cv::GaussianBlur(cover, cover, cv::Size(), 0.7);
    soft_mask = soft_mask.mul(cover) * static_cast<float>(1 - 0.3 * o.buried_fraction);
  }

  const double full = tex->image.depth() == CV_16U ? 65535.0 : 255.0;
  const int ch = tex->image.channels();
  cv::Mat patch;
  tex->image(roi).convertTo(patch, CV_MAKETYPE(CV_32F, ch));
  const cv::Vec3f colour = kColour[o.class_id];  // NOLINT: class_id < kKindCount
  const float base = kAlbedo[o.class_id];
  for (int y = 0; y < roi.height; ++y) {
    float* p = patch.ptr<float>(y);
    for (int x = 0; x < roi.width; ++x) {
      const float m = soft_mask(y, x), dark = 1 - 0.55f * shadow(y, x) * (1 - m);
      const cv::Vec3f n = cv::normalize(cv::Vec3f(-hx(y, x), -hy(y, x), 1.f));
      const float shade = std::clamp(n.dot(light) / light[2], 0.15f, 1.7f);
      const float a = (mask(y, x) > 0 ? albedo(y, x) : 1.f) * base * shade * (1 + grain(y, x));
      for (int c = 0; c < ch; ++c) {
        const float body = static_cast<float>(full) * a * (ch == 3 ? colour[c] : 1.f);
        const float v = p[x * ch + c] * dark * (1 - m) + body * m;
        p[x * ch + c] = std::clamp(v, static_cast<float>(0.02 * full), static_cast<float>(0.98 * full));
      }
    }
  }
  patch.convertTo(tex->image(roi), tex->image.type());
}

// Places `count` objects of `kinds` in turn, away from `placed` (which they join). `noun`
// and `option` name them in the error.
void PlaceInTurn(int count, const std::vector<int>& kinds, const std::vector<cv::Rect2d>& frame_bounds_m, cv::RNG& rng,
                 double min_gap_m, const char* noun, const std::string& option, std::vector<SeabedObject>* all) {
  std::vector<SeabedObject>& placed = *all;
  if (frame_bounds_m.empty()) throw InputError("", 0, option, "there are no frames to place objects under");
  cv::Rect2d area = frame_bounds_m[0];
  for (const cv::Rect2d& r : frame_bounds_m) area |= r;
  // A frame's ground bounds hold its whole footprint, which tilt and lens distortion bend
  // inwards: only their inner 84 % counts as seen.
  auto covered = [&](double e, double n) {
    for (const cv::Rect2d& r : frame_bounds_m) {
      const double me = 0.08 * r.width, mn = 0.08 * r.height;
      if (e >= r.x + me && e <= r.x + r.width - me && n >= r.y + mn && n <= r.y + r.height - mn) return true;
    }
    return false;
  };
  constexpr int kTries = 4000;
  for (int i = 0; i < count; ++i) {
    bool ok = false;
    for (int t = 0; t < kTries && !ok; ++t) {
      SeabedObject o;
      RandomObject(kinds[i % kinds.size()], rng, &o);
      Derive(&o);  // at the origin first: where is its box centre?
      const double e = rng.uniform(area.x, area.x + area.width), n = rng.uniform(area.y, area.y + area.height);
      o.ref_east_m = e - o.centre_east_m, o.ref_north_m = n - o.centre_north_m;
      Derive(&o);
      const double hw = o.box_width_m / 2, hh = o.box_height_m / 2;
      if (!covered(e - hw, n - hh) || !covered(e + hw, n - hh) || !covered(e - hw, n + hh) || !covered(e + hw, n + hh))
        continue;
      ok = true;
      for (const SeabedObject& p : placed) {
        const double reach = std::hypot(hw, hh) + std::hypot(p.box_width_m, p.box_height_m) / 2 + min_gap_m;
        if (std::hypot(p.centre_east_m - e, p.centre_north_m - n) >= reach) continue;
        if (PolygonGap(o.footprint_m, p.footprint_m) < min_gap_m) {
          ok = false;
          break;
        }
      }
      if (ok) placed.push_back(o);
    }
    if (!ok) {
      char msg[256];
      std::snprintf(msg, sizeof msg,
                    "only %d of %d %s fit %.1f m apart inside the surveyed area (%.1f x %.1f m); use fewer "
                    "%s or a larger survey (--frames)",
                    i, count, noun, min_gap_m, area.width, area.height, option.c_str());
      throw InputError("", 0, option, msg);
    }
  }
}

}  // namespace

bool SeabedObject::negative() const {
  return class_id >= kClassCount;
}

const std::string& SeabedObject::class_name() const {
  return negative() ? ClutterKinds().at(class_id - kClassCount) : SimulatedObjectClasses().at(class_id);
}

const std::vector<std::string>& SeabedObjectClasses() {
  static const std::vector<std::string> names = {"tyre", "crate", "pipe", "anchor", "rock"};
  return names;
}

const std::vector<std::string>& SimulatedObjectClasses() {
  static const std::vector<std::string> names = {"tyre", "crate", "pipe", "anchor", "rock", "drum"};
  return names;
}

const std::vector<std::string>& ClutterKinds() {
  static const std::vector<std::string> names = {"rock_ring", "pipe_piece", "dark_rock"};
  return names;
}

std::vector<int> ParseObjectClasses(const std::string& list, const std::string& option) {
  const std::vector<std::string>& names = SimulatedObjectClasses();
  std::vector<int> ids;
  size_t start = 0;
  while (start <= list.size()) {
    const size_t end = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, end - start);
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end())
      throw InputError("", 0, option,
                       "unknown class '" + name.substr(0, 100) + "'; expected a comma-separated list of " +
                           "tyre, crate, pipe, anchor, rock, drum");
    const int id = static_cast<int>(it - names.begin());
    if (std::find(ids.begin(), ids.end(), id) != ids.end())
      throw InputError("", 0, option, "class '" + name + "' is listed twice");
    ids.push_back(id);
    start = end + 1;
  }
  return ids;
}

std::vector<SeabedObject> PlaceSeabedObjects(int count, const std::vector<cv::Rect2d>& frame_bounds_m, uint64_t seed,
                                             double min_gap_m, const std::vector<int>& class_ids) {
  if (count < 0) throw InputError("", 0, "--objects", "expected a number of objects >= 0");
  std::vector<SeabedObject> placed;
  if (count == 0) return placed;
  std::vector<int> kinds = class_ids;
  if (kinds.empty())
    for (int k = 0; k < kShippedClasses; ++k) kinds.push_back(k);
  for (int k : kinds)
    if (k < 0 || k >= kClassCount) throw InputError("", 0, "--object-classes", "class id out of range");
  // The random stream of the five-class surveys: a seed's objects stay where they were.
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ull + 0x0b1ec75ull);
  PlaceInTurn(count, kinds, frame_bounds_m, rng, min_gap_m, "objects", "--objects", &placed);
  return placed;
}

std::vector<SeabedObject> PlaceClutter(int count, const std::vector<cv::Rect2d>& frame_bounds_m, uint64_t seed,
                                       const std::vector<SeabedObject>& objects, double min_gap_m) {
  if (count < 0) throw InputError("", 0, "--clutter", "expected a number of clutter pieces >= 0");
  if (count == 0) return {};
  std::vector<SeabedObject> all = objects;
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ull + 0xc1a77e4ull);
  PlaceInTurn(count, {kRockRing, kPipePiece, kDarkRock}, frame_bounds_m, rng, min_gap_m, "clutter pieces", "--clutter",
              &all);
  return std::vector<SeabedObject>(all.begin() + static_cast<std::ptrdiff_t>(objects.size()), all.end());
}

void PaintSeabedObjects(const std::vector<SeabedObject>& objects, SeabedTexture* texture) {
  for (const SeabedObject& o : objects) PaintOne(o, texture);
}

void SaveObjectsTruth(const std::vector<SeabedObject>& objects, const LocalFrame& frame, const std::string& truth_dir) {
  std::filesystem::create_directories(truth_dir);
  const std::string csv_path = truth_dir + "/objects.csv", json_path = truth_dir + "/objects.json";
  std::ofstream csv(csv_path);
  csv << "class,lat,lon,x_m,y_m,size_m\n";
  nlohmann::json list = nlohmann::json::array(), negatives = nlohmann::json::array();
  bool new_classes = false;  // a class the shipped model does not know
  for (const SeabedObject& o : objects) {
    const std::string& name = o.class_name();
    const LatLon ll = frame.ToLatLon({o.centre_east_m, o.centre_north_m});
    if (!o.negative()) {
      char line[256];
      std::snprintf(line, sizeof line, "%s,%.9f,%.9f,%.4f,%.4f,%.4f\n", name.c_str(), ll.lat, ll.lon, o.centre_east_m,
                    o.centre_north_m, o.size_m());
      csv << line;
    }
    nlohmann::json metres = nlohmann::json::array(), ring = nlohmann::json::array();
    for (size_t k = 0; k <= o.footprint_m.size(); ++k) {  // closed rings
      const LatLon q = frame.ToLatLon(o.footprint_m[k % o.footprint_m.size()]);
      metres.push_back({o.footprint_m[k % o.footprint_m.size()].east, o.footprint_m[k % o.footprint_m.size()].north});
      ring.push_back({q.lon, q.lat});
    }
    nlohmann::json item = {{"class", name},
                           {"class_id", o.class_id},
                           {"lat", ll.lat},
                           {"lon", ll.lon},
                           {"x_m", o.centre_east_m},
                           {"y_m", o.centre_north_m},
                           {"size_m", o.size_m()},
                           {"box_m", {o.box_width_m, o.box_height_m}},
                           {"angle_deg", o.angle_rad * 180 / M_PI},
                           {"footprint_m", metres},
                           {"footprint_lonlat", ring}};
    // Keys only where they say something, so the five-class truth stays as it was.
    if (o.class_id == kDrum) item["pose"] = o.standing ? "standing" : "lying";
    if (o.buried_fraction > 0) item["buried_fraction"] = o.buried_fraction;
    if (o.negative()) {
      item["negative"] = true;
      negatives.push_back(item);
    } else {
      new_classes |= o.class_id >= kShippedClasses;
      list.push_back(item);
    }
  }
  if (!csv) throw InputError(csv_path, 0, "", "cannot write the object truth");
  std::ofstream json(json_path);
  nlohmann::json truth = {{"origin", {frame.origin().lat, frame.origin().lon}},
                          {"classes", new_classes ? SimulatedObjectClasses() : SeabedObjectClasses()},
                          {"objects", list}};
  if (!negatives.empty()) truth["negatives"] = negatives;
  json << truth.dump(2) << "\n";
  if (!json) throw InputError(json_path, 0, "", "cannot write the object truth");
}

}  // namespace seamap
