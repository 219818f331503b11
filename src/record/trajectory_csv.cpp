#include "rigidae/record/trajectory_csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "rigidae/core/error.hpp"
#include "rigidae/record/columns.hpp"

namespace rigidae {

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::istringstream row(line);
  std::string cell;
  while (std::getline(row, cell, ',')) cells.push_back(cell);
  return cells;
}

}  // namespace

GridTrajectory read_trajectory_csv(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  if (!in) throw InputError(fmt::format("{}: cannot read", csv.string()));
  std::string line;
  std::getline(in, line);  // units comment
  if (!std::getline(in, line)) throw InputError(fmt::format("{}: no header line", csv.string()));
  const std::vector<std::string> header = split_csv_line(line);
  auto column = [&](const char* name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw InputError(fmt::format("{}: no column '{}' in the header", csv.string(), name));
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t c_t = column("t"), c_qw = column("qw"), c_wx = column("omega_x");
  GridTrajectory g;
  std::vector<std::size_t> c_mult;
  for (std::size_t k = 0; k < header.size(); ++k)
    if (columns::is_multiplier(header[k])) {
      g.multiplier_names.push_back(header[k]);
      c_mult.push_back(k);
    }
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split_csv_line(line);
    if (cells.size() < header.size()) break;  // a row cut short by a crash: the rows before it stand
    auto value = [&](std::size_t k) { return std::strtod(cells[k].c_str(), nullptr); };
    g.t.push_back(value(c_t));
    g.q_WB.emplace_back(value(c_qw), value(c_qw + 1), value(c_qw + 2), value(c_qw + 3));
    g.omega_B.emplace_back(value(c_wx), value(c_wx + 1), value(c_wx + 2));
    std::vector<double> m(c_mult.size());
    for (std::size_t k = 0; k < c_mult.size(); ++k) m[k] = value(c_mult[k]);
    g.multipliers.push_back(std::move(m));
  }
  return g;
}

}  // namespace rigidae
