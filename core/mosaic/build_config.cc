#include "core/mosaic/build_config.h"

#include <fstream>
#include <set>

#include "core/util/error.h"

namespace seamap {
namespace {

using nlohmann::json;

template <typename T>
T Get(const json& value, const std::string& source, const std::string& key) {
  try {
    return value.get<T>();
  } catch (const json::exception&) {
    throw InputError(source, 0, key,
                     "expected a " +
                         std::string(std::is_same_v<T, std::string> ? "string"
                                     : std::is_same_v<T, bool>      ? "boolean"
                                                                    : "number") +
                         ", got " + value.dump());
  }
}

int GetInt(const json& v, const std::string& source, const std::string& key, int lo, int hi) {
  if (!v.is_number_integer()) throw InputError(source, 0, key, "expected a whole number, got " + v.dump());
  int x = v.get<int>();
  if (x < lo || x > hi)
    throw InputError(source, 0, key,
                     "expected " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + std::to_string(x));
  return x;
}

double GetPositive(const json& v, const std::string& source, const std::string& key) {
  if (!v.is_number()) throw InputError(source, 0, key, "expected a number, got " + v.dump());
  double x = v.get<double>();
  if (!(x > 0)) throw InputError(source, 0, key, "expected a number > 0, got " + v.dump());
  return x;
}

cv::Scalar ParseColor(const json& v, const std::string& source, const std::string& key) {
  // "#rrggbb" -> BGR scalar
  std::string s = Get<std::string>(v, source, key);
  unsigned rgb = 0;
  if (s.size() != 7 || s[0] != '#' || std::sscanf(s.c_str() + 1, "%6x", &rgb) != 1)
    throw InputError(source, 0, key, "expected a colour like \"#1a2b3c\", got \"" + s + "\"");
  return cv::Scalar(rgb & 0xff, (rgb >> 8) & 0xff, (rgb >> 16) & 0xff);
}

void ApplyNav(const json& nav, const std::string& source, NavReadOptions* out) {
  if (!nav.is_object()) throw InputError(source, 0, "navigation", "expected an object");
  for (auto& [key, v] : nav.items()) {
    const std::string k = "navigation." + key;
    if (key == "columns") {
      if (!v.is_object()) throw InputError(source, 0, k, "expected an object {canonical: name}");
      for (auto& [canon, name] : v.items()) out->columns[canon] = Get<std::string>(name, source, k + "." + canon);
    } else if (key == "utm_zone") {
      out->utm_zone = GetInt(v, source, k, 1, 60);
    } else if (key == "utm_north") {
      out->utm_north = Get<bool>(v, source, k);
    } else if (key == "origin") {
      if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
        throw InputError(source, 0, k, "expected [lat, lon]");
      out->origin = LatLon{v[0].get<double>(), v[1].get<double>()};
    } else {
      throw InputError(source, 0, k, "unknown key (known: columns, utm_zone, utm_north, origin)");
    }
  }
}

}  // namespace

void ApplyBuildConfig(const json& s, const std::string& source, BuildConfig* c) {
  if (!s.is_object()) throw InputError(source, 0, "", "expected a JSON object at the top level");
  for (auto& [key, v] : s.items()) {
    if (key == "name")
      c->name = Get<std::string>(v, source, key);
    else if (key == "attribution")
      c->attribution = Get<std::string>(v, source, key);
    else if (key == "tile_size") {
      c->tile_size = GetInt(v, source, key, 256, 512);
      if (c->tile_size != 256 && c->tile_size != 512) throw InputError(source, 0, key, "expected 256 or 512");
    } else if (key == "base_zoom")
      c->base_zoom = GetInt(v, source, key, 0, 30);
    else if (key == "min_zoom")
      c->min_zoom = GetInt(v, source, key, 0, 30);
    else if (key == "tile_format")
      c->encoding.format = ParseTileFormat(Get<std::string>(v, source, key), source);
    else if (key == "png_level")
      c->encoding.png_level = GetInt(v, source, key, 0, 9);
    else if (key == "jpeg_quality")
      c->encoding.jpeg_quality = GetInt(v, source, key, 1, 100);
    else if (key == "webp_quality")
      c->encoding.webp_quality = GetInt(v, source, key, 1, 101);
    else if (key == "background")
      c->encoding.background = ParseColor(v, source, key);
    else if (key == "feather_power")
      c->feather_power = GetPositive(v, source, key);
    else if (key == "seam_band") {
      if (!v.is_number() || !(v.get<double>() > 0 && v.get<double>() <= 1))
        throw InputError(source, 0, key, "expected a number in (0, 1], got " + v.dump());
      c->seam_band = v.get<double>();
    } else if (key == "blend_all_overlaps")
      c->blend_all_overlaps = Get<bool>(v, source, key);
    else if (key == "linger_frames")
      c->linger_frames = GetInt(v, source, key, 1, 100000);
    else if (key == "lookahead_frames")
      c->lookahead_frames = GetInt(v, source, key, 0, 1000000);
    else if (key == "defer_edge_tails")
      c->defer_edge_tails = Get<bool>(v, source, key);
    else if (key == "memory_cap_mb")
      c->memory_cap_mb = GetInt(v, source, key, 16, 1 << 20);
    else if (key == "batch_frames")
      c->batch_frames = GetInt(v, source, key, 1, 100000);
    else if (key == "batch_seconds") {
      if (!v.is_number() || v.get<double>() < 0)
        throw InputError(source, 0, key, "expected a number >= 0, got " + v.dump());
      c->batch_seconds = v.get<double>();
    } else if (key == "threads")
      c->threads = GetInt(v, source, key, 0, 256);
    else if (key == "live_tiles")
      c->live_tiles = Get<bool>(v, source, key);
    else if (key == "max_footprint_ratio")
      c->max_footprint_ratio = GetPositive(v, source, key);
    else if (key == "sixteen_bit_white")
      c->sixteen_bit_white = GetInt(v, source, key, 1, 65535);
    else if (key == "navigation")
      ApplyNav(v, source, &c->nav);
    else if (key == "enhance")
      c->enhance = v;
    else if (key == "server")
      c->server = v;
    else if (key == "layers") {
      c->layers = Get<std::string>(v, source, key);
      if (c->layers != "raw" && c->layers != "enhanced" && c->layers != "both")
        throw InputError(source, 0, key, "expected \"raw\", \"enhanced\" or \"both\", got \"" + c->layers + "\"");
    } else if (key.rfind("_", 0) == 0 || key == "comment") {
      // comments
    } else {
      throw InputError(source, 0, key, "unknown key");
    }
  }
  if (c->base_zoom && c->min_zoom && *c->min_zoom > *c->base_zoom)
    throw InputError(source, 0, "min_zoom", "must not exceed base_zoom");
}

BuildConfig LoadBuildConfig(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "", "cannot read the config file");
  json s;
  try {
    s = json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(path, 0, "", std::string("not valid JSON: ") + e.what());
  }
  BuildConfig c;
  ApplyBuildConfig(s, path, &c);
  return c;
}

}  // namespace seamap
