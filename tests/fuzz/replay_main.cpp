// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A main() for a fuzz target without libFuzzer: feeds every file named on the command line (or
// found directly in a folder named there) to LLVMFuzzerTestOneInput once. The test run builds
// each target with it and replays the seeds and regression inputs under ASan + UBSan, so CI
// checks them without a timed fuzzing run (tests/CMakeLists.txt).
#include <dirent.h>
#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

bool isFolder(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

int replayFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "replay: cannot read %s\n", path.c_str());
    return 1;
  }
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  int replayed = 0, failures = 0;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (!isFolder(arg)) {
      failures += replayFile(arg);
      ++replayed;
      continue;
    }
    DIR* d = opendir(arg.c_str());
    while (dirent* e = d ? readdir(d) : nullptr) {
      const std::string name = e->d_name;
      if (name == "." || name == ".." || name.rfind("README", 0) == 0) continue;
      const std::string path = arg + "/" + name;
      if (isFolder(path)) continue;
      failures += replayFile(path);
      ++replayed;
    }
    if (d) closedir(d);
  }
  std::printf("replay: %d inputs, %d unreadable\n", replayed, failures);
  if (replayed == 0) {
    std::fprintf(stderr, "replay: no inputs\n");
    return 1;
  }
  return failures == 0 ? 0 : 1;
}
