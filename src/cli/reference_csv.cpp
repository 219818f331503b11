#include "reference_csv.hpp"

#include <fmt/format.h>


#include "rigidae/io/checked_file.hpp"

namespace rigidae::cli {

void write_reference_csv(const ReferenceTrajectory& ref, const std::filesystem::path& path) {
  if (!ref.ok || ref.grid.t.empty()) return;
  // In the layout of the runs it is compared with (record/trajectory_csv.hpp),
  // which the error-against-time figures read.
  write_file_atomically(path, grid_csv_text(ref.grid, "reference: " + ref.describe()));
}

}  // namespace rigidae::cli
