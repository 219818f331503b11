#pragma once
// What a run or a study's timing was measured on (internal header): host,
// CPU model, load average now, the sources' git commit and the compiler; and
// the provenance block of summary.json. The same pieces as
// bench/machine_info.hpp, read without a shell where Linux allows.
#include <nlohmann/json.hpp>

namespace rigidae {

// {"host", "cpu_model", "load_average" (1, 5, 15 min), "commit", "compiler"};
// everything but the load average is read once per process. "commit" is the
// build's (build_record), with "-dirty" appended when it was dirty.
nlohmann::json machine_record();

// The sources this binary was built from, recorded at build time
// (cmake/build_info.cmake): {"commit": HEAD or "unknown" outside a git
// checkout, "dirty": tracked files differed from HEAD, "date": UTC ISO 8601
// time of the first build of this state of the sources}.
nlohmann::json build_record();

// This process: {"command_line": its words from /proc/self/cmdline, quoted
// for a POSIX shell where needed, "date": UTC ISO 8601 time of the call}.
nlohmann::json run_record();

// Adds "build" (build_record) and "run" (run_record) to a summary.json
// object: the one place both solve summaries (single body, multibody) get them.
void add_provenance(nlohmann::json& summary);

}  // namespace rigidae
