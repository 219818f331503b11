// libFuzzer target: the study-file loader and its planner on arbitrary bytes.
//
// A study file names scene files relative to itself, so each input is
// written to SCRATCH/studies/study.toml, with SCRATCH/problems pointing at the
// shipped scenes: the shipped studies' `scenes = ["../problems/..."]` resolve. Every
// input must end in one of two ways: an InputError whose message is one line
// "PATH:LINE:COL: error: ..." (PATH the study file or a scene it names) of
// printable text and reasonable length, or a StudySpec whose values are in
// range and whose plan is non-empty and consistent. Anything else (a crash, a
// sanitizer report, another exception, a malformed message) is a finding.
// Build and run: tools/fuzz.sh --study (docs/robustness.md).
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "rigidae/app/study.hpp"
#include "rigidae/core/error.hpp"
#include "fuzz_check.hpp"

const char* const rigidae_fuzz::kTarget = "fuzz_study_loader";

namespace {

using namespace rigidae;
namespace fs = std::filesystem;

fs::path g_study;  // the scratch study file

using rigidae_fuzz::require;

// "SOMEFILE:LINE:COL: error: ..." on one printable line.
void check_message(const std::string& m) {
  const std::size_t colon = m.find(".toml:");
  require(colon != std::string::npos, "an error message without a .toml file name");
  rigidae_fuzz::check_message_after_file(m, colon + 6);
}

void check_spec(const StudySpec& s) {
  require(!s.scenes.empty(), "a study without scenes");
  require(!s.rtols.empty(), "a study without tolerances");
  for (double r : s.rtols) require(std::isfinite(r) && r > 0 && r < 1, "an rtol out of range");
  if (s.atol_tied)
    require(std::isfinite(s.atol_ratio) && s.atol_ratio > 0, "a bad atol ratio");
  else
    require(std::isfinite(s.atol) && s.atol > 0, "a bad atol");
  require(s.warmups >= 0 && s.repeats >= 1, "bad timing counts");
  for (double t : s.targets) require(std::isfinite(t) && t > 0, "a bad error target");
  if (s.reference_rtol) require(*s.reference_rtol > 0 && *s.reference_rtol < 1, "a bad reference rtol");
  std::vector<StudyRun> runs;
  try {
    runs = plan_study(s);
  } catch (const InputError& e) {
    check_message(e.what());  // e.g. patterns that select nothing
    return;
  }
  for (std::size_t i = 0; i < runs.size(); ++i) {
    require(runs[i].scene < s.scenes.size(), "a run naming a scene that does not exist");
    require(runs[i].rtol > 0 && runs[i].atol > 0, "a run with a bad tolerance");
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::cerr.rdbuf(nullptr);  // the loaders' warnings would flood the fuzzer's output
  const fs::path dir = fs::temp_directory_path() / ("rigidae_fuzz_study_" + std::to_string(::getpid()));
  fs::create_directories(dir / "studies");
  std::error_code ec;
  fs::create_directory_symlink(fs::path(RIGIDAE_SOURCE_DIR) / "problems", dir / "problems", ec);
  g_study = dir / "studies" / "study.toml";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream f(g_study, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    require(static_cast<bool>(f), "could not write the scratch study file");
  }
  StudySpec spec;
  try {
    spec = load_study(g_study.string());
  } catch (const InputError& e) {
    check_message(e.what());
    return 0;
  }
  check_spec(spec);
  return 0;
}
