// seed_detections MISSION [--stereo]: publishes a few recogniser detections
// into a built mission through DetectionRegistry::Publish (what a recogniser
// calls), for the console's browser tests: classes tyre, crate and pipe with
// scores 0.45-0.95 at the centres of photos, each seen by three photos.
// --stereo: one object located by stereo instead ("manifold", heading 123.7,
// 41.2 m deep, sigma 12.3 mm, at the centre of the sixth photo). Prints the ids, one per line.
#include <cstdio>
#include <cstring>
#include <exception>

#include "core/tiles/mbtiles_store.h"
#include "server/detection_registry.h"

int main(int argc, char** argv) {
  using namespace seamap;
  const bool stereo = argc == 3 && std::strcmp(argv[2], "--stereo") == 0;
  if (argc != 2 && !stereo) {
    std::fprintf(stderr, "usage: seed_detections MISSION.mbtiles [--stereo]\n");
    return 2;
  }
  try {
    MBTilesStore store(argv[1]);
    const auto frames = store.Frames();
    if (frames.size() < 12) throw std::runtime_error("the mission needs at least 12 frames");
    server::DetectionRegistry registry(&store, nullptr);
    registry.Load(store);
    if (stereo) {
      const FrameRecord& f = frames[5];
      Detection d;
      d.class_name = "manifold";
      d.source = "stereo";
      d.model = "manifold.json";
      d.position = {(f.footprint[0].lat + f.footprint[2].lat) / 2, (f.footprint[0].lon + f.footprint[2].lon) / 2};
      d.heading_deg = 123.7;
      d.depth_m = 41.2;
      d.sigma_m = 0.0123;  // its uncertainty, as stereo location stores it
      d.time_s = f.time_s;
      server::PublishOptions options;
      options.model_classes = {"manifold"};
      for (int64_t id : registry.Publish({d}, options).ids) std::printf("%lld\n", static_cast<long long>(id));
      return 0;
    }
    const char* classes[] = {"tyre", "crate", "pipe", "tyre", "crate"};
    const double scores[] = {0.95, 0.8, 0.65, 0.5, 0.45};
    std::vector<Detection> batch;
    for (int i = 0; i < 5; ++i) {
      const FrameRecord& f = frames[2 + 2 * i];
      Detection d;
      d.class_name = classes[i];
      d.score = scores[i];
      d.model = "seamap-tiles.onnx@e2e0";
      d.position = {(f.footprint[0].lat + f.footprint[2].lat) / 2, (f.footprint[0].lon + f.footprint[2].lon) / 2};
      d.size_m = std::array<double, 2>{0.6, 0.4};
      d.level = 25;
      d.levels = {25};
      d.frames = {f.id, f.id - 1, f.id + 1};
      d.frame_id = f.id;
      d.time_s = f.time_s;
      batch.push_back(d);
    }
    server::PublishOptions options;
    options.model_classes = {"tyre", "crate", "pipe", "anchor", "rock"};
    for (int64_t id : registry.Publish(batch, options).ids) std::printf("%lld\n", static_cast<long long>(id));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "seed_detections: %s\n", e.what());
    return 1;
  }
  return 0;
}
