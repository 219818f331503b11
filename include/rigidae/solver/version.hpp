#pragma once
// The SUNDIALS version rigidae was built against, for reports (so that no
// module outside solver/ includes a SUNDIALS header).
#include <string>

namespace rigidae {

std::string sundials_version();

}  // namespace rigidae
