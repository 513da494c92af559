#include "core/mosaic/build_config.h"

#include <cmath>

#include "core/util/error.h"
#include "core/util/json_file.h"

namespace seamap {
namespace {

using nlohmann::json;

// Typed reads: the value's JSON type is checked here, its range by Check().
std::string String(const json& v, const std::string& source, const std::string& key) {
  if (!v.is_string()) throw InputError(source, 0, key, "expected a string, got " + v.dump());
  return v.get<std::string>();
}

bool Bool(const json& v, const std::string& source, const std::string& key) {
  if (!v.is_boolean()) throw InputError(source, 0, key, "expected a boolean, got " + v.dump());
  return v.get<bool>();
}

int Int(const json& v, const std::string& source, const std::string& key) {
  if (!v.is_number_integer() || v.get<int64_t>() < INT32_MIN || v.get<int64_t>() > INT32_MAX)
    throw InputError(source, 0, key, "expected a whole number, got " + v.dump());
  return v.get<int>();
}

double Number(const json& v, const std::string& source, const std::string& key) {
  if (!v.is_number()) throw InputError(source, 0, key, "expected a number, got " + v.dump());
  return v.get<double>();
}

void CheckRange(int value, int lo, int hi, const std::string& source, const std::string& key) {
  if (value < lo || value > hi)
    throw InputError(source, 0, key,
                     "expected " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + std::to_string(value));
}

void CheckPositive(double value, const std::string& source, const std::string& key) {
  if (!(value > 0)) throw InputError(source, 0, key, "expected a number > 0, got " + std::to_string(value));
}

cv::Scalar Colour(const json& v, const std::string& source, const std::string& key) {
  // "#rrggbb" -> BGR scalar
  const std::string s = String(v, source, key);
  unsigned rgb = 0;
  if (s.size() != 7 || s[0] != '#' || std::sscanf(s.c_str() + 1, "%6x", &rgb) != 1)
    throw InputError(source, 0, key, "expected a colour like \"#1a2b3c\", got \"" + s + "\"");
  return cv::Scalar(rgb & 0xff, (rgb >> 8) & 0xff, (rgb >> 16) & 0xff);
}

void ApplyNavigation(const json& nav, const std::string& source, NavReadOptions* out, NavigationSettings* settings) {
  if (!nav.is_object()) throw InputError(source, 0, "navigation", "expected an object");
  for (auto& [key, v] : nav.items()) {
    const std::string k = "navigation." + key;
    if (key == "columns") {
      if (!v.is_object()) throw InputError(source, 0, k, "expected an object {canonical: name}");
      for (auto& [canon, name] : v.items()) out->columns[canon] = String(name, source, k + "." + canon);
    } else if (key == "utm_zone") {
      out->utm_zone = Int(v, source, k);
      CheckRange(*out->utm_zone, 1, 60, source, k);
    } else if (key == "utm_north") {
      out->utm_north = Bool(v, source, k);
    } else if (key == "origin") {
      if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
        throw InputError(source, 0, k, "expected [lat, lon]");
      out->origin = LatLon{v[0].get<double>(), v[1].get<double>()};
    } else if (key == "angle_unit") {
      const std::string unit = String(v, source, k);
      if (unit != "degrees" && unit != "radians")
        throw InputError(source, 0, k, "expected \"degrees\" or \"radians\", got " + v.dump());
      out->angle_unit = unit == "radians" ? AngleUnit::kRadians : AngleUnit::kDegrees;
    } else if (key == "time_columns") {
      if (!v.is_object() || v.empty())
        throw InputError(source, 0, k,
                         "expected an object {part: column}, e.g. {\"date\": \"Date\", \"time\": \"UTC\"}");
      out->time_columns.clear();
      for (auto& [part, name] : v.items()) out->time_columns[part] = String(name, source, k + "." + part);
    } else if (key == "refine") {
      settings->refine = Bool(v, source, k);
    } else if (key == "noise_m") {
      settings->noise_m = Number(v, source, k);
    } else if (key == "drift_m_per_min") {
      settings->drift_m_per_min = Number(v, source, k);
    } else if (key == "heading_noise_deg") {
      settings->heading_noise_deg = Number(v, source, k);
    } else {
      throw InputError(source, 0, k,
                       "unknown key (known: columns, time_columns, angle_unit, utm_zone, utm_north, origin, refine, "
                       "noise_m, drift_m_per_min, heading_noise_deg)");
    }
  }
}

}  // namespace

void MapSettings::Check(const std::string& source) const {
  if (tile_size != 256 && tile_size != 512)
    throw InputError(source, 0, "tile_size", "expected 256 or 512, got " + std::to_string(tile_size));
  if (base_zoom) CheckRange(*base_zoom, 0, 30, source, "base_zoom");
  if (min_zoom) CheckRange(*min_zoom, 0, 30, source, "min_zoom");
  if (base_zoom && min_zoom && *min_zoom > *base_zoom)
    throw InputError(source, 0, "min_zoom", "must not exceed base_zoom");
  CheckRange(encoding.png_level, 0, 9, source, "png_level");
  CheckRange(encoding.jpeg_quality, 1, 100, source, "jpeg_quality");
  CheckRange(encoding.webp_quality, 1, 101, source, "webp_quality");
}

void BlendSettings::Check(const std::string& source) const {
  CheckPositive(feather_power, source, "feather_power");
  if (!(seam_band > 0 && seam_band <= 1))
    throw InputError(source, 0, "seam_band", "expected a number in (0, 1], got " + std::to_string(seam_band));
}

void BufferSettings::Check(const std::string& source) const {
  CheckRange(linger_frames, 1, 100000, source, "linger_frames");
  CheckRange(lookahead_frames, 0, 1000000, source, "lookahead_frames");
  CheckRange(memory_cap_mb, 16, 1 << 20, source, "memory_cap_mb");
  CheckRange(batch_frames, 1, 100000, source, "batch_frames");
  if (!(batch_seconds >= 0))
    throw InputError(source, 0, "batch_seconds", "expected a number >= 0, got " + std::to_string(batch_seconds));
  if (!(checkpoint_seconds >= 0))
    throw InputError(source, 0, "checkpoint_seconds",
                     "expected a number >= 0, got " + std::to_string(checkpoint_seconds));
}

void FrameSettings::Check(const std::string& source) const {
  CheckPositive(max_footprint_ratio, source, "max_footprint_ratio");
  CheckRange(sixteen_bit_white, 1, 65535, source, "sixteen_bit_white");
  CheckRange(max_image_pixels, 1, 1 << 30, source, "max_image_pixels");
}

void NavigationSettings::Check(const std::string& source) const {
  for (const auto& [value, key] : {std::pair{noise_m, "navigation.noise_m"},
                                   {drift_m_per_min, "navigation.drift_m_per_min"},
                                   {heading_noise_deg, "navigation.heading_noise_deg"}})
    if (!(value >= 0) || !std::isfinite(value))
      throw InputError(source, 0, key, "expected a number >= 0, got " + std::to_string(value));
}

void BuildConfig::Check(const std::string& source) const {
  map.Check(source);
  navigation.Check(source);
  nav.Check(source);
  blend.Check(source);
  buffer.Check(source);
  frames.Check(source);
  CheckRange(threads, 0, 256, source, "threads");
  if (layers != "raw" && layers != "enhanced" && layers != "both")
    throw InputError(source, 0, "layers", "expected \"raw\", \"enhanced\" or \"both\", got \"" + layers + "\"");
}

MemoryBudget MemoryBudget::Of(int memory_cap_mb) {
  const size_t cap = static_cast<size_t>(memory_cap_mb) << 20;
  return {cap / 8, cap / 8 * 5, cap / 16 * 3, cap / 16};
}

void ApplyBuildConfig(const json& s, const std::string& source, BuildConfig* c) {
  if (!s.is_object()) throw InputError(source, 0, "", "expected a JSON object at the top level");
  for (auto& [key, v] : s.items()) {
    if (key == "name")
      c->map.name = String(v, source, key);
    else if (key == "attribution")
      c->map.attribution = String(v, source, key);
    else if (key == "tile_size")
      c->map.tile_size = Int(v, source, key);
    else if (key == "base_zoom")
      c->map.base_zoom = Int(v, source, key);
    else if (key == "min_zoom")
      c->map.min_zoom = Int(v, source, key);
    else if (key == "tile_format")
      c->map.encoding.format = ParseTileFormat(String(v, source, key), source);
    else if (key == "png_level")
      c->map.encoding.png_level = Int(v, source, key);
    else if (key == "jpeg_quality")
      c->map.encoding.jpeg_quality = Int(v, source, key);
    else if (key == "webp_quality")
      c->map.encoding.webp_quality = Int(v, source, key);
    else if (key == "background")
      c->map.encoding.background = Colour(v, source, key);
    else if (key == "feather_power")
      c->blend.feather_power = Number(v, source, key);
    else if (key == "seam_band")
      c->blend.seam_band = Number(v, source, key);
    else if (key == "nadir_seams")
      c->blend.nadir_seams = Bool(v, source, key);
    else if (key == "blend_all_overlaps")
      c->blend.blend_all_overlaps = Bool(v, source, key);
    else if (key == "linger_frames")
      c->buffer.linger_frames = Int(v, source, key);
    else if (key == "lookahead_frames")
      c->buffer.lookahead_frames = Int(v, source, key);
    else if (key == "memory_cap_mb")
      c->buffer.memory_cap_mb = Int(v, source, key);
    else if (key == "batch_frames")
      c->buffer.batch_frames = Int(v, source, key);
    else if (key == "batch_seconds")
      c->buffer.batch_seconds = Number(v, source, key);
    else if (key == "checkpoint_seconds")
      c->buffer.checkpoint_seconds = Number(v, source, key);
    else if (key == "live_tiles")
      c->buffer.live_tiles = Bool(v, source, key);
    else if (key == "max_footprint_ratio")
      c->frames.max_footprint_ratio = Number(v, source, key);
    else if (key == "sixteen_bit_white")
      c->frames.sixteen_bit_white = Int(v, source, key);
    else if (key == "max_image_pixels")
      c->frames.max_image_pixels = Int(v, source, key);
    else if (key == "threads")
      c->threads = Int(v, source, key);
    else if (key == "navigation")
      ApplyNavigation(v, source, &c->nav, &c->navigation);
    else if (key == "terrain") {
      if (v.is_boolean()) {
        c->terrain = TerrainSettings{v.get<bool>(), ""};
      } else if (v.is_string() && !v.get<std::string>().empty()) {
        c->terrain = TerrainSettings{false, v.get<std::string>()};
      } else {
        throw InputError(source, 0, key, "expected true, false or a height model's file name");
      }
    } else if (key == "enhance")
      c->enhance = v;
    else if (key == "layers")
      c->layers = String(v, source, key);
    else if (key == "server")
      c->server = v;  // the server's to read (server/server_options.h)
    else if (key == "detect")
      c->detect = v;  // build/replay --detect's (cli/detect_setup.h)
    else if (key == "comment" || key.rfind("_", 0) == 0) {
      // comments
    } else
      throw InputError(source, 0, key, "unknown key");
  }
  c->Check(source);
}

BuildConfig LoadBuildConfig(const std::string& path) {
  BuildConfig c;
  ApplyBuildConfig(ReadJsonFile(path, "config file"), path, &c);
  return c;
}

}  // namespace seamap
