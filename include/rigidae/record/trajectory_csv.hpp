#pragma once
// Reading back a run's trajectory.csv (the output grid), as the recorder
// wrote it, into one layout for every scene (BodyGrid). CsvRows is the one
// reader of the recorders' CSV files.
#include <cstddef>
#include <filesystem>
#include <istream>
#include <memory>
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
  // The same rows from a file's text held in memory; `name` stands for the
  // file in messages.
  CsvRows(const std::string& text, const std::string& name);
  // The header's names; empty when the file has no header line.
  const std::vector<std::string>& header() const { return header_; }
  // The index of column `name`; throws InputError naming the file and the column.
  std::size_t column(const std::string& name) const;
  // Reads the next whole row; false at the end.
  bool next();
  // Cell k of the current row as a number (strtod: 0 where it is none).
  double value(std::size_t k) const;

 private:
  void read_header();
  std::filesystem::path path_;
  std::unique_ptr<std::istream> in_;
  std::string line_;
  std::vector<std::string> header_, cells_;
};

// A run's output grid in the one layout every scene reads back into, one
// body or many: per grid point, each body's orientation, centre-of-mass
// position and angular velocity (body frame), plus the multipliers a
// one-body file carries by name. Two column sets write trajectory.csv
// (record/run_columns.hpp): the one-body set (t, qw..qz, omega_x..z in the
// body frame, lambda_*, mu_*; no position: the body turns about a fixed
// point or its centre of mass) and the mechanism set (BODY.qw..qz,
// BODY.x..z, BODY.vx..vz, BODY.wx..wz in the space frame, per body; a
// particle has no BODY.qw and no BODY.wx). The reader below, beside the
// column sets that write them, is the one place that tells them apart.
enum class GridLayout {
  OneBody,  // the one-body column set's (unprefixed, one body named "body")
  Bodies,   // the mechanism column set's (BODY.* per body)
};

struct BodyGrid {
  GridLayout layout = GridLayout::Bodies;
  std::vector<std::string> bodies;          // in column order
  std::vector<double> t;                    // s
  std::vector<std::vector<Vec4>> q_WB;      // [grid point][body], unit quaternion of R_WB, scalar first
  std::vector<std::vector<Vec3>> x_W;       // [grid point][body], m; empty when the file records no position
  std::vector<std::vector<Vec3>> omega_B;   // [grid point][body], rad/s, body components
  std::vector<std::string> multiplier_names;     // "lambda_*", "mu_*", in column order (one-body files)
  std::vector<std::vector<double>> multipliers;  // [grid point][multiplier]
  bool empty() const { return bodies.empty(); }
  bool has_positions() const { return !x_W.empty(); }
  // The angular velocity of body b at point i in space components.
  Vec3 omega_W(std::size_t i, std::size_t b) const;
  // Appends one grid point.
  void add_point(double t_i, std::vector<Vec4> q, std::vector<Vec3> x, std::vector<Vec3> w_B);
};

// Reads either column set's trajectory.csv (or a reference.csv written by
// write_grid_csv). Throws InputError naming the file when it is missing or
// holds neither layout.
BodyGrid read_trajectory_csv(const std::filesystem::path& csv);
// The same from the file's text (`name` for messages): an in-memory run's grid.
BodyGrid read_trajectory_text(const std::string& text, const std::string& name);

// The grid as CSV text in its own layout, after one comment line `# units:
// ...; ` + `note`: the one-body layout t, qw..qz, omega_x..z (body frame);
// the bodies layout t, then per body BODY.qw..qz, BODY.wx..wz (space
// frame), BODY.x..z. Multipliers are not written.
std::string grid_csv_text(const BodyGrid& g, const std::string& note);

// Largest rotation angle (rad) between the two grids' body orientations, over
// the grid points and bodies both have; NaN when they share none.
double max_body_angle(const BodyGrid& a, const BodyGrid& b);
// Largest centre-of-mass distance (m) between them the same way; NaN when
// either records no position or they share no point.
double max_body_distance(const BodyGrid& a, const BodyGrid& b);

}  // namespace rigidae
