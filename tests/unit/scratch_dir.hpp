#pragma once
// Output folders of the tests: one per test and process under the system's
// temporary directory (CTest points TMPDIR at the build folder's
// test_scratch, so two checkouts never share one). A folder is removed when
// the test case that made it passes (the listener in main.cpp) and kept when
// it fails, for a look at what the run wrote; RIGIDAE_KEEP_TEST_OUTPUT=1
// keeps every folder. Without the clean-up a full CTest run left ~5 GB
// behind, and every repeat added as much (each case is its own process).
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

namespace rigidae::test {

// Folders made by the test case now running.
inline std::vector<std::filesystem::path>& scratch_dirs_of_this_case() {
  static std::vector<std::filesystem::path> dirs;
  return dirs;
}

// TMPDIR/<group>/<pid>-<name>, emptied; created unless `create` is false
// (a folder the CLI under test must make itself).
inline std::filesystem::path scratch_dir(const std::string& group, const std::string& name, bool create = true) {
  const auto dir = std::filesystem::temp_directory_path() / group / (std::to_string(::getpid()) + "-" + name);
  std::filesystem::remove_all(dir);
  if (create) std::filesystem::create_directories(dir);
  else std::filesystem::create_directories(dir.parent_path());
  scratch_dirs_of_this_case().push_back(dir);
  return dir;
}

}  // namespace rigidae::test
