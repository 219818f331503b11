#pragma once
// Reading back a run's trajectory.csv (the output grid), as the recorder
// wrote it: orientation, angular velocity and multipliers by column name.
// CsvRows is the one reader of the recorders' CSV files (single-body here,
// multibody in app/body_grid.cpp).
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "rigidae/core/types.hpp"

namespace rigidae {

// A recorder's CSV file read a row at a time: comment lines ('#') and blank
// lines before the header are passed over; a row with fewer cells than the
// header (cut short by a crash) ends the rows, and the rows before it stand.
class CsvRows {
 public:
  // Throws InputError naming the file when it cannot be opened.
  explicit CsvRows(const std::filesystem::path& csv);
  // The header's names; empty when the file has no header line.
  const std::vector<std::string>& header() const { return header_; }
  // The index of column `name`; throws InputError naming the file and the column.
  std::size_t column(const std::string& name) const;
  // Reads the next whole row; false at the end.
  bool next();
  // Cell k of the current row as a number (strtod: 0 where it is none).
  double value(std::size_t k) const;

 private:
  std::filesystem::path path_;
  std::ifstream in_;
  std::string line_;
  std::vector<std::string> header_, cells_;
};

struct GridTrajectory {
  std::vector<double> t;
  std::vector<Vec4> q_WB;     // unit quaternion of R_WB, scalar first
  std::vector<Vec3> omega_B;  // rad/s, body components
  std::vector<std::string> multiplier_names;  // "lambda_*", "mu_*", in column order
  std::vector<std::vector<double>> multipliers;  // [grid point][multiplier]
};

// Throws InputError naming the file when it is missing or not a trajectory.
GridTrajectory read_trajectory_csv(const std::filesystem::path& csv);

}  // namespace rigidae
