#include "core/util/input_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>

#include "core/util/error.h"

namespace seamap {

const char* FileKindOf(mode_t mode) {
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a file";
}

int64_t RegularFileBytes(const std::string& path, const std::string& what, const std::string& field,
                         int64_t max_bytes) {
  const auto failure = [&](const std::string& reason) {
    return InputError(path, 0, field, "cannot read the " + what + ": " + reason);
  };
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw failure(errno == ENOENT || errno == ENOTDIR ? std::string("no such file") : std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw failure(std::string("not a regular file (") + FileKindOf(st.st_mode) + ")");
  const int64_t bytes = st.st_size;
  if (max_bytes > 0 && bytes > max_bytes)
    throw failure(std::to_string(bytes) + " bytes, over the limit of " + std::to_string(max_bytes));
  return bytes;
}

}  // namespace seamap
