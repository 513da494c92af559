#pragma once
// Randomised tests with a time budget: cases are drawn from a seeded
// generator until the budget is spent (SEAMAP_FUZZ_SECONDS, default 2 s), so
// the suite's time stays bounded whatever the machine. The seed is random
// unless SEAMAP_FUZZ_SEED gives it; it is part of every failure message
// (SCOPED_TRACE), so a failure can be replayed with the same seed.
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>

#include <gtest/gtest.h>

namespace seamap::testing {

class Fuzz {
 public:
  Fuzz()
      : seed_(std::getenv("SEAMAP_FUZZ_SEED")
                  ? static_cast<uint32_t>(std::strtoul(std::getenv("SEAMAP_FUZZ_SEED"), nullptr, 10))
                  : std::random_device{}()),
        rng_(seed_),
        trace_(__FILE__, __LINE__,
               "fuzz seed " + std::to_string(seed_) + " (replay: SEAMAP_FUZZ_SEED=" + std::to_string(seed_) + ")") {
    const char* s = std::getenv("SEAMAP_FUZZ_SECONDS");
    const double seconds = s ? std::atof(s) : 2.0;
    deadline_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000));
  }
  // Whether to run another case: budget left and no failure yet (one
  // failing case is enough to replay).
  bool More() {
    ++cases_;
    return !::testing::Test::HasFailure() && (cases_ <= kMinCases || std::chrono::steady_clock::now() < deadline_);
  }
  int cases() const { return cases_; }
  std::mt19937& rng() { return rng_; }
  uint32_t seed() const { return seed_; }
  size_t Below(size_t n) { return n == 0 ? 0 : rng_() % n; }
  bool OneIn(size_t n) { return Below(n) == 0; }
  template <typename T>
  const T& Pick(const std::vector<T>& items) {
    return items[Below(items.size())];
  }

  // A value a corrupted or hostile file may hold where a number belongs.
  std::string HostileNumber() {
    static const std::vector<std::string> kValues = {"1e308",
                                                     "-1e308",
                                                     "1e999",
                                                     "-1e999",
                                                     "nan",
                                                     "NaN",
                                                     "inf",
                                                     "-inf",
                                                     "Infinity",
                                                     "1e9",
                                                     "-1e9",
                                                     "0",
                                                     "-0",
                                                     "1e-320",
                                                     "4.9e-324",
                                                     "0x1p1023",
                                                     "9999999999999999999999",
                                                     "1,5",
                                                     "\xE2\x88\x92"
                                                     "2",
                                                     "",
                                                     " ",
                                                     "+",
                                                     "-",
                                                     ".",
                                                     "1e",
                                                     "e5",
                                                     "--1",
                                                     "1..2",
                                                     "\"3\"",
                                                     "2147483648",
                                                     "-2147483649",
                                                     "18446744073709551616",
                                                     "1e+308"};
    return Pick(kValues);
  }
  // Random bytes, text-like or not.
  std::string Bytes(size_t max) {
    std::string out(Below(max + 1), '\0');
    const bool text = OneIn(2);
    for (char& c : out)
      c = text ? static_cast<char>(" ,;\t\"#\r\n0123456789.-eEabc"[Below(26)]) : static_cast<char>(rng_());
    return out;
  }
  // `text` with a few random edits: bytes replaced, inserted or removed.
  std::string Mutate(std::string text) {
    const size_t edits = 1 + Below(4);
    for (size_t i = 0; i < edits; ++i) {
      const size_t at = Below(text.size() + 1);
      switch (Below(3)) {
        case 0:
          if (at < text.size()) text[at] = static_cast<char>(rng_());
          break;
        case 1:
          text.insert(at, Bytes(8));
          break;
        default:
          text.erase(at, Below(8));
          break;
      }
    }
    return text;
  }

 private:
  static constexpr int kMinCases = 20;
  uint32_t seed_;
  std::mt19937 rng_;
  ::testing::ScopedTrace trace_;
  std::chrono::steady_clock::time_point deadline_;
  int cases_ = 0;
};

}  // namespace seamap::testing
