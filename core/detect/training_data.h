#pragma once
// `seamap training-data MAP... --out DIR`: reviewed missions as YOLO training
// data (training_windows.h says which windows and boxes). Layout, which
// scripts/train_detector.py reads:
//   DIR/images/<mission>_z<z>_x<x>_y<y>.png   the window as composed (768 x 768 for 256 px tiles)
//   DIR/labels/<same>.txt                     "class_id cx cy w h" normalised, one line a label
//   DIR/manifest.json                         missions, classes, counts, every window's boxes
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace seamap {

struct TrainingDataOptions {
  std::vector<std::string> maps;
  std::string out_dir;
  bool overwrite = false;                 // --overwrite: replace images/, labels/, manifest.json of an existing --out
  std::string model_path;                 // its class names come first; its class sizes choose the levels
  std::optional<std::vector<int>> zooms;  // --zooms (default: the recogniser's)
  double empty_per_labelled = 1;          // --empty
  uint64_t seed = 1;                      // --seed: the empty windows' sample
  bool quiet = false;
  void Check() const;  // InputError naming the option
};

struct TrainingDataSummary {
  int windows = 0, labels = 0, negatives = 0, empty = 0, skipped = 0, ignored = 0;
  std::map<std::string, int> per_class;  // labels
  std::vector<std::string> classes;
};

TrainingDataSummary WriteTrainingData(const TrainingDataOptions& options);

}  // namespace seamap
