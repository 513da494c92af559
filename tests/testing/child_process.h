#pragma once
// A program run in the background by a test (a server, a replay): its stdout
// is read line by line, and it is killed when the test ends, pass or fail.
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include <sys/types.h>

namespace seamap::testing {

class ChildProcess {
 public:
  // Runs argv[0] with the arguments; stderr goes to `stderr_path` (or is discarded).
  explicit ChildProcess(const std::vector<std::string>& argv, const std::string& stderr_path = "");
  ~ChildProcess();  // SIGTERM, then SIGKILL if it does not stop
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // The next stdout line containing `needle`, waiting up to `timeout`.
  std::optional<std::string> WaitForLine(const std::string& needle, std::chrono::seconds timeout);
  // Waits for the exit; the exit code, or nullopt on timeout (0s: has it ended?).
  std::optional<int> Wait(std::chrono::seconds timeout);
  void Signal(int sig);
  // Everything read from stdout so far.
  const std::string& output() const { return output_; }

 private:
  pid_t pid_ = -1;
  int out_fd_ = -1;
  std::string output_;
  size_t consumed_ = 0;
  std::optional<int> exit_code_;
};

// The port in a line like "serving http://127.0.0.1:PORT/ ...", or 0.
int PortFromServingLine(const std::string& line);

}  // namespace seamap::testing
