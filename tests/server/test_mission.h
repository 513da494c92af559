#pragma once
// A small but real mission for the server tests: an MBTiles file with PNG
// tiles (main map and an "enhanced" layer), TileJSON metadata, frames with
// footprints and photos on disk, a track, one recogniser detection and one
// operator mark. Header-only: tests/server/*_test.cc are the only sources.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/tiles/mbtiles_store.h"
#include "core/tiles/tile_version.h"

namespace seamap::server::test {

// A real PNG of w x h pixels in one grey shade (different shades: different bytes).
inline std::vector<uint8_t> Png(int w, int h, int shade) {
  cv::Mat image(h, w, CV_8UC3, cv::Scalar(shade, 255 - shade, (shade * 7) % 256));
  std::vector<uint8_t> out;
  cv::imencode(".png", image, out);
  return out;
}

inline std::string Text(const std::vector<uint8_t>& bytes) {
  return std::string(bytes.begin(), bytes.end());
}

// The strong ETag the server must send for these bytes.
inline std::string QuotedVersion(const std::vector<uint8_t>& bytes) {
  return "\"" + TileVersionHex(TileVersion(bytes)) + "\"";
}

// A square footprint of +-half degrees around the centre (TL, TR, BR, BL).
inline FrameRecord MakeFrame(int id, LatLon centre, double half, const std::string& status,
                             const std::string& image_path) {
  FrameRecord f;
  f.id = id;
  f.image = std::filesystem::path(image_path).filename().string();
  f.image_path = image_path;
  f.time_s = 10.0 * id;
  f.position = centre;
  f.altitude_m = 2.5;
  f.depth_m = 30 + id;
  f.heading_deg = 90;
  f.pitch_deg = 1;
  f.roll_deg = -1;
  f.footprint = {LatLon{centre.lat + half, centre.lon - half}, LatLon{centre.lat + half, centre.lon + half},
                 LatLon{centre.lat - half, centre.lon + half}, LatLon{centre.lat - half, centre.lon - half}};
  f.status = status;
  return f;
}

struct TestMission {
  std::filesystem::path path;                    // the .mbtiles file
  std::map<TileId, std::vector<uint8_t>> tiles;  // main map
  std::map<TileId, std::vector<uint8_t>> enhanced;
  std::filesystem::path photo0, photo1;  // photos of frames 0 (PNG) and 1 (JPEG)
};

// Frames: 0 at (43, 5) and 1 at (43.0001, 5.0001), both used, footprints
// +-0.0002 deg; 2 rejected ("too dark") over the same place; 3 far away, its
// photo missing. Track: 5 points, seq 0..4. Detections: 1 (recogniser,
// "tyre", 0.8) and 2 (operator, "anchor", 1.0), last seq 2.
inline TestMission WriteTestMission(const std::filesystem::path& dir) {
  TestMission m;
  m.path = dir / "mission.mbtiles";
  m.tiles[TileId{3, 4, 2}] = Png(16, 16, 10);
  m.tiles[TileId{3, 4, 3}] = Png(16, 16, 20);
  m.tiles[TileId{2, 2, 1}] = Png(16, 16, 30);
  m.enhanced[TileId{3, 4, 2}] = Png(16, 16, 200);

  m.photo0 = dir / "photos" / "frame_0.png";
  m.photo1 = dir / "photos" / "frame_1.jpg";
  std::filesystem::create_directories(m.photo0.parent_path());
  cv::Mat photo(100, 200, CV_8UC3, cv::Scalar(40, 120, 200));
  cv::line(photo, {0, 0}, {199, 99}, cv::Scalar(255, 255, 255), 3);
  cv::imwrite(m.photo0.string(), photo);
  cv::imwrite(m.photo1.string(), photo);

  MBTilesStore store(m.path.string(), MBTilesStore::Mode::kCreate);
  for (const auto& [id, bytes] : m.tiles) store.PutTile(id, bytes);
  store.SetMetadata("name", "Test mission");
  store.SetMetadata("format", "png");
  store.SetMetadata("bounds", "4.999,42.999,5.011,43.011");
  store.SetMetadata("center", "5.005,43.005,17");
  store.SetMetadata("minzoom", "15");
  store.SetMetadata("maxzoom", "19");
  store.SetMetadata("attribution", "Test survey");
  store.SetMetadata("seamap_layers", "raw,enhanced");
  store.SetMetadata("seamap_state", "complete");
  store.SetMetadata("seamap_origin", "43,5");
  {
    auto layer = store.OpenLayer("enhanced");
    for (const auto& [id, bytes] : m.enhanced) layer->PutTile(id, bytes);
    layer->SetMetadata("name", "Test mission (enhanced)");
    layer->SetMetadata("format", "png");
    layer->SetMetadata("bounds", "4.999,42.999,5.011,43.011");
    layer->SetMetadata("center", "5.005,43.005,17");
    layer->SetMetadata("minzoom", "15");
    layer->SetMetadata("maxzoom", "19");
  }

  store.PutFrame(MakeFrame(0, {43.0, 5.0}, 0.0002, "used", m.photo0.string()));
  store.PutFrame(MakeFrame(1, {43.0001, 5.0001}, 0.0002, "used", m.photo1.string()));
  store.PutFrame(MakeFrame(2, {43.0, 5.0}, 0.0003, "too dark", (dir / "photos" / "frame_2.png").string()));
  store.PutFrame(MakeFrame(3, {43.01, 5.01}, 0.0002, "used", (dir / "photos" / "gone.png").string()));
  for (int i = 0; i < 5; ++i) {
    TrackPoint p;
    p.seq = i;
    p.time_s = 2.0 * i;
    p.position = {43.0 + 0.00005 * i, 5.0 + 0.00005 * i};
    p.depth_m = 30;
    store.PutTrackPoint(p);
  }

  Detection tyre;
  tyre.id = 1;
  tyre.class_name = "tyre";
  tyre.score = 0.8;
  tyre.position = {43.0001, 5.0001};
  tyre.source = "recogniser";
  tyre.frame_id = 0;
  tyre.time_s = 12.5;
  tyre.created = tyre.updated = "2024-05-01T10:00:00Z";
  tyre.seq = 1;
  store.PutDetection(tyre);
  Detection anchor;
  anchor.id = 2;
  anchor.class_name = "anchor";
  anchor.position = {43.0005, 5.0005};
  anchor.note = "seen by the diver";
  anchor.created = anchor.updated = "2024-05-01T10:05:00Z";
  anchor.seq = 2;
  store.PutDetection(anchor);
  store.Flush();
  return m;
}

}  // namespace seamap::server::test
