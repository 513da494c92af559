#pragma once
// The recogniser on a finished map (spec detections-on-tiles): what `seamap
// detect` runs. Searches the map's tiles with a YOLO model, one network per
// thread, merges what was found and stores it in the mission (source
// "recogniser"), replacing the recogniser's earlier objects.
#include <optional>
#include <string>
#include <vector>

#include "core/detect/detection_run.h"
#include "core/detect/recognised_object.h"

namespace seamap {

struct ObjectDetectionOptions {
  std::string map_path;
  std::string model_path;                 // ONNX, v5 or v8 layout
  std::string classes_path;               // class names, one per line ("": the model's metadata)
  std::optional<std::vector<int>> zooms;  // levels to search (none: the model's default zooms)
  std::optional<float> min_score;         // none: the model's own
  bool keep_cut_views = false;            // --keep-cut-views (level_rule.h)
  std::string layer = "raw";              // raw | enhanced
  int threads = 1;                        // windows searched at once, one network each
  bool quiet = false;                     // no progress bar
  // InputError naming the option that does not fit (--threads, --layer).
  void Check() const;
};

struct ObjectDetectionResult {
  std::vector<RecognisedObject> objects;  // as stored in the mission
  DetectStats stats;
};

// Checks the options, then the model (before the map is opened), then the
// map; InputError naming what does not fit. The search line, warnings and
// the progress bar go to stderr.
ObjectDetectionResult DetectObjects(const ObjectDetectionOptions& options);

}  // namespace seamap
