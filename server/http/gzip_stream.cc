#include "server/http/gzip_stream.h"

#include <zlib.h>

#include <cctype>
#include <stdexcept>

namespace seamap::server {

struct GzipStream::State {
  z_stream z{};
  bool finished = false;
};

GzipStream::GzipStream() : state_(std::make_unique<State>()) {
  // windowBits 15 + 16: gzip wrapper; memLevel 8; level 6 (zlib's default balance).
  if (deflateInit2(&state_->z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("gzip: cannot start a deflate stream");
}

GzipStream::~GzipStream() {
  deflateEnd(&state_->z);
}

namespace {

std::string Deflate(z_stream& z, std::string_view in, int flush) {
  std::string out;
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = static_cast<uInt>(in.size());
  char buffer[16384];
  do {
    z.next_out = reinterpret_cast<Bytef*>(buffer);
    z.avail_out = sizeof buffer;
    const int rc = deflate(&z, flush);
    if (rc == Z_STREAM_ERROR) throw std::runtime_error("gzip: deflate failed");
    out.append(buffer, sizeof buffer - z.avail_out);
  } while (z.avail_out == 0);
  return out;
}

}  // namespace

std::string GzipStream::Write(std::string_view piece) {
  if (state_->finished) throw std::logic_error("gzip: write after finish");
  return Deflate(state_->z, piece, Z_SYNC_FLUSH);
}

std::string GzipStream::Finish() {
  if (state_->finished) return "";
  state_->finished = true;
  return Deflate(state_->z, {}, Z_FINISH);
}

bool AcceptsGzip(std::string_view header) {
  while (!header.empty()) {
    const size_t comma = std::min(header.find(','), header.size());
    std::string_view item = header.substr(0, comma);
    header.remove_prefix(std::min(comma + 1, header.size()));
    while (!item.empty() && (item.front() == ' ' || item.front() == '\t')) item.remove_prefix(1);
    const size_t semi = std::min(item.find(';'), item.size());
    std::string_view coding = item.substr(0, semi);
    while (!coding.empty() && (coding.back() == ' ' || coding.back() == '\t')) coding.remove_suffix(1);
    std::string lower(coding);
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower != "gzip" && lower != "x-gzip") continue;
    std::string_view params = item.substr(semi);
    const size_t q = params.find("q=");
    if (q != std::string_view::npos) {
      std::string_view value = params.substr(q + 2);
      bool nonzero = false;
      for (char c : value) {
        if (c >= '1' && c <= '9') nonzero = true;
        if (c != '0' && c != '.' && !(c >= '1' && c <= '9')) break;
      }
      if (!nonzero) return false;
    }
    return true;
  }
  return false;
}

}  // namespace seamap::server
