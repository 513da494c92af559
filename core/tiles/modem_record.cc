#include "core/tiles/modem_record.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace seamap {
namespace {

template <typename T>
T Clamped(double v, double lo, double hi) {
  return static_cast<T>(std::llround(std::clamp(v, lo, hi)));
}

void PutU16(uint8_t* at, uint16_t v) {
  at[0] = static_cast<uint8_t>(v & 0xFF);
  at[1] = static_cast<uint8_t>(v >> 8);
}

void PutU32(uint8_t* at, uint32_t v) {
  for (int i = 0; i < 4; ++i) at[i] = static_cast<uint8_t>((v >> (8 * i)) & 0xFF);
}

uint16_t GetU16(const uint8_t* at) {
  return static_cast<uint16_t>(at[0] | (at[1] << 8));
}

uint32_t GetU32(const uint8_t* at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | at[i];
  return v;
}

ModemStatus StatusOf(const std::string& status) {
  if (status == "confirmed") return ModemStatus::kConfirmed;
  if (status == "rejected") return ModemStatus::kRejected;
  return ModemStatus::kUnconfirmed;
}

ModemSource SourceOf(const std::string& source) {
  if (source == "recogniser") return ModemSource::kRecogniser;
  if (source == "operator") return ModemSource::kOperator;
  if (source == "stereo") return ModemSource::kStereo;
  return ModemSource::kOther;
}

const char* StatusName(ModemStatus s) {
  switch (s) {
    case ModemStatus::kUnconfirmed:
      return "unconfirmed";
    case ModemStatus::kConfirmed:
      return "confirmed";
    case ModemStatus::kRejected:
      return "rejected";
    case ModemStatus::kDeleted:
      return "deleted";
  }
  return "";
}

const char* SourceName(ModemSource s) {
  switch (s) {
    case ModemSource::kRecogniser:
      return "recogniser";
    case ModemSource::kOperator:
      return "operator";
    case ModemSource::kStereo:
      return "stereo";
    case ModemSource::kOther:
      return "other";
  }
  return "";
}

}  // namespace

uint16_t Crc16CcittFalse(const uint8_t* bytes, size_t size) {
  uint16_t crc = 0xFFFF;
  for (size_t i = 0; i < size; ++i) {
    crc ^= static_cast<uint16_t>(bytes[i] << 8);
    for (int bit = 0; bit < 8; ++bit)
      crc = (crc & 0x8000) ? static_cast<uint16_t>((crc << 1) ^ 0x1021) : static_cast<uint16_t>(crc << 1);
  }
  return crc;
}

ModemRecord ModemRecordOf(const Detection& original, uint8_t class_id, std::optional<double> t0, bool deleted) {
  Detection d = original;
  NormaliseDetection(&d);
  ModemRecord r;
  r.class_id = class_id;
  r.id = static_cast<uint16_t>(static_cast<uint64_t>(d.id) & 0xFFFF);
  r.seq = static_cast<uint16_t>(static_cast<uint64_t>(d.seq) & 0xFFFF);
  r.lat_e7 = Clamped<int32_t>(d.position.lat * 1e7, -900000000, 900000000);
  r.lon_e7 = Clamped<int32_t>(d.position.lon * 1e7, -1800000000, 1800000000);
  if (d.time_s && t0 && std::isfinite(*d.time_s - *t0))
    r.time_ds = Clamped<uint32_t>((*d.time_s - *t0) * 10, 0, kModemUnknownTime - 1.0);
  r.score_pct = std::isfinite(d.score) ? Clamped<uint8_t>(d.score * 100, 0, 100) : 0;
  if (d.size_m) {
    const double longest = std::max((*d.size_m)[0], (*d.size_m)[1]);
    if (std::isfinite(longest)) r.size_5cm = Clamped<uint8_t>(longest / 0.05, 0, 255);
  }
  const ModemStatus status = deleted ? ModemStatus::kDeleted : StatusOf(d.status);
  r.flags = static_cast<uint8_t>(static_cast<uint8_t>(status) | (static_cast<uint8_t>(SourceOf(d.source)) << 2));
  if (d.heading_deg && std::isfinite(*d.heading_deg)) {  // 360/256 degree steps, rounded
    const double turns = std::fmod(std::fmod(*d.heading_deg, 360.0) + 360.0, 360.0) / 360.0;
    r.heading = static_cast<uint8_t>(static_cast<int>(std::lround(turns * 256)) & 0xFF);
    r.flags |= 0x10;
  }
  return r;
}

std::array<uint8_t, kModemRecordBytes> EncodeModemRecord(const ModemRecord& r) {
  std::array<uint8_t, kModemRecordBytes> b{};
  b[0] = r.version;
  b[1] = r.class_id;
  PutU16(&b[2], r.id);
  PutU16(&b[4], r.seq);
  PutU32(&b[6], static_cast<uint32_t>(r.lat_e7));
  PutU32(&b[10], static_cast<uint32_t>(r.lon_e7));
  PutU32(&b[14], r.time_ds);
  b[18] = r.score_pct;
  b[19] = r.size_5cm;
  b[20] = r.flags;
  b[21] = r.heading;
  PutU16(&b[22], Crc16CcittFalse(b.data(), 22));
  return b;
}

ModemRecord DecodeModemRecord(const uint8_t* b, size_t size) {
  if (size != kModemRecordBytes)
    throw std::invalid_argument("expected a record of 24 bytes, got " + std::to_string(size));
  if (b[0] != kModemRecordVersion)
    throw std::invalid_argument("record version " + std::to_string(b[0]) + " (expected 1)");
  const uint16_t crc = GetU16(&b[22]), want = Crc16CcittFalse(b, 22);
  if (crc != want) {
    char text[80];
    std::snprintf(text, sizeof text, "CRC mismatch: record says 0x%04X, bytes 0-21 give 0x%04X", crc, want);
    throw std::invalid_argument(text);
  }
  ModemRecord r;
  r.version = b[0];
  r.class_id = b[1];
  r.id = GetU16(&b[2]);
  r.seq = GetU16(&b[4]);
  r.lat_e7 = static_cast<int32_t>(GetU32(&b[6]));
  r.lon_e7 = static_cast<int32_t>(GetU32(&b[10]));
  r.time_ds = GetU32(&b[14]);
  r.score_pct = b[18];
  r.size_5cm = b[19];
  r.flags = b[20];
  r.heading = b[21];
  if (r.flags & 0xE0) throw std::invalid_argument("flags bits 5-7 are set (reserved, must be zero)");
  if (r.score_pct > 100) throw std::invalid_argument("score " + std::to_string(r.score_pct) + " (expected 0-100)");
  if (std::abs(static_cast<int64_t>(r.lat_e7)) > 900000000 || std::abs(static_cast<int64_t>(r.lon_e7)) > 1800000000)
    throw std::invalid_argument("latitude or longitude out of range");
  return r;
}

std::vector<uint8_t> PackModemRecords(std::vector<Detection> detections, const std::vector<std::string>& classes,
                                      std::optional<double> t0) {
  std::stable_sort(detections.begin(), detections.end(),
                   [](const Detection& a, const Detection& b) { return a.seq < b.seq; });
  std::vector<uint8_t> out;
  out.reserve(detections.size() * kModemRecordBytes);
  for (const Detection& d : detections) {
    auto it = std::find(classes.begin(), classes.end(), d.class_name);
    const auto index = it - classes.begin();
    const uint8_t class_id = it == classes.end() || index >= 255 ? kModemUnknownClass : static_cast<uint8_t>(index);
    const auto bytes = EncodeModemRecord(ModemRecordOf(d, class_id, t0));
    out.insert(out.end(), bytes.begin(), bytes.end());
  }
  return out;
}

std::string ModemCsvHeader() {
  return "version,class_id,class,id,seq,lat,lon,time_s,score,size_m,status,source,heading_deg";
}

std::string ModemCsvLine(const ModemRecord& r, const std::vector<std::string>& classes) {
  std::string cls = r.class_id < classes.size() ? classes[r.class_id] : "";
  if (cls.find_first_of(",\"\n") != std::string::npos) {  // a CSV field in quotes, quotes doubled
    std::string quoted = "\"";
    for (char c : cls) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    cls = quoted + "\"";
  }
  char time[32] = "", heading[32] = "";
  if (r.time_ds != kModemUnknownTime) std::snprintf(time, sizeof time, "%.1f", r.time_ds / 10.0);
  if (r.heading_valid()) std::snprintf(heading, sizeof heading, "%.2f", r.heading * 360.0 / 256.0);
  char line[256];
  std::snprintf(line, sizeof line, "%u,%u,%s,%u,%u,%.7f,%.7f,%s,%.2f,%.2f,%s,%s,%s", r.version, r.class_id, cls.c_str(),
                r.id, r.seq, r.lat(), r.lon(), time, r.score_pct / 100.0, r.size_5cm * 0.05, StatusName(r.status()),
                SourceName(r.source()), heading);
  return line;
}

}  // namespace seamap
