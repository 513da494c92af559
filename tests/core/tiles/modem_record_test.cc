// The 24-byte record for the acoustic modem: golden bytes (computed with
// Python's struct and binascii.crc_hqx, independently of this code), round
// trips within the quantisation, CRC and rejection of damaged records.
#include "core/tiles/modem_record.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

namespace seamap {
namespace {

std::string Hex(const uint8_t* b, size_t n) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (size_t i = 0; i < n; ++i) {
    out += digits[b[i] >> 4];
    out += digits[b[i] & 15];
  }
  return out;
}

Detection Fixed() {
  Detection d;
  d.id = 0x11234;  // low 16 bits: 0x1234
  d.seq = 300;
  d.class_name = "anchor";
  d.position = {-33.8567844, 151.2152967};
  d.time_s = 1000.25;
  d.score = 0.876;
  d.size_m = std::array<double, 2>{0.62, 1.13};
  d.status = "confirmed";
  d.source = "recogniser";
  return d;
}

std::string ErrorOf(const std::array<uint8_t, kModemRecordBytes>& b, size_t size = kModemRecordBytes) {
  try {
    DecodeModemRecord(b.data(), size);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(ModemRecord, CrcCheckValue) {
  const std::string text = "123456789";
  EXPECT_EQ(Crc16CcittFalse(reinterpret_cast<const uint8_t*>(text.data()), text.size()), 0x29B1);
  EXPECT_EQ(Crc16CcittFalse(nullptr, 0), 0xFFFF);
}

TEST(ModemRecord, GoldenBytesOfAFixedRecord) {
  const ModemRecord r = ModemRecordOf(Fixed(), 3, 900.0);
  const auto b = EncodeModemRecord(r);
  // struct.pack('<BBHHiiIBBBB', 1, 3, 0x1234, 300, -338567844, 1512152967, 1003, 88, 23, 1, 0) + CRC
  EXPECT_EQ(Hex(b.data(), b.size()), "010334122c015cddd1eb879f215aeb03000058170100116f");
  EXPECT_EQ(r.time_ds, 1003u);  // 1002.5 tenths rounds away from zero
  EXPECT_EQ(r.score_pct, 88);
  EXPECT_EQ(r.size_5cm, 23);  // 1.13 m / 5 cm = 22.6
  EXPECT_EQ(r.status(), ModemStatus::kConfirmed);
  EXPECT_EQ(r.source(), ModemSource::kRecogniser);
  EXPECT_FALSE(r.heading_valid());
}

TEST(ModemRecord, FlagsCarryStatusAndSource) {
  Detection d = Fixed();
  d.status = "rejected";
  d.source = "operator";
  ModemRecord r = ModemRecordOf(d, 0, std::nullopt);
  EXPECT_EQ(r.status(), ModemStatus::kRejected);
  EXPECT_EQ(r.source(), ModemSource::kOperator);
  EXPECT_EQ(r.time_ds, kModemUnknownTime);  // no t0
  d.source = "stereo";
  r = ModemRecordOf(d, 0, 0.0, /*deleted=*/true);
  EXPECT_EQ(r.status(), ModemStatus::kDeleted);
  EXPECT_EQ(r.source(), ModemSource::kStereo);
}

TEST(ModemRecord, RandomRecordsRoundTripWithinTheQuantisation) {
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> lat(-90, 90), lon(-180, 180), score(0, 1), size(0, 12.7), dt(0, 86400);
  const char* statuses[] = {"unconfirmed", "confirmed", "rejected"};
  const char* sources[] = {"recogniser", "operator", "stereo"};
  for (int i = 0; i < 10000; ++i) {
    Detection d;
    d.id = static_cast<int64_t>(rng() % 1000000) + 1;
    d.seq = static_cast<int64_t>(rng() % 1000000) + 1;
    d.position = {lat(rng), lon(rng)};
    d.score = score(rng);
    const double t0 = 1.7e9;
    d.time_s = t0 + dt(rng);
    d.size_m = std::array<double, 2>{size(rng), size(rng)};
    const int status = static_cast<int>(rng() % 3), source = static_cast<int>(rng() % 3);
    d.status = statuses[status];
    d.source = sources[source];
    const uint8_t cls = static_cast<uint8_t>(rng() % 256);
    const auto bytes = EncodeModemRecord(ModemRecordOf(d, cls, t0));
    const ModemRecord r = DecodeModemRecord(bytes.data(), bytes.size());
    ASSERT_EQ(r.class_id, cls);
    ASSERT_EQ(r.id, d.id & 0xFFFF);
    ASSERT_EQ(r.seq, d.seq & 0xFFFF);
    ASSERT_LE(std::abs(r.lat() - d.position.lat), 0.5e-7 + 1e-12) << i;
    ASSERT_LE(std::abs(r.lon() - d.position.lon), 0.5e-7 + 1e-12) << i;
    ASSERT_LE(std::abs(r.time_ds / 10.0 - (*d.time_s - t0)), 0.05 + 1e-6) << i;
    ASSERT_LE(std::abs(r.score_pct / 100.0 - d.score), 0.005 + 1e-12) << i;
    ASSERT_LE(std::abs(r.size_5cm * 0.05 - std::max((*d.size_m)[0], (*d.size_m)[1])), 0.025 + 1e-9) << i;
    ASSERT_EQ(static_cast<int>(r.status()), status);
    ASSERT_EQ(static_cast<int>(r.source()), source);
    ASSERT_EQ(EncodeModemRecord(r), bytes);  // decoding loses nothing the bytes hold
  }
}

TEST(ModemRecord, ExtremesAndNegativeRounding) {
  Detection d = Fixed();
  for (auto [la, lo] : {std::pair{90.0, 180.0}, {-90.0, -180.0}, {90.0, -180.0}, {-90.0, 180.0}}) {
    d.position = {la, lo};
    const auto b = EncodeModemRecord(ModemRecordOf(d, 0, 0.0));
    const ModemRecord r = DecodeModemRecord(b.data(), b.size());
    EXPECT_EQ(r.lat_e7, static_cast<int32_t>(la * 1e7));
    EXPECT_EQ(r.lon_e7, static_cast<int32_t>(lo * 1e7));
  }
  // Half steps round away from zero on both sides (llround), not towards -inf.
  d.position = {-0.00000005, -0.00000015};
  ModemRecord r = ModemRecordOf(d, 0, 0.0);
  EXPECT_EQ(r.lat_e7, -1);
  EXPECT_EQ(r.lon_e7, -2);
  d.position = {-12.34567894, -0.00000004};
  r = ModemRecordOf(d, 0, 0.0);
  EXPECT_EQ(r.lat_e7, -123456789);
  EXPECT_EQ(r.lon_e7, 0);
  // Clamped: score, size (>= 12.75 m is 255), time before t0 and far after it.
  d.score = 1.7;
  d.size_m = std::array<double, 2>{40.0, 2.0};
  d.time_s = -5;
  r = ModemRecordOf(d, 0, 0.0);
  EXPECT_EQ(r.score_pct, 100);
  EXPECT_EQ(r.size_5cm, 255);
  EXPECT_EQ(r.time_ds, 0u);
  d.score = -0.2;
  d.size_m.reset();
  d.time_s = 1e12;
  r = ModemRecordOf(d, 0, 0.0);
  EXPECT_EQ(r.score_pct, 0);
  EXPECT_EQ(r.size_5cm, 0);
  EXPECT_EQ(r.time_ds, kModemUnknownTime - 1);  // the largest known time, not "unknown"
}

TEST(ModemRecord, DamagedRecordsAreRejectedSayingWhy) {
  const auto good = EncodeModemRecord(ModemRecordOf(Fixed(), 3, 900.0));
  EXPECT_EQ(ErrorOf(good), "");
  EXPECT_NE(ErrorOf(good, 23).find("24 bytes, got 23"), std::string::npos);
  auto version = good;
  version[0] = 2;
  version[22] = version[23] = 0;  // even with a right CRC the version is refused first
  const uint16_t crc = Crc16CcittFalse(version.data(), 22);
  version[22] = crc & 0xFF;
  version[23] = crc >> 8;
  EXPECT_NE(ErrorOf(version).find("version 2"), std::string::npos);
  for (size_t i = 1; i < kModemRecordBytes; ++i) {  // any flipped bit breaks the CRC
    auto bad = good;
    bad[i] ^= 0x10;
    EXPECT_NE(ErrorOf(bad).find("CRC"), std::string::npos) << "byte " << i;
  }
}

TEST(ModemRecord, PackIsInSeqOrderWithClassIdsFromTheTable) {
  Detection a = Fixed(), b = Fixed(), c = Fixed();
  a.seq = 9;
  a.class_name = "tyre";
  b.seq = 4;
  b.class_name = "anchor";
  c.seq = 6;
  c.class_name = "wreck";  // not in the table
  const auto bytes = PackModemRecords({a, b, c}, {"tyre", "crate", "anchor"}, 900.0);
  ASSERT_EQ(bytes.size(), 3 * kModemRecordBytes);
  std::vector<std::pair<int, int>> got;
  for (size_t i = 0; i < bytes.size(); i += kModemRecordBytes) {
    const ModemRecord r = DecodeModemRecord(&bytes[i], kModemRecordBytes);
    got.push_back({r.seq, r.class_id});
  }
  EXPECT_EQ(got, (std::vector<std::pair<int, int>>{{4, 2}, {6, 255}, {9, 0}}));
  EXPECT_EQ(ModemCsvLine(DecodeModemRecord(bytes.data(), kModemRecordBytes), {"tyre", "crate", "anchor"}),
            "1,2,anchor,4660,4,-33.8567844,151.2152967,100.3,0.88,1.15,confirmed,recogniser,");
  EXPECT_EQ(ModemCsvLine(DecodeModemRecord(bytes.data(), kModemRecordBytes), {"a", "b", "rope, \"blue\""}),
            "1,2,\"rope, \"\"blue\"\"\",4660,4,-33.8567844,151.2152967,100.3,0.88,1.15,confirmed,recogniser,");
}

}  // namespace
}  // namespace seamap
