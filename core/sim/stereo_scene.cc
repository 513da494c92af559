#include "core/sim/stereo_scene.h"

#include <cmath>
#include <random>

#include "core/sim/seabed_relief.h"

namespace seamap {
namespace {

uint32_t Hash(int32_t x, int32_t y, int32_t z, uint32_t seed) {
  uint32_t h = seed * 0x9E3779B9u;
  h ^= static_cast<uint32_t>(x) * 0x85EBCA6Bu;
  h = (h << 13) | (h >> 19);
  h ^= static_cast<uint32_t>(y) * 0xC2B2AE35u;
  h = (h << 17) | (h >> 15);
  h ^= static_cast<uint32_t>(z) * 0x27D4EB2Fu;
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return h;
}

float Fade(float t) {
  return t * t * t * (t * (t * 6 - 15) + 10);
}

// Multi-octave noise, roughly in [-1, 1].
float Fbm(const Eigen::Vector3d& p, double frequency, int octaves, uint32_t seed) {
  float sum = 0, amplitude = 1, norm = 0;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * ValueNoise3(p * frequency, seed + 101 * o);
    norm += amplitude;
    amplitude *= 0.55f;
    frequency *= 2.03;
  }
  return sum / norm;
}

void AddTriangle(std::vector<SceneTriangle>* t, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                 const Eigen::Vector3d& c, SceneMaterial m) {
  t->push_back({a, b, c, m});
}

void AddQuad(std::vector<SceneTriangle>* t, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
             const Eigen::Vector3d& c, const Eigen::Vector3d& d, SceneMaterial m) {
  AddTriangle(t, a, b, c, m);
  AddTriangle(t, a, c, d, m);
}

// An axis-aligned box; its bottom face is left out when it rests on the seabed.
void AddBox(std::vector<SceneTriangle>* t, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, SceneMaterial m) {
  const auto v = [&](int i) {
    return Eigen::Vector3d(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  };
  AddQuad(t, v(4), v(5), v(7), v(6), m);  // top
  if (lo.z() > 1e-9) AddQuad(t, v(0), v(2), v(3), v(1), m);
  AddQuad(t, v(0), v(1), v(5), v(4), m);  // y = lo
  AddQuad(t, v(2), v(6), v(7), v(3), m);  // y = hi
  AddQuad(t, v(0), v(4), v(6), v(2), m);  // x = lo
  AddQuad(t, v(1), v(3), v(7), v(5), m);  // x = hi
}

}  // namespace

float ValueNoise3(const Eigen::Vector3d& p, uint32_t seed) {
  const double fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
  const int32_t x = static_cast<int32_t>(fx), y = static_cast<int32_t>(fy), z = static_cast<int32_t>(fz);
  const float tx = Fade(static_cast<float>(p.x() - fx)), ty = Fade(static_cast<float>(p.y() - fy)),
              tz = Fade(static_cast<float>(p.z() - fz));
  const auto h = [&](int dx, int dy, int dz) {
    return static_cast<float>(Hash(x + dx, y + dy, z + dz, seed) & 0xFFFFFF) / 8388607.5f - 1;
  };
  const auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  const float x00 = lerp(h(0, 0, 0), h(1, 0, 0), tx), x10 = lerp(h(0, 1, 0), h(1, 1, 0), tx);
  const float x01 = lerp(h(0, 0, 1), h(1, 0, 1), tx), x11 = lerp(h(0, 1, 1), h(1, 1, 1), tx);
  return lerp(lerp(x00, x10, ty), lerp(x01, x11, ty), tz);
}

double StereoScene::SeabedZ(double x_m, double y_m) const {
  if (!relief) return 0;
  // The mesh's own triangles (Plane), not the grid's bilinear surface.
  double row = 0, col = 0;
  relief->CellOf({x_m, y_m}, &row, &col);
  if (!(row >= 0 && col >= 0 && row < relief->rows() - 1 && col < relief->cols() - 1)) return 0;
  const int r = static_cast<int>(row), c = static_cast<int>(col);
  const double fr = row - r, fc = col - c;
  const cv::Mat1f& h = relief->height_m;
  const double a = h(r, c), b = h(r, c + 1), cc = h(r + 1, c + 1), d = h(r + 1, c);
  return fc >= fr ? a + fc * (b - a) + fr * (cc - b) : a + fr * (d - a) + fc * (cc - d);
}

StereoScene StereoScene::Plane(const StereoSceneOptions& options) {
  StereoScene scene;
  scene.seed_ = static_cast<uint32_t>(options.seed);
  scene.object_texture_ = options.object_texture;
  if (options.relief_rms_m > 0) {
    // The simulator's relief, its mesh a quad per cell between cell centres.
    SeabedReliefOptions relief;
    relief.rms_m = options.relief_rms_m;
    relief.cell_m = options.relief_cell_m;
    const double size = options.seabed_size_m;
    const HeightGrid grid = MakeSeabedRelief(relief, {-size / 2, -size / 2, size, size}, 0, options.seed * 31 + 7);
    scene.relief = std::make_shared<const HeightGrid>(grid);
    const auto vertex = [&](int row, int col) {
      const LocalXY p = grid.CellCentre(row, col);
      return Eigen::Vector3d(p.east, p.north, grid.height_m(row, col));
    };
    for (int r = 0; r + 1 < grid.rows(); ++r)
      for (int c = 0; c + 1 < grid.cols(); ++c)
        AddQuad(&scene.triangles, vertex(r, c), vertex(r, c + 1), vertex(r + 1, c + 1), vertex(r + 1, c),
                SceneMaterial::kSeabed);
    scene.layout = cv::format("bare seabed, relief %.2f m rms", options.relief_rms_m);
    return scene;
  }
  // The seabed as 2 m tiles: small triangles keep the rasteriser's boxes tight.
  const double half = options.seabed_size_m / 2;
  const int tiles = std::max(1, static_cast<int>(std::ceil(options.seabed_size_m / 2)));
  const double step = options.seabed_size_m / tiles;
  for (int i = 0; i < tiles; ++i)
    for (int j = 0; j < tiles; ++j) {
      const double x0 = -half + i * step, y0 = -half + j * step;
      AddQuad(&scene.triangles, {x0, y0, 0}, {x0 + step, y0, 0}, {x0 + step, y0 + step, 0}, {x0, y0 + step, 0},
              SceneMaterial::kSeabed);
    }
  scene.layout = "bare seabed";
  return scene;
}

StereoScene StereoScene::Wellhead(const StereoSceneOptions& options) {
  StereoScene scene = Plane(options);
  if (!options.with_object) return scene;
  std::mt19937_64 rng(options.seed * 7919 + 17);
  const auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  std::vector<SceneTriangle>& t = scene.triangles;
  const auto steel = SceneMaterial::kSteel;

  // Frame: a square of beams on the seabed, four posts, a top ring of beams.
  const double half = uniform(1.05, 1.25), beam = 0.18, frame_top = uniform(1.1, 1.5);
  AddBox(&t, {-half, -half, 0}, {half, -half + beam, 0.25}, steel);
  AddBox(&t, {-half, half - beam, 0}, {half, half, 0.25}, steel);
  AddBox(&t, {-half, -half + beam, 0}, {-half + beam, half - beam, 0.25}, steel);
  AddBox(&t, {half - beam, -half + beam, 0}, {half, half - beam, 0.25}, steel);
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) {
      const double x = sx > 0 ? half - beam : -half, y = sy > 0 ? half - beam : -half;
      AddBox(&t, {x, y, 0.25}, {x + beam, y + beam, frame_top - beam}, steel);
      scene.check_points.push_back({"post", {x + beam / 2, y + beam / 2, frame_top}});
    }
  AddBox(&t, {-half, -half, frame_top - beam}, {half, -half + beam, frame_top}, steel);
  AddBox(&t, {-half, half - beam, frame_top - beam}, {half, half, frame_top}, steel);
  AddBox(&t, {-half, -half + beam, frame_top - beam}, {-half + beam, half - beam, frame_top}, steel);
  AddBox(&t, {half - beam, -half + beam, frame_top - beam}, {half, half - beam, frame_top}, steel);

  // Column and its cylindrical cover (24 facets), the top of the object.
  const double column = uniform(0.28, 0.36), radius = uniform(0.5, 0.65);
  const double cover_bottom = uniform(2.5, 2.75), cover_top = cover_bottom + uniform(0.25, 0.35);
  AddBox(&t, {-column, -column, 0}, {column, column, cover_bottom}, steel);
  const Eigen::Vector3d centre(0, 0, cover_top);
  for (int k = 0; k < 24; ++k) {
    const double a0 = 2 * M_PI * k / 24, a1 = 2 * M_PI * (k + 1) / 24;
    const Eigen::Vector3d p0(radius * std::cos(a0), radius * std::sin(a0), 0);
    const Eigen::Vector3d p1(radius * std::cos(a1), radius * std::sin(a1), 0);
    const Eigen::Vector3d lo(0, 0, cover_bottom), hi(0, 0, cover_top);
    AddQuad(&t, p0 + lo, p1 + lo, p1 + hi, p0 + hi, SceneMaterial::kCover);
    AddTriangle(&t, centre, p0 + hi, p1 + hi, SceneMaterial::kCover);
    AddTriangle(&t, p0 + lo, Eigen::Vector3d(0, 0, cover_bottom), p1 + lo, SceneMaterial::kCover);
  }
  scene.check_points.push_back({"cover-centre", centre});
  for (int k = 0; k < 4; ++k) {
    const double a = M_PI / 4 + k * M_PI / 2;
    scene.check_points.push_back({"cover-rim", {0.9 * radius * std::cos(a), 0.9 * radius * std::sin(a), cover_top}});
  }

  // Pipes from the column to the frame, at seed-dependent heights and sides.
  const double pipe = 0.07;
  const double z1 = uniform(0.5, 0.9), z2 = uniform(0.5, 0.9);
  AddBox(&t, {column, -pipe, z1 - pipe}, {half - beam, pipe, z1 + pipe}, SceneMaterial::kPipe);
  AddBox(&t, {-pipe, column, z2 - pipe}, {pipe, half - beam, z2 + pipe}, SceneMaterial::kPipe);
  scene.check_points.push_back({"pipe", {(column + half - beam) / 2, 0, z1 + pipe}});

  // Valve wheel on the top beam: a ring of eight spokes' rims (small boxes).
  const double vx = uniform(-0.5, 0.5), vr = 0.16;
  for (int k = 0; k < 8; ++k) {
    const double a = 2 * M_PI * k / 8;
    const double x = vx + vr * std::cos(a), y = -half + beam / 2 + vr * std::sin(a);
    AddBox(&t, {x - 0.03, y - 0.03, frame_top}, {x + 0.03, y + 0.03, frame_top + 0.06}, SceneMaterial::kValve);
  }
  scene.check_points.push_back({"valve", {vx, -half + beam / 2, frame_top + 0.06}});

  // Instrument boxes on the top ring, and a stencilled plate on one.
  const double bx = uniform(-0.6, 0.3), by = uniform(-0.6, 0.3);
  AddBox(&t, {bx, half - beam - 0.05, frame_top}, {bx + 0.45, half + 0.05, frame_top + 0.3}, steel);
  AddBox(&t, {half - beam - 0.05, by, frame_top}, {half + 0.05, by + 0.4, frame_top + 0.25}, steel);
  const double pz = frame_top + 0.3 + 0.002;
  AddQuad(&t, {bx + 0.05, half - beam, pz}, {bx + 0.4, half - beam, pz}, {bx + 0.4, half, pz}, {bx + 0.05, half, pz},
          SceneMaterial::kPlate);
  scene.check_points.push_back({"box", {bx + 0.225, half - beam / 2, frame_top + 0.3}});
  scene.check_points.push_back({"box", {half - beam / 2, by + 0.2, frame_top + 0.25}});
  scene.check_points.push_back({"base", {-half + beam / 2, 0, 0.25}});
  scene.check_points.push_back({"base", {0, half - beam / 2, 0.25}});

  scene.top_z_m = cover_top;
  scene.footprint_m = 2 * half;
  char text[160];
  std::snprintf(text, sizeof text, "wellhead %.2f m frame, %.2f m tall, cover r %.2f m", 2 * half, cover_top, radius);
  scene.layout = text;
  return scene;
}

float StereoScene::Albedo(SceneMaterial material, const Eigen::Vector3d& p) const {
  const uint32_t s = seed_ * 31 + static_cast<uint32_t>(material) * 1013;
  if (material == SceneMaterial::kSeabed) {
    // Sand and gravel: patches, ripples of growth, fine grain (mm to dm).
    const float coarse = Fbm(p, 0.8, 3, s);
    const float fine = Fbm(p, 18, 4, s + 7);
    const float blobs = std::max(0.0f, Fbm(p, 4, 2, s + 13) - 0.2f);
    return std::clamp(0.42f + 0.12f * coarse + 0.22f * fine - 0.5f * blobs, 0.03f, 1.0f);
  }
  float base = 0.5f;
  switch (material) {
    case SceneMaterial::kSteel:
      base = 0.45f;
      break;
    case SceneMaterial::kCover:
      base = 0.6f;
      break;
    case SceneMaterial::kPipe:
      base = 0.35f;
      break;
    case SceneMaterial::kValve:
      base = 0.75f;
      break;
    case SceneMaterial::kPlate:
      base = 0.85f;
      break;
    default:
      break;
  }
  const float tex = static_cast<float>(object_texture_);
  // Fouling and rust: blotches at cm to dm scale, grain at mm scale.
  const float blotch = Fbm(p, 9, 3, s + 3);
  const float grain = Fbm(p, 45, 3, s + 5);
  const float rust = std::max(0.0f, Fbm(p, 5, 2, s + 11) - 0.15f);
  float a = base + tex * (0.2f * blotch + 0.18f * grain - 0.6f * rust);
  if (material == SceneMaterial::kPlate) {
    // Stencilled marks: dark bars on a 4 cm grid, a few missing.
    const double u = p.x() * 25, v = p.y() * 25;
    if (Hash(static_cast<int32_t>(std::floor(u)), static_cast<int32_t>(std::floor(v)), 0, s) % 3 == 0 &&
        std::abs(u - std::floor(u) - 0.5) < 0.3)
      a *= 0.25f;
  }
  return std::clamp(a, 0.03f, 1.0f);
}

}  // namespace seamap
