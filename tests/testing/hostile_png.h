#pragma once
// PNG files that claim far more pixels than they take bytes, for the tests of
// what a build refuses to decode: a header alone, and a valid image of zeros
// (30000 x 30000 zeros deflate to about 875 KB). Header-only: zlib comes with
// libpng, which every test binary that uses this links.
#include <zlib.h>

#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>

namespace seamap::testing {

inline void PutBe32(std::string* out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out->push_back(static_cast<char>((v >> shift) & 0xFF));
}

inline std::string PngChunk(const std::string& type, const std::string& data) {
  std::string chunk;
  PutBe32(&chunk, static_cast<uint32_t>(data.size()));
  const std::string body = type + data;
  chunk += body;
  PutBe32(&chunk,
          static_cast<uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size()))));
  return chunk;
}

inline std::string PngHeader(uint32_t width, uint32_t height, int colour_type) {
  std::string ihdr;
  PutBe32(&ihdr, width);
  PutBe32(&ihdr, height);
  ihdr += std::string{8, static_cast<char>(colour_type), 0, 0, 0};  // 8 bit, deflate, no filter, no interlace
  return std::string("\x89PNG\r\n\x1a\n", 8) + PngChunk("IHDR", ihdr);
}

// Deflates `chunks` copies of `chunk_bytes` zeros as zlib data: two chunks are
// compressed (each after a full flush, so every later copy is the same
// bytes), then repeated, then the stream's end with the Adler-32 of all
// zeros (a = 1, b = count mod 65521).
inline std::string DeflatedZeros(size_t chunk_bytes, size_t chunks) {
  z_stream z{};
  if (deflateInit(&z, 6) != Z_OK) throw std::runtime_error("deflateInit");
  const std::string zeros(chunk_bytes, '\0');
  auto run = [&](const char* in, size_t n, int flush) {
    std::string out(deflateBound(&z, static_cast<uLong>(n)) + 64, '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in));
    z.avail_in = static_cast<uInt>(n);
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = static_cast<uInt>(out.size());
    deflate(&z, flush);
    out.resize(out.size() - z.avail_out);
    return out;
  };
  const std::string first = run(zeros.data(), zeros.size(), Z_FULL_FLUSH);
  const std::string next = run(zeros.data(), zeros.size(), Z_FULL_FLUSH);
  std::string end = run(nullptr, 0, Z_FINISH);
  deflateEnd(&z);
  std::string stream = first;
  for (size_t i = 1; i < chunks; ++i) stream += next;
  end.resize(end.size() - 4);
  const uint64_t total = uint64_t{chunk_bytes} * chunks;
  PutBe32(&end, static_cast<uint32_t>(((total % 65521) << 16) | 1));
  return stream + end;
}

// A valid 8-bit gray PNG of width x height zeros; height must be a multiple of 100.
inline std::string ZeroPng(uint32_t width, uint32_t height) {
  if (height % 100 != 0) throw std::invalid_argument("ZeroPng: height must be a multiple of 100");
  const size_t row = size_t{width} + 1;  // filter byte 0, then the zeros
  return PngHeader(width, height, 0) + PngChunk("IDAT", DeflatedZeros(row * 100, height / 100)) + PngChunk("IEND", "");
}

// A PNG header claiming width x height gray pixels, followed by a few bytes
// of image data and the end: what decoders allocate for before they fail.
inline std::string ClaimingPng(uint32_t width, uint32_t height) {
  return PngHeader(width, height, 0) + PngChunk("IDAT", DeflatedZeros(1000, 1)) + PngChunk("IEND", "");
}

inline void WriteBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

}  // namespace seamap::testing
