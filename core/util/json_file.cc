#include "core/util/json_file.h"

#include <filesystem>
#include <fstream>

#include "core/util/error.h"

namespace seamap {

nlohmann::json ReadJsonFile(const std::string& path, const std::string& what) {
  const auto failure = [&](const std::string& reason) {
    return InputError(path, 0, "", "cannot read the " + what + ": " + reason);
  };
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw failure("no such file");
  if (!std::filesystem::is_regular_file(status)) throw failure("not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw failure("cannot open it");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw failure(std::string("not JSON: ") + e.what());
  }
}

}  // namespace seamap
