#pragma once
// A fresh folder under the system temp dir, removed when the test ends.
#include <filesystem>
#include <string>

namespace seamap::testing {

class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// Writes text to a file (creating parent folders) and returns its path.
std::filesystem::path WriteFile(const std::filesystem::path& path, const std::string& text);

// Path of the built seamap executable (SEAMAP_BIN, set by CTest).
std::string SeamapBinary();

// Runs a shell command, returns its exit code; stdout+stderr go to *output.
int RunCommand(const std::string& command, std::string* output);

}  // namespace seamap::testing
