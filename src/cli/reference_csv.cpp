#include "reference_csv.hpp"

#include <fmt/format.h>

#include <charconv>
#include <string>

#include "rigidae/io/checked_file.hpp"

namespace rigidae::cli {

namespace {

// Shortest text that reads back to the same double, as in trajectory.csv.
void put(std::string& s, double x) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, x).ptr;
  s.append(text, end);
}

}  // namespace

void write_reference_csv(const ReferenceTrajectory& ref, const std::filesystem::path& path) {
  // A multibody reference holds its grid per body (ref.bodies): the figures
  // read the tight run's own trajectory.csv (reference/) instead.
  if (!ref.ok || ref.t.empty() || ref.multibody) return;
  std::string s = fmt::format(
      "# units: t s; qw..qz unit quaternion of R_WB (body to space, scalar first); omega_* rad/s body frame; "
      "reference: {}\n",
      ref.describe());
  s += "t,qw,qx,qy,qz,omega_x,omega_y,omega_z\n";
  for (std::size_t k = 0; k < ref.t.size(); ++k) {
    put(s, ref.t[k]);
    for (int i = 0; i < 4; ++i) s += ',', put(s, ref.q_WB[k](i));
    for (int i = 0; i < 3; ++i) s += ',', put(s, ref.omega_B[k](i));
    s += '\n';
  }
  write_file_atomically(path, s);
}

}  // namespace rigidae::cli
