#pragma once
// What a study's timing was measured on (internal header): host, CPU model,
// load average now, the sources' git commit and the compiler. The same
// pieces as bench/machine_info.hpp, read without a shell where Linux allows.
#include <nlohmann/json.hpp>

namespace rigidae {

// {"host", "cpu_model", "load_average" (1, 5, 15 min), "commit", "compiler"};
// everything but the load average is read once per process.
nlohmann::json machine_record();

}  // namespace rigidae
