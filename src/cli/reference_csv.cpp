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
  if (!ref.ok || ref.t.empty()) return;
  std::string s;
  if (ref.multibody) {
    // The tight run's per-body grid, named as a multibody trajectory.csv
    // (BODY.qw .. qz, BODY.wx .. wz, BODY.x .. z): what the error-against-time
    // figures of a multibody compare measure every run against.
    const BodyGrid& g = ref.bodies;
    s = fmt::format(
        "# units: t s; BODY.qw..qz unit quaternion of R_WB (body to space, scalar first); BODY.wx..wz rad/s space "
        "frame; BODY.x..z centre of mass m; reference: {}\n",
        ref.describe());
    s += "t";
    for (const std::string& b : g.bodies)
      for (const char* c : {"qw", "qx", "qy", "qz", "wx", "wy", "wz", "x", "y", "z"}) s += fmt::format(",{}.{}", b, c);
    s += '\n';
    for (std::size_t k = 0; k < g.t.size(); ++k) {
      put(s, g.t[k]);
      for (std::size_t b = 0; b < g.bodies.size(); ++b) {
        for (int i = 0; i < 4; ++i) s += ',', put(s, g.q_WB[k][b](i));
        for (int i = 0; i < 3; ++i) s += ',', put(s, g.omega_W[k][b](i));
        for (int i = 0; i < 3; ++i) s += ',', put(s, g.x_W[k][b](i));
      }
      s += '\n';
    }
    write_file_atomically(path, s);
    return;
  }
  s = fmt::format(
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
