#pragma once
// The compact form of a detection for a hydroacoustic modem (tens of bits per
// second): a fixed 24-byte little-endian record, docs/MODEM_RECORD.md.
//   0 u8 version (1) | 1 u8 class id (255 unknown) | 2 u16 id low 16 | 4 u16 seq low 16
//   6 i32 lat x 1e7 | 10 i32 lon x 1e7 | 14 u32 tenths of s since t0 (0xFFFFFFFF unknown)
//   18 u8 score x 100 | 19 u8 longest side in 5 cm steps | 20 u8 flags | 21 u8 heading
//   22 u16 CRC-16/CCITT-FALSE over bytes 0-21
// Encoded byte by byte, so the layout does not depend on the host.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/tiles/mission_records.h"

namespace seamap {

constexpr size_t kModemRecordBytes = 24;
constexpr uint8_t kModemRecordVersion = 1;
constexpr uint8_t kModemUnknownClass = 255;
constexpr uint32_t kModemUnknownTime = 0xFFFFFFFFu;

// Flags: bits 0-1 status, bits 2-3 source, bit 4 heading valid.
enum class ModemStatus : uint8_t { kUnconfirmed = 0, kConfirmed = 1, kRejected = 2, kDeleted = 3 };
enum class ModemSource : uint8_t { kRecogniser = 0, kOperator = 1, kStereo = 2, kOther = 3 };

struct ModemRecord {
  uint8_t version = kModemRecordVersion;
  uint8_t class_id = kModemUnknownClass;
  uint16_t id = 0;   // detection id, low 16 bits
  uint16_t seq = 0;  // change number, low 16 bits
  int32_t lat_e7 = 0, lon_e7 = 0;
  uint32_t time_ds = kModemUnknownTime;  // tenths of a second since the mission's first frame
  uint8_t score_pct = 0;                 // 0-100
  uint8_t size_5cm = 0;                  // longest side; 255 means >= 12.75 m
  uint8_t flags = 0;
  uint8_t heading = 0;  // 360/256 degree steps, valid when flags bit 4 is set

  ModemStatus status() const { return static_cast<ModemStatus>(flags & 3); }
  ModemSource source() const { return static_cast<ModemSource>((flags >> 2) & 3); }
  bool heading_valid() const { return (flags & 0x10) != 0; }
  double lat() const { return lat_e7 * 1e-7; }
  double lon() const { return lon_e7 * 1e-7; }
};

// CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection, no final xor
// ("123456789" gives 0x29B1).
uint16_t Crc16CcittFalse(const uint8_t* bytes, size_t size);

// The record of a detection: class_id from the mission's class table
// (kModemUnknownClass when absent), t0 the mission's first frame time (no
// t0 or no time_s: unknown time). Rounds with llround and clamps score,
// size and time. `deleted` marks a detection that is gone.
ModemRecord ModemRecordOf(const Detection& d, uint8_t class_id, std::optional<double> t0, bool deleted = false);

std::array<uint8_t, kModemRecordBytes> EncodeModemRecord(const ModemRecord& r);
// Throws std::invalid_argument saying what is wrong: length, version, CRC,
// reserved flag bits or a latitude/longitude out of range.
ModemRecord DecodeModemRecord(const uint8_t* bytes, size_t size);

// Records of `detections` in seq order, concatenated; `classes` is the
// mission's class table (index = class id).
std::vector<uint8_t> PackModemRecords(std::vector<Detection> detections, const std::vector<std::string>& classes,
                                      std::optional<double> t0);

// CSV of decoded records: ModemCsvHeader() then one ModemCsvLine per record
// (class as its name where `classes` has it, else the id).
std::string ModemCsvHeader();
std::string ModemCsvLine(const ModemRecord& r, const std::vector<std::string>& classes);

}  // namespace seamap
