#include "core/sim/ground_truth.h"

#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/terrain/height_grid_io.h"
#include "core/util/error.h"
#include "core/util/json_file.h"

namespace seamap {
namespace {

double Number(const nlohmann::json& j, const std::string& key, const std::string& file) {
  if (!j.contains(key) || !j[key].is_number()) throw InputError(file, 0, key, "missing or not a number");
  return j[key].get<double>();
}

template <typename T>
cv::Vec3f Bilinear(const cv::Mat& img, double x, double y) {
  const int x0 = std::min(static_cast<int>(x), img.cols - 2 < 0 ? 0 : img.cols - 2);
  const int y0 = std::min(static_cast<int>(y), img.rows - 2 < 0 ? 0 : img.rows - 2);
  const int x1 = std::min(x0 + 1, img.cols - 1), y1 = std::min(y0 + 1, img.rows - 1);
  const double fx = x - x0, fy = y - y0;
  const int n = img.channels();
  cv::Vec3f out;
  for (int c = 0; c < 3; ++c) {
    const int ch = n == 1 ? 0 : c;
    const auto at = [&](int yy, int xx) { return static_cast<double>(img.ptr<T>(yy)[xx * n + ch]); };
    out[c] = static_cast<float>((1 - fy) * ((1 - fx) * at(y0, x0) + fx * at(y0, x1)) +
                                fy * ((1 - fx) * at(y1, x0) + fx * at(y1, x1)));
  }
  return out;
}

}  // namespace

GroundTruth GroundTruth::Load(const std::string& survey_dir) {
  const std::string json_path = survey_dir + "/truth/texture.json";
  const std::string png = survey_dir + "/truth/texture.png";
  nlohmann::json j = ReadJsonFile(json_path, "ground-truth georeference");
  GroundTruth t;
  if (!j.contains("origin") || !j["origin"].is_array() || j["origin"].size() != 2)
    throw InputError(json_path, 0, "origin", "expected [lat, lon]");
  t.origin = {j["origin"][0].get<double>(), j["origin"][1].get<double>()};
  t.res_m = Number(j, "res_m", json_path);
  t.east_min = Number(j, "east_min", json_path);
  t.north_max = Number(j, "north_max", json_path);
  if (!(t.res_m > 0)) throw InputError(json_path, 0, "res_m", "expected a positive resolution");
  t.image = cv::imread(png, cv::IMREAD_UNCHANGED);
  if (t.image.empty()) throw InputError(png, 0, "", "cannot read the ground-truth texture");
  if (t.image.cols != Number(j, "width", json_path) || t.image.rows != Number(j, "height", json_path))
    throw InputError(json_path, 0, "width", "does not match the size of texture.png");
  const std::string terrain = survey_dir + "/truth/terrain.tif";
  if (std::filesystem::exists(terrain)) t.terrain = ReadHeightGridGeotiff(terrain, t.origin);
  return t;
}

bool GroundTruth::Sample(LocalXY p, cv::Vec3f* value) const {
  const SeabedTexture tex = Texture();
  const double x = tex.Column(p.east), y = tex.Row(p.north);
  if (!(x >= 0 && y >= 0 && x <= image.cols - 1 && y <= image.rows - 1)) return false;
  *value = image.depth() == CV_16U ? Bilinear<uint16_t>(image, x, y) : Bilinear<uint8_t>(image, x, y);
  return true;
}

cv::Mat RenderTruth(const GroundTruth& truth, const cv::Mat& east_map, const cv::Mat& north_map) {
  CV_Assert(east_map.size() == north_map.size() && east_map.channels() == 1 && north_map.channels() == 1);
  // Local metres to texture pixel coordinates (centre convention).
  cv::Mat map_x, map_y;
  east_map.convertTo(map_x, CV_32F, 1 / truth.res_m, -truth.east_min / truth.res_m - 0.5);
  north_map.convertTo(map_y, CV_32F, -1 / truth.res_m, truth.north_max / truth.res_m - 0.5);
  cv::Mat out;
  cv::remap(truth.image, out, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  return out;
}

}  // namespace seamap
