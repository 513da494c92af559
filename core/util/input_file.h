#pragma once
// The checks every reader of a user's file makes before reading it: it must
// be a regular file (a FIFO would block, /dev/zero never ends, a folder is
// not a file) and, where the reader has a limit, no larger than that limit.
// Done on the path before it is opened, so nothing is read or allocated.
#include <sys/types.h>

#include <cstdint>
#include <string>

namespace seamap {

// The size in bytes of the regular file at `path`. Throws
// InputError(path, 0, field, "cannot read the <what>: <reason>"), the reason
// being "no such file", "not a regular file (a FIFO)" (a folder, a device, a
// socket), or "N bytes, over the limit of M" when max_bytes > 0.
// What a path that is not a regular file is, for a message: "a FIFO", "a folder", ...
const char* FileKindOf(mode_t mode);

int64_t RegularFileBytes(const std::string& path, const std::string& what, const std::string& field = "",
                         int64_t max_bytes = 0);

}  // namespace seamap
