#include "core/mosaic/build_checkpointer.h"

#include <libdeflate.h>

#include <climits>
#include <cstring>
#include <future>
#include <memory>
#include <stdexcept>

namespace seamap {
namespace {

enum BlobKind { kSums = 0, kWeights = 1 };
constexpr char kSumsTag[4] = {'S', 'M', 'S', '1'}, kWeightsTag[4] = {'S', 'M', 'W', '1'};

// Byte planes (every value's first bytes, then its second bytes, ...): the
// high bytes of smooth sums and weights then compress well, the low ones as
// they can. libdeflate at its fastest level: a checkpoint is written often.
std::vector<uint8_t> Pack(const char (&tag)[4], const std::vector<const cv::Mat*>& planes) {
  size_t raw_size = 0;
  for (const cv::Mat* m : planes) raw_size += m->total() * m->elemSize();
  std::vector<uint8_t> raw(raw_size);
  size_t at = 0;
  for (const cv::Mat* m : planes) {
    CV_Assert(m->isContinuous());
    const size_t width = m->elemSize1(), n = m->total() * m->channels();
    const uint8_t* src = m->ptr<uint8_t>();
    for (size_t b = 0; b < width; ++b)
      for (size_t i = 0; i < n; ++i) raw[at + b * n + i] = src[i * width + b];
    at += n * width;
  }
  struct Free {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
  };
  thread_local std::unique_ptr<libdeflate_compressor, Free> compressor(libdeflate_alloc_compressor(1));
  if (!compressor) throw std::runtime_error("libdeflate: out of memory");
  std::vector<uint8_t> out(8 + libdeflate_deflate_compress_bound(compressor.get(), raw.size()));
  std::memcpy(out.data(), tag, 4);
  const uint32_t size = static_cast<uint32_t>(raw.size());
  std::memcpy(out.data() + 4, &size, 4);
  const size_t n =
      libdeflate_deflate_compress(compressor.get(), raw.data(), raw.size(), out.data() + 8, out.size() - 8);
  if (n == 0) throw std::runtime_error("libdeflate: cannot compress a checkpoint");
  out.resize(8 + n);
  return out;
}

void Unpack(const char (&tag)[4], const std::vector<uint8_t>& blob, const std::vector<cv::Mat*>& planes) {
  size_t raw_size = 0;
  for (const cv::Mat* m : planes) raw_size += m->total() * m->elemSize();
  uint32_t size = 0;
  if (blob.size() >= 8) std::memcpy(&size, blob.data() + 4, 4);
  if (blob.size() < 8 || std::memcmp(blob.data(), tag, 4) != 0 || size != raw_size)
    throw std::runtime_error("a checkpoint blob is not what this build saves");
  std::vector<uint8_t> raw(raw_size);
  std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> d(libdeflate_alloc_decompressor(),
                                                                                 libdeflate_free_decompressor);
  size_t got = 0;
  if (!d ||
      libdeflate_deflate_decompress(d.get(), blob.data() + 8, blob.size() - 8, raw.data(), raw.size(), &got) !=
          LIBDEFLATE_SUCCESS ||
      got != raw_size)
    throw std::runtime_error("a checkpoint blob is damaged");
  size_t at = 0;
  for (cv::Mat* m : planes) {
    const size_t width = m->elemSize1(), n = m->total() * m->channels();
    uint8_t* dst = m->ptr<uint8_t>();
    for (size_t b = 0; b < width; ++b)
      for (size_t i = 0; i < n; ++i) dst[i * width + b] = raw[at + b * n + i];
    at += n * width;
  }
}

nlohmann::json TileJson(const TileId& id, int64_t value) {
  return {id.z, id.x, id.y, value};
}

TileId TileOf(const nlohmann::json& j) {
  return {j.at(0).get<int>(), j.at(1).get<int>(), j.at(2).get<int>()};
}

}  // namespace

nlohmann::json BuildProgress::ToJson() const {
  nlohmann::json t = nlohmann::json::array(), k = nlohmann::json::array();
  for (const auto& [id, last] : tiles) t.push_back(TileJson(id, last));
  for (const auto& [id, stamp] : kept) k.push_back(TileJson(id, static_cast<int64_t>(stamp)));
  return {{"frame_index", frame_index},
          {"handover_index", handover_index},
          {"frames_total", frames_total},
          {"consumed", consumed},
          {"frame_id_offset", frame_id_offset},
          {"track_seq", track_seq},
          {"frames_used", frames_used},
          {"tiles_written", tiles_written},
          {"tile_bytes", tile_bytes},
          {"readbacks", readbacks},
          {"previous_state", previous_state},
          {"command", command},
          {"settings", settings},
          {"tiles", t},
          {"kept", k}};
}

BuildProgress BuildProgress::FromJson(const std::string& text) {
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    BuildProgress p;
    p.frame_index = j.at("frame_index");
    p.handover_index = j.at("handover_index");
    p.frames_total = j.at("frames_total");
    p.consumed = j.at("consumed");
    p.frame_id_offset = j.at("frame_id_offset");
    p.track_seq = j.at("track_seq");
    p.frames_used = j.at("frames_used");
    p.tiles_written = j.at("tiles_written");
    p.tile_bytes = j.at("tile_bytes");
    p.readbacks = j.at("readbacks");
    p.previous_state = j.at("previous_state");
    p.command = j.value("command", "");
    p.settings = j.at("settings");
    for (const auto& t : j.at("tiles")) p.tiles.push_back({TileOf(t), t.at(3).get<int>()});
    for (const auto& k : j.at("kept")) p.kept.push_back({TileOf(k), k.at(3).get<uint64_t>()});
    return p;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("the checkpoint is damaged: ") + e.what());
  }
}

std::vector<uint8_t> PackSums(const TileAccumulator& tile) {
  return Pack(kSumsTag, {&tile.weight_sums(), &tile.sums()});
}

std::pair<cv::Mat, cv::Mat> UnpackSums(const std::vector<uint8_t>& blob, int tile_size, int channels) {
  cv::Mat sums(tile_size, tile_size, CV_32FC(channels)), weights(tile_size, tile_size, CV_32F);
  Unpack(kSumsTag, blob, {&weights, &sums});
  return {sums, weights};
}

std::vector<uint8_t> PackWeights(const cv::Mat& weights) {
  return Pack(kWeightsTag, {&weights});
}

cv::Mat UnpackWeights(const std::vector<uint8_t>& blob, int tile_size) {
  cv::Mat weights(tile_size, tile_size, CV_16U);
  Unpack(kWeightsTag, blob, {&weights});
  return weights;
}

BuildCheckpointer::BuildCheckpointer(CheckpointStore* store, TileBuffer* buffer, const TileForecast* forecast,
                                     ThreadPool* pool, int tile_size, int channels)
    : store_(store), buffer_(buffer), forecast_(forecast), pool_(pool), tile_size_(tile_size), channels_(channels) {}

void BuildCheckpointer::Write(BuildProgress progress, int64_t frames_from, int64_t track_from, bool keep_start) {
  const TileBuffer::Changes changes = buffer_->TakeChanges();
  CheckpointUpdate update;
  std::vector<std::future<std::vector<uint8_t>>> packed;
  for (const TileId& id : changes.tiles) {
    if (const TileAccumulator* tile = buffer_->Unfinished(id)) {
      update.put.push_back({kSums, id, {}});
      packed.push_back(pool_->Submit([tile] { return PackSums(*tile); }));
    } else {
      update.drop.push_back({kSums, id});
    }
  }
  // Weights matter only for a tile some later frame will be over: the others
  // are listed without them (so that the budget keeps the same ones).
  const int after = progress.frame_index;
  for (const TileId& id : changes.kept) {
    const cv::Mat* weights = buffer_->Kept(id);
    const bool needed = weights && !weights->empty() &&
                        (!forecast_ || forecast_->empty() || forecast_->OverSoon(id, after, INT_MAX - after));
    if (needed) {
      update.put.push_back({kWeights, id, {}});
      packed.push_back(pool_->Submit([weights] { return PackWeights(*weights); }));
    } else {
      update.drop.push_back({kWeights, id});
    }
  }
  for (size_t i = 0; i < packed.size(); ++i) update.put[i].data = packed[i].get();
  progress.tiles = buffer_->LastFrames();
  progress.kept = buffer_->KeptOrder();
  update.progress = progress.ToJson().dump();
  update.frames_from = frames_from;
  update.track_from = track_from;
  update.keep_start = keep_start;
  store_->WriteCheckpoint(update);
}

std::optional<BuildProgress> BuildCheckpointer::Read() const {
  const std::optional<StoredCheckpoint> stored = store_->ReadCheckpoint();
  if (!stored) return std::nullopt;
  return BuildProgress::FromJson(stored->progress);
}

void BuildCheckpointer::Restore(const BuildProgress& progress) {
  for (const auto& [id, last_frame] : progress.tiles) {
    const auto blob = store_->ReadCheckpointBlob(kSums, id);
    if (!blob) throw std::runtime_error("the checkpoint lacks the sums of a tile it lists");
    const auto [sums, weights] = UnpackSums(*blob, tile_size_, channels_);
    buffer_->RestoreTile(id, last_frame, sums, weights);
  }
  for (const auto& [id, stamp] : progress.kept) {
    const auto blob = store_->ReadCheckpointBlob(kWeights, id);
    buffer_->RestoreKept(id, stamp, blob ? UnpackWeights(*blob, tile_size_) : cv::Mat());
  }
  buffer_->RestoreReadbacks(progress.readbacks);
  buffer_->TakeChanges();  // what was restored is saved already
}

}  // namespace seamap
