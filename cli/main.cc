// seamap: one executable, one subcommand per job.
#include <cstdio>
#include <cstring>
#include <string>

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "--help")) {
    std::puts("usage: seamap <simulate|build|info|enhance|enhance-report> [options]");
    return argc < 2 ? 2 : 0;
  }
  std::fprintf(stderr, "seamap: unknown command '%s'\n", argv[1]);
  return 2;
}
