#include "core/tiles/map_lock.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "core/util/error.h"

namespace seamap {
namespace {

// A whole-file write lock, taken (F_OFD_SETLK) or tested (F_OFD_GETLK).
bool LockCall(int fd, int command, struct flock* fl) {
  *fl = {};
  fl->l_type = F_WRLCK;
  fl->l_whence = SEEK_SET;
  return fcntl(fd, command, fl) == 0;
}

int ReadPid(int fd) {
  char text[32] = {};
  const ssize_t n = pread(fd, text, sizeof text - 1, 0);
  return n > 0 ? std::atoi(text) : 0;
}

std::string HolderText(int pid) {
  return pid > 0 ? "process " + std::to_string(pid) : "another process";
}

}  // namespace

std::string MapLock::LockPath(const std::string& map_path) {
  std::string p = map_path;
  while (p.size() > 1 && p.back() == '/') p.pop_back();  // a folder given as "tiles/"
  return p + ".lock";
}

MapLock MapLock::Acquire(const std::string& map_path, const std::string& param) {
  const std::string path = LockPath(map_path);
  // A holder that ends removes the file; whoever opened it just before then
  // holds a lock on a file nobody else sees: check, and try again.
  for (int attempt = 0; attempt < 20; ++attempt) {
    const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0)
      throw InputError(map_path, 0, param, "cannot create the lock file " + path + ": " + std::strerror(errno));
    struct flock fl;
    if (!LockCall(fd, F_OFD_SETLK, &fl)) {
      const int error = errno;
      const int pid = ReadPid(fd);
      close(fd);
      if (error == EAGAIN || error == EACCES)
        throw InputError(map_path, 0, param,
                         "is being written by " + HolderText(pid) + " (it holds " + path +
                             "); wait for it to finish or stop it first");
      throw InputError(map_path, 0, param, "cannot lock " + path + ": " + std::strerror(error));
    }
    struct stat opened, named;
    if (fstat(fd, &opened) == 0 && stat(path.c_str(), &named) == 0 && opened.st_ino == named.st_ino &&
        opened.st_dev == named.st_dev) {
      const std::string pid = std::to_string(getpid()) + "\n";
      if (ftruncate(fd, 0) != 0 || pwrite(fd, pid.data(), pid.size(), 0) < 0) {
        // The pid only serves messages; the lock itself is held.
      }
      MapLock lock;
      lock.fd_ = fd;
      lock.path_ = path;
      return lock;
    }
    close(fd);
  }
  throw InputError(map_path, 0, param, "cannot lock " + path + ": it keeps being replaced");
}

std::optional<int> MapLock::Holder(const std::string& map_path) {
  const std::string path = LockPath(map_path);
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;  // nobody has written it since the file went
  struct flock fl;
  std::optional<int> holder;
  if (LockCall(fd, F_OFD_GETLK, &fl) && fl.l_type != F_UNLCK) holder = ReadPid(fd);
  close(fd);
  return holder;
}

MapLock::MapLock(MapLock&& other) noexcept : fd_(other.fd_), path_(std::move(other.path_)) {
  other.fd_ = -1;
}

MapLock& MapLock::operator=(MapLock&& other) noexcept {
  if (this != &other) {
    Release();
    fd_ = other.fd_;
    path_ = std::move(other.path_);
    other.fd_ = -1;
  }
  return *this;
}

MapLock::~MapLock() {
  Release();
}

void MapLock::Release() {
  if (fd_ < 0) return;
  unlink(path_.c_str());  // while still held: see Acquire
  close(fd_);
  fd_ = -1;
}

}  // namespace seamap
