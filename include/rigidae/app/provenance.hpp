#pragma once
// Where a result came from: summary.json's "build" and "run" blocks (the
// CLI's summaries, and the Python module's MultibodyRun.summary, which has
// no summary.json of its own). Defined in src/app/machine_record.cpp.
#include <nlohmann/json.hpp>

namespace rigidae {

// The sources this binary was built from, recorded at build time
// (cmake/build_info.cmake): {"commit": HEAD or "unknown" outside a git
// checkout, "dirty": tracked files differed from HEAD, "date": UTC ISO 8601
// time of the first build of this state of the sources}.
nlohmann::json build_record();

// This process: {"command_line": its words from /proc/self/cmdline, quoted
// for a POSIX shell where needed, "date": UTC ISO 8601 time of the call}.
nlohmann::json run_record();

// Adds "build" (build_record) and "run" (run_record) to a summary.json
// object: the one place every summary gets them.
void add_provenance(nlohmann::json& summary);

}  // namespace rigidae
