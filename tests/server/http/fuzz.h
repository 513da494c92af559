#pragma once
// Time-bounded randomised testing for the server's parsers (http_fuzz_test.cc).
// Each test runs for SEAMAP_FUZZ_SECONDS (default 2) from one seed:
// SEAMAP_FUZZ_SEED, or a fresh one. A failure names the seed and the
// iteration; rerun with SEAMAP_FUZZ_SEED=<seed> to get the same inputs.
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace seamap::server::fuzz {

class Fuzzer {
 public:
  Fuzzer() {
    const char* seed = std::getenv("SEAMAP_FUZZ_SEED");
    seed_ = seed ? std::strtoull(seed, nullptr, 10) : std::random_device{}() * 0x100000001ull + std::random_device{}();
    const char* seconds = std::getenv("SEAMAP_FUZZ_SECONDS");
    const double s = seconds ? std::atof(seconds) : 2.0;
    deadline_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<int64_t>(s * 1000));
  }

  // The next input, until the time is up or a check failed (one failure
  // is enough: the seed reproduces it).
  bool Next() {
    if (::testing::Test::HasFailure()) {
      ADD_FAILURE() << "to reproduce: SEAMAP_FUZZ_SEED=" << seed_ << " (failed at " << Where() << ")";
      return false;
    }
    if (iteration_ > 0 && std::chrono::steady_clock::now() >= deadline_) {
      std::printf("fuzz: %llu inputs, seed %llu\n", static_cast<unsigned long long>(iteration_),
                  static_cast<unsigned long long>(seed_));
      return false;
    }
    rng_.seed(seed_ + iteration_++);  // each input from its own seed
    return true;
  }
  std::string Where() const {
    return "seed " + std::to_string(seed_) + " input " + std::to_string(iteration_ > 0 ? iteration_ - 1 : 0);
  }

  size_t Below(size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }
  bool OneIn(size_t n) { return Below(n) == 0; }
  template <typename T>
  const T& Pick(const std::vector<T>& v) {
    return v[Below(v.size())];
  }

  std::string Bytes(size_t max_size) {
    std::string s(Below(max_size + 1), '\0');
    for (char& c : s) c = static_cast<char>(Below(256));
    return s;
  }

  // `s` changed in a few random ways that parsers trip on: bytes flipped,
  // inserted, removed, duplicated; CR, LF, digits, huge numbers, escapes.
  std::string Mutate(std::string s) {
    static const std::vector<std::string> kPieces = {"\r\n",
                                                     "\r",
                                                     "\n",
                                                     " ",
                                                     "\t",
                                                     ":",
                                                     "/",
                                                     ".",
                                                     "..",
                                                     "%",
                                                     "%2e",
                                                     "%00",
                                                     "0",
                                                     "9",
                                                     "f",
                                                     "F",
                                                     ";",
                                                     ",",
                                                     std::string(1, '\0'),
                                                     "\x80",
                                                     "\xff",
                                                     "\xc3",
                                                     "-1",
                                                     "99999999999999999999",
                                                     "ffffffffffffffff",
                                                     "Content-Length: 5\r\n",
                                                     "Transfer-Encoding: chunked\r\n",
                                                     "Connection: close\r\n",
                                                     "Expect: 100-continue\r\n",
                                                     "HTTP/1.0",
                                                     "\r\n\r\n"};
    const size_t edits = 1 + Below(4);
    for (size_t e = 0; e < edits; ++e) {
      const size_t at = Below(s.size() + 1);
      switch (Below(6)) {
        case 0:
          if (!s.empty()) s[Below(s.size())] = static_cast<char>(Below(256));
          break;
        case 1:
          s.insert(at, 1, static_cast<char>(Below(256)));
          break;
        case 2:
          s.erase(at, Below(8));
          break;
        case 3:
          s.insert(at, s.substr(Below(s.size() + 1), Below(16)));
          break;
        case 4:
          s.resize(Below(s.size() + 1));
          break;
        default:
          s.insert(at, Pick(kPieces));
          break;
      }
    }
    return s;
  }

 private:
  uint64_t seed_;
  uint64_t iteration_ = 0;
  std::chrono::steady_clock::time_point deadline_;
  std::mt19937_64 rng_;
};

}  // namespace seamap::server::fuzz
