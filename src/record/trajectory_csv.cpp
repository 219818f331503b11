#include "rigidae/record/trajectory_csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>

#include "rigidae/core/error.hpp"
#include "rigidae/record/columns.hpp"

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

CsvRows::CsvRows(const std::filesystem::path& csv) : path_(csv), in_(csv) {
  if (!in_) throw InputError(fmt::format("{}: cannot read", csv.string()));
  while (std::getline(in_, line_))
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
  if (!std::getline(in_, line_)) return false;
  split_csv_line(line_, cells_);
  return cells_.size() >= header_.size();
}

double CsvRows::value(std::size_t k) const { return std::strtod(cells_[k].c_str(), nullptr); }

GridTrajectory read_trajectory_csv(const std::filesystem::path& csv) {
  CsvRows rows(csv);
  const std::vector<std::string>& header = rows.header();
  if (header.empty()) throw InputError(fmt::format("{}: no header line", csv.string()));
  const std::size_t c_t = rows.column("t"), c_qw = rows.column("qw"), c_wx = rows.column("omega_x");
  GridTrajectory g;
  std::vector<std::size_t> c_mult;
  for (std::size_t k = 0; k < header.size(); ++k)
    if (columns::is_multiplier(header[k])) {
      g.multiplier_names.push_back(header[k]);
      c_mult.push_back(k);
    }
  while (rows.next()) {
    g.t.push_back(rows.value(c_t));
    g.q_WB.emplace_back(rows.value(c_qw), rows.value(c_qw + 1), rows.value(c_qw + 2), rows.value(c_qw + 3));
    g.omega_B.emplace_back(rows.value(c_wx), rows.value(c_wx + 1), rows.value(c_wx + 2));
    std::vector<double> m(c_mult.size());
    for (std::size_t k = 0; k < c_mult.size(); ++k) m[k] = rows.value(c_mult[k]);
    g.multipliers.push_back(std::move(m));
  }
  return g;
}

}  // namespace rigidae
