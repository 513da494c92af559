#include "core/mosaic/tile_writer.h"

#include <cstdlib>
#include <exception>

namespace seamap {

TileWriter::TileWriter(TileStore* store, ThreadPool* pool, TileEncoding encoding, std::vector<TileConsumer*> consumers)
    : store_(store), pool_(pool), encoding_(encoding), consumers_(std::move(consumers)) {}

TileWriter::~TileWriter() {
  for (auto& f : in_flight_)
    if (f.valid()) f.wait();
}

void TileWriter::Submit(const TileId& id, const cv::Mat& tile, bool final) {
  uint64_t version;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    version = next_version_++;
    pending_[id] = {tile, version};
    seen_.insert(id);
    // Drop futures that are done so the list stays short.
    if (in_flight_.size() > 256) {
      std::vector<std::future<void>> still;
      for (auto& f : in_flight_) {
        // Finished jobs' errors stay in their futures until Flush reports them.
        if (IsReady(f))
          done_.push_back(std::move(f));
        else
          still.push_back(std::move(f));
      }
      in_flight_.swap(still);
    }
  }
  auto job = pool_->Submit([this, id, tile, version, final] { Encode(id, tile, version, final); });
  std::lock_guard<std::mutex> lock(mutex_);
  in_flight_.push_back(std::move(job));
}

void TileWriter::Encode(TileId id, cv::Mat tile, uint64_t version, bool final) {
  std::vector<uint8_t> bytes = EncodeTile(tile, encoding_);
  std::lock_guard<std::mutex> order(store_mutex_);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = pending_.find(id);
    if (it == pending_.end() || it->second.version != version) return;  // a newer one follows
  }
  store_->PutTile(id, bytes);
  ++written_;
  bytes_ += static_cast<int64_t>(bytes.size());
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = pending_.find(id);
    if (it != pending_.end() && it->second.version == version) pending_.erase(it);
  }
  for (TileConsumer* c : consumers_) c->OnTileWritten(id, tile, version, final);
}

std::optional<cv::Mat> TileWriter::Read(const TileId& id) const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = pending_.find(id);
    if (it != pending_.end()) return it->second.tile.clone();
  }
  auto bytes = store_->GetTile(id);
  if (!bytes) return std::nullopt;
  return DecodeTile(*bytes);
}

cv::Mat TileWriter::ReadToPaint(const TileId& id, int channels, int tile_size) const {
  auto tile = Read(id);
  if (!tile || tile->rows != tile_size) return {};
  cv::Mat t = WithColourChannels(*tile, channels);
  if (encoding_.format == TileFormat::kJpeg) {
    // JPEG has no alpha: pixels that still show the background colour are empty.
    const cv::Scalar& bg = encoding_.background;
    for (int y = 0; y < t.rows; ++y) {
      uint8_t* p = t.ptr<uint8_t>(y);
      for (int x = 0; x < t.cols; ++x, p += t.channels()) {
        bool is_bg = true;
        for (int c = 0; c < channels; ++c)
          is_bg &= std::abs(p[c] - static_cast<int>(channels == 1 ? bg[0] : bg[c])) <= 3;
        if (is_bg) p[channels] = 0;
      }
    }
  }
  return t;
}

void TileWriter::Flush() {
  std::vector<std::future<void>> jobs;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs.swap(in_flight_);
    for (auto& f : done_) jobs.push_back(std::move(f));
    done_.clear();
  }
  // Wait for every job before rethrowing the first error: none may outlive us.
  std::exception_ptr error;
  for (auto& f : jobs) {
    try {
      f.get();
    } catch (...) {
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  store_->Flush();
}

void TileWriter::Resume(int64_t tiles_written, int64_t bytes_written, const std::vector<TileId>& stored) {
  std::lock_guard<std::mutex> lock(mutex_);
  written_ = tiles_written;
  bytes_ = bytes_written;
  seen_.insert(stored.begin(), stored.end());
}

std::map<int, int64_t> TileWriter::distinct_tiles_per_zoom() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<int, int64_t> out;
  for (const TileId& id : seen_) ++out[id.z];
  return out;
}

}  // namespace seamap
