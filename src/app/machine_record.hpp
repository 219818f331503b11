#pragma once
// What a run or a study's timing was measured on (internal header): host,
// CPU model, load average now, the sources' git commit and the compiler; and
// the provenance block of summary.json. The same pieces as
// bench/machine_info.hpp, read without a shell where Linux allows.
#include <nlohmann/json.hpp>

#include "rigidae/app/provenance.hpp"

namespace rigidae {

// {"host", "cpu_model", "load_average" (1, 5, 15 min), "commit", "compiler"};
// everything but the load average is read once per process. "commit" is the
// build's (build_record), with "-dirty" appended when it was dirty.
nlohmann::json machine_record();

// build_record, run_record, add_provenance: rigidae/app/provenance.hpp.

}  // namespace rigidae
