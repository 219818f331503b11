// Reading a multibody trajectory.csv (see body_grid.hpp).
#include "rigidae/app/body_grid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "rigidae/core/error.hpp"
#include "rigidae/record/trajectory_csv.hpp"
#include "rigidae/so3/rotation.hpp"

namespace rigidae {

BodyGrid read_body_grid(const std::filesystem::path& csv) {
  CsvRows rows(csv);
  const std::vector<std::string>& header = rows.header();
  if (header.empty() || header[0] != "t")
    throw InputError(fmt::format("{}: no header line starting with t", csv.string()));
  BodyGrid g;
  // Bodies: BODY.x followed by BODY.y, BODY.z, BODY.vx (a rigid body has
  // BODY.qw..wz before them, a particle has none: its orientation is the
  // identity).
  const auto has = [&](const std::string& name) { return std::find(header.begin(), header.end(), name) != header.end(); };
  const std::string suffix = ".x";
  for (std::size_t k = 0; k + 3 < header.size(); ++k) {
    const std::string& h = header[k];
    if (h.size() <= suffix.size() || h.compare(h.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
    const std::string b = h.substr(0, h.size() - suffix.size());
    if (header[k + 1] == b + ".y" && header[k + 2] == b + ".z" && header[k + 3] == b + ".vx") g.bodies.push_back(b);
  }
  if (g.bodies.empty())
    throw InputError(fmt::format("{}: no BODY.x, BODY.y, BODY.z, BODY.vx columns: not a multibody trajectory", csv.string()));
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::vector<std::size_t> cq, cx, cw;
  for (const std::string& b : g.bodies) {
    const bool rigid = has(b + ".qw");
    cq.push_back(rigid ? rows.column(b + ".qw") : kNone);
    cx.push_back(rows.column(b + ".x"));
    cw.push_back(rigid ? rows.column(b + ".wx") : kNone);
  }
  while (rows.next()) {
    auto v = [&](std::size_t k) { return rows.value(k); };
    g.t.push_back(v(0));
    std::vector<Vec4> q;
    std::vector<Vec3> x, w;
    for (std::size_t b = 0; b < g.bodies.size(); ++b) {
      q.push_back(cq[b] == kNone ? Vec4(1, 0, 0, 0) : Vec4(v(cq[b]), v(cq[b] + 1), v(cq[b] + 2), v(cq[b] + 3)));
      x.emplace_back(v(cx[b]), v(cx[b] + 1), v(cx[b] + 2));
      w.push_back(cw[b] == kNone ? Vec3::Zero() : Vec3(v(cw[b]), v(cw[b] + 1), v(cw[b] + 2)));
    }
    g.q_WB.push_back(std::move(q));
    g.x_W.push_back(std::move(x));
    g.omega_W.push_back(std::move(w));
  }
  return g;
}

double max_body_angle(const BodyGrid& a, const BodyGrid& b) {
  const std::size_t n = std::min(a.t.size(), b.t.size());
  const std::size_t nb = std::min(a.bodies.size(), b.bodies.size());
  double m = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < nb; ++k) m = std::max(m, so3::quaternion_distance(a.q_WB[i][k], b.q_WB[i][k]));
  return n > 0 && nb > 0 ? m : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace rigidae
