#pragma once
// The recogniser during a build or replay (spec sect. 5): a TileConsumer
// that notes the windows holding each finished tile, and one worker thread
// that searches them from the store while the build goes on. It never
// blocks the builder: OnTileWritten only inserts window keys into a set. A
// tile finished again makes its windows due again (their boxes replaced), and
// a window holding a tile shown half-painted (live, not final) waits for it.
// Finish() searches every window changed since its last search, so the
// result equals `seamap detect` on the finished map.
#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "core/detect/detection_run.h"
#include "core/mosaic/tile_consumer.h"

namespace seamap {

class LiveDetector : public TileConsumer {
 public:
  // store: where the builder writes the tiles searched (it must outlive this).
  LiveDetector(const DetectSettings& settings, const TileStore* store);
  const YoloModelInfo& model() const { return *settings_.model; }
  ~LiveDetector() override;

  void OnTileWritten(const TileId& id, const cv::Mat& tile, uint64_t version, bool final) override;

  // A live view (replay): `found` is called on the worker, at most every
  // `every` while windows are being searched, with every object found so far
  // merged as Finish would merge them (frames from `frames`).
  using Found = std::function<void(const std::vector<RecognisedObject>&)>;
  void OnFound(Found found, std::function<std::vector<FrameRecord>()> frames, std::chrono::milliseconds every);

  // Call after the builder's Finish: searches what is still due and every
  // window of the map never searched (tiles of an earlier build: --append,
  // --resume), stops the worker, returns the merged objects. Rethrows a
  // worker's error.
  std::vector<RecognisedObject> Finish(const std::vector<FrameRecord>& frames);
  const DetectStats& stats() const { return searcher_.stats(); }
  double drain_seconds() const { return drain_s_; }  // Finish's wait for the queue
  int backlog_peak() const { return backlog_peak_; }

 private:
  void Work();
  bool Due(const WindowKey& w) const;  // call with mutex_ held

  DetectSettings settings_;
  const TileStore* store_;
  WindowSearcher searcher_;  // worker thread only (and Finish after the join)
  std::mutex mutex_;
  std::condition_variable wake_;
  std::map<WindowKey, std::chrono::steady_clock::time_point> dirty_;  // window -> last change
  std::set<TileId> live_;                                             // tiles whose latest version is not final
  bool finishing_ = false, stop_ = false;
  std::exception_ptr error_;
  Found found_;
  std::function<std::vector<FrameRecord>()> frames_;
  std::chrono::milliseconds every_{0};
  std::chrono::steady_clock::time_point last_found_{};
  double drain_s_ = 0;
  int backlog_peak_ = 0;
  std::thread worker_;
};

}  // namespace seamap
