#pragma once
// The protobuf wire format, read field by field from a buffer that holds the
// whole message: enough to read an ONNX model without its schema. Every read
// is bounded by the message's end; a malformed message reads as false.
#include <cstddef>
#include <cstdint>
#include <string>

namespace seamap {

// [begin, end) of a length-delimited payload in the buffer.
struct WireSpan {
  size_t begin = 0, end = 0;
  size_t size() const { return end - begin; }
};

enum WireType { kWireVarint = 0, kWireFixed64 = 1, kWireBytes = 2, kWireFixed32 = 5 };

class WireReader {
 public:
  WireReader(const std::string& bytes, size_t begin, size_t end) : s_(bytes), pos_(begin), end_(end) {}
  WireReader(const std::string& bytes, WireSpan span) : WireReader(bytes, span.begin, span.end) {}
  bool Done() const { return pos_ >= end_; }
  // Next field: number and wire type; false on malformed data.
  bool Next(int* field, int* type) {
    uint64_t key;
    if (!Varint(&key) || (key >> 3) > 0x1FFFFFFF) return false;
    *field = static_cast<int>(key >> 3);
    *type = static_cast<int>(key & 7);
    return *field > 0;
  }
  bool Varint(uint64_t* v) {
    *v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (pos_ >= end_) return false;
      const uint8_t b = static_cast<uint8_t>(s_[pos_++]);
      *v |= static_cast<uint64_t>(b & 0x7f) << shift;
      if (!(b & 0x80)) return true;
    }
    return false;
  }
  // A length-delimited payload: [begin, end) in the buffer.
  bool Bytes(size_t* begin, size_t* end) {
    uint64_t n;
    if (!Varint(&n) || n > end_ - pos_) return false;
    *begin = pos_;
    *end = pos_ + n;
    pos_ += n;
    return true;
  }
  bool Bytes(WireSpan* span) { return Bytes(&span->begin, &span->end); }
  bool Skip(int type) {
    uint64_t v;
    size_t b, e;
    switch (type) {
      case kWireVarint:
        return Varint(&v);
      case kWireFixed64:
        return Advance(8);
      case kWireBytes:
        return Bytes(&b, &e);
      case kWireFixed32:
        return Advance(4);
      default:
        return false;  // groups are not used by ONNX
    }
  }

 private:
  bool Advance(size_t n) {
    if (n > end_ - pos_) return false;
    pos_ += n;
    return true;
  }
  const std::string& s_;
  size_t pos_, end_;
};

// How many varints a packed repeated field holds (bytes whose high bit is clear).
inline size_t CountPackedVarints(const std::string& s, WireSpan span) {
  size_t n = 0;
  for (size_t i = span.begin; i < span.end; ++i) n += (static_cast<uint8_t>(s[i]) & 0x80) == 0;
  return n;
}

}  // namespace seamap
