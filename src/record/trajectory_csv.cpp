#include "rigidae/record/trajectory_csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "rigidae/core/error.hpp"
#include "rigidae/record/columns.hpp"
#include "rigidae/so3/rotation.hpp"
#include "shortest_double.hpp"

namespace rigidae {

namespace {

// Fills `cells` with the line's comma-separated cells (a trailing empty cell is none).
void split_csv_line(const std::string& line, std::vector<std::string>& cells) {
  cells.clear();
  std::istringstream row(line);
  std::string cell;
  while (std::getline(row, cell, ',')) cells.push_back(cell);
}

}  // namespace

CsvRows::CsvRows(const std::filesystem::path& csv) : path_(csv), in_(std::make_unique<std::ifstream>(csv)) {
  if (!*in_) throw InputError(fmt::format("{}: cannot read", csv.string()));
  read_header();
}

CsvRows::CsvRows(const std::string& text, const std::string& name)
    : path_(name), in_(std::make_unique<std::istringstream>(text)) {
  read_header();
}

void CsvRows::read_header() {
  while (std::getline(*in_, line_))
    if (!line_.empty() && line_[0] != '#') {
      split_csv_line(line_, header_);
      break;
    }
}

std::size_t CsvRows::column(const std::string& name) const {
  const auto it = std::find(header_.begin(), header_.end(), name);
  if (it == header_.end()) throw InputError(fmt::format("{}: no column '{}' in the header", path_.string(), name));
  return static_cast<std::size_t>(it - header_.begin());
}

bool CsvRows::next() {
  if (!std::getline(*in_, line_)) return false;
  split_csv_line(line_, cells_);
  return cells_.size() >= header_.size();
}

double CsvRows::value(std::size_t k) const { return std::strtod(cells_[k].c_str(), nullptr); }

Vec3 BodyGrid::omega_W(std::size_t i, std::size_t b) const {
  return so3::quaternion_to_matrix(q_WB[i][b]) * omega_B[i][b];
}

void BodyGrid::add_point(double t_i, std::vector<Vec4> q, std::vector<Vec3> x, std::vector<Vec3> w_B) {
  t.push_back(t_i);
  q_WB.push_back(std::move(q));
  if (!x.empty()) x_W.push_back(std::move(x));
  omega_B.push_back(std::move(w_B));
}

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The one-body column set's file: t, qw..qz, omega_x..z (body frame), multipliers by name.
BodyGrid read_one_body(CsvRows& rows) {
  const std::vector<std::string>& header = rows.header();
  const std::size_t c_t = rows.column("t"), c_qw = rows.column("qw"), c_wx = rows.column("omega_x");
  BodyGrid g;
  g.layout = GridLayout::OneBody;
  g.bodies = {"body"};
  std::vector<std::size_t> c_mult;
  for (std::size_t k = 0; k < header.size(); ++k)
    if (columns::is_multiplier(header[k])) {
      g.multiplier_names.push_back(header[k]);
      c_mult.push_back(k);
    }
  while (rows.next()) {
    g.add_point(rows.value(c_t),
                {Vec4(rows.value(c_qw), rows.value(c_qw + 1), rows.value(c_qw + 2), rows.value(c_qw + 3))}, {},
                {Vec3(rows.value(c_wx), rows.value(c_wx + 1), rows.value(c_wx + 2))});
    std::vector<double> m(c_mult.size());
    for (std::size_t k = 0; k < c_mult.size(); ++k) m[k] = rows.value(c_mult[k]);
    g.multipliers.push_back(std::move(m));
  }
  return g;
}

// The mechanism column set's file. A body's columns end in BODY.x, .y, .z,
// .vx, .vy, .vz (a rigid body has BODY.qw..qz and BODY.wx..wz before them,
// a particle has none: its orientation is the identity); a marker's
// M.x .. M.vz are followed by M.ax, which tells it from a particle.
BodyGrid read_bodies(CsvRows& rows, const std::filesystem::path& csv) {
  const std::vector<std::string>& header = rows.header();
  BodyGrid g;
  g.layout = GridLayout::Bodies;
  const auto has = [&](const std::string& name) { return std::find(header.begin(), header.end(), name) != header.end(); };
  for (std::size_t k = 0; k + 3 < header.size(); ++k) {
    if (!ends_with(header[k], ".x")) continue;
    const std::string b = header[k].substr(0, header[k].size() - 2);
    const bool marker = k + 6 < header.size() && header[k + 6] == b + ".ax";
    if (header[k + 1] == b + ".y" && header[k + 2] == b + ".z" && header[k + 3] == b + ".vx" && !marker)
      g.bodies.push_back(b);
  }
  if (g.bodies.empty())
    throw InputError(fmt::format("{}: neither a one-body trajectory (t, qw..qz, omega_x..z) nor a mechanism's "
                                 "(BODY.x, BODY.y, BODY.z, BODY.vx per body)",
                                 csv.string()));
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
    std::vector<Vec4> q;
    std::vector<Vec3> x, w;
    for (std::size_t b = 0; b < g.bodies.size(); ++b) {
      q.push_back(cq[b] == kNone ? Vec4(1, 0, 0, 0) : Vec4(v(cq[b]), v(cq[b] + 1), v(cq[b] + 2), v(cq[b] + 3)));
      x.emplace_back(v(cx[b]), v(cx[b] + 1), v(cx[b] + 2));
      const Vec3 w_W = cw[b] == kNone ? Vec3::Zero() : Vec3(v(cw[b]), v(cw[b] + 1), v(cw[b] + 2));
      w.push_back(so3::quaternion_to_matrix(q.back()).transpose() * w_W);
    }
    g.add_point(v(0), std::move(q), std::move(x), std::move(w));
  }
  return g;
}

// Shortest text that reads back to the same double, as the recorder writes it.
void put(std::string& s, double x) {
  char text[record_detail::kShortestMaxBytes];
  s.append(text, record_detail::write_shortest(text, x));
}

}  // namespace

namespace {

BodyGrid read_grid(CsvRows& rows, const std::filesystem::path& csv) {
  const std::vector<std::string>& header = rows.header();
  if (header.empty() || header[0] != "t")
    throw InputError(fmt::format("{}: no header line starting with t", csv.string()));
  if (std::find(header.begin(), header.end(), "qw") != header.end()) return read_one_body(rows);
  return read_bodies(rows, csv);
}

}  // namespace

BodyGrid read_trajectory_csv(const std::filesystem::path& csv) {
  CsvRows rows(csv);
  return read_grid(rows, csv);
}

BodyGrid read_trajectory_text(const std::string& text, const std::string& name) {
  CsvRows rows(text, name);
  return read_grid(rows, name);
}

std::string grid_csv_text(const BodyGrid& g, const std::string& note) {
  std::string s;
  if (g.layout == GridLayout::OneBody) {
    s = "# units: t s; qw..qz unit quaternion of R_WB (body to space, scalar first); omega_* rad/s body frame; " +
        note + "\nt,qw,qx,qy,qz,omega_x,omega_y,omega_z\n";
    for (std::size_t k = 0; k < g.t.size(); ++k) {
      put(s, g.t[k]);
      for (int i = 0; i < 4; ++i) s += ',', put(s, g.q_WB[k][0](i));
      for (int i = 0; i < 3; ++i) s += ',', put(s, g.omega_B[k][0](i));
      s += '\n';
    }
    return s;
  }
  s = "# units: t s; BODY.qw..qz unit quaternion of R_WB (body to space, scalar first); BODY.wx..wz rad/s space "
      "frame; BODY.x..z centre of mass m; " +
      note + "\nt";
  for (const std::string& b : g.bodies)
    for (const char* c : {"qw", "qx", "qy", "qz", "wx", "wy", "wz", "x", "y", "z"}) s += fmt::format(",{}.{}", b, c);
  s += '\n';
  for (std::size_t k = 0; k < g.t.size(); ++k) {
    put(s, g.t[k]);
    for (std::size_t b = 0; b < g.bodies.size(); ++b) {
      const Vec3 w = g.omega_W(k, b);
      const Vec3 x = g.has_positions() ? g.x_W[k][b] : Vec3::Zero();
      for (int i = 0; i < 4; ++i) s += ',', put(s, g.q_WB[k][b](i));
      for (int i = 0; i < 3; ++i) s += ',', put(s, w(i));
      for (int i = 0; i < 3; ++i) s += ',', put(s, x(i));
    }
    s += '\n';
  }
  return s;
}

double max_body_angle(const BodyGrid& a, const BodyGrid& b) {
  const std::size_t n = std::min(a.t.size(), b.t.size());
  const std::size_t nb = std::min(a.bodies.size(), b.bodies.size());
  double m = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < nb; ++k) m = std::max(m, so3::quaternion_distance(a.q_WB[i][k], b.q_WB[i][k]));
  return n > 0 && nb > 0 ? m : std::numeric_limits<double>::quiet_NaN();
}

double max_body_distance(const BodyGrid& a, const BodyGrid& b) {
  const std::size_t n = std::min(a.t.size(), b.t.size());
  const std::size_t nb = std::min(a.bodies.size(), b.bodies.size());
  if (!a.has_positions() || !b.has_positions() || n == 0 || nb == 0) return std::numeric_limits<double>::quiet_NaN();
  double m = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < nb; ++k) m = std::max(m, (a.x_W[i][k] - b.x_W[i][k]).norm());
  return m;
}

}  // namespace rigidae
