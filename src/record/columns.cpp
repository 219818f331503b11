// The table of output columns (rigidae/record/columns.hpp). One row per
// column; a group of columns (qw..qz) states its units once, on its first row.
#include "rigidae/record/columns.hpp"

#include "shortest_double.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>

// Rows name only the fields they set; the others keep their defaults by design.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace rigidae::columns {

namespace {

const Observation& obs(const Sample& s) { return *s.observation; }

constexpr unsigned kBoth = kSteps | kTrajectory;

const Column kColumns[] = {
    {"t", "t s", kBoth, Kind::Real, [](const Sample& s) { return s.t; }},
    {"h", "h s", kSteps, Kind::Real, [](const Sample& s) { return s.h; }},
    {"order", "", kSteps, Kind::Integer, nullptr, [](const Sample& s) { return static_cast<long>(s.order); }},
    {"qw", "qw..qz unit quaternion of R_WB (body to space, scalar first)", kBoth, Kind::Real,
     [](const Sample& s) { return obs(s).q_WB(0); }},
    {"qx", "", kBoth, Kind::Real, [](const Sample& s) { return obs(s).q_WB(1); }},
    {"qy", "", kBoth, Kind::Real, [](const Sample& s) { return obs(s).q_WB(2); }},
    {"qz", "", kBoth, Kind::Real, [](const Sample& s) { return obs(s).q_WB(3); }},
    {"omega_x", "omega_* rad/s body frame", kBoth, Kind::Real, [](const Sample& s) { return obs(s).omega_B(0); }},
    {"omega_y", "", kBoth, Kind::Real, [](const Sample& s) { return obs(s).omega_B(1); }},
    {"omega_z", "", kBoth, Kind::Real, [](const Sample& s) { return obs(s).omega_B(2); }},
    {"drift_position", "drift_position |Phi(q)| 1", kBoth, Kind::Real,
     [](const Sample& s) { return obs(s).drift.position; }},
    {"drift_velocity", "drift_velocity |dPhi/dt| 1/s", kBoth, Kind::Real,
     [](const Sample& s) { return obs(s).drift.velocity; }},
    {"multipliers", "lambda_* J (generalized constraint force); mu_* 1/s (kinematic multiplier)", kBoth,
     Kind::Multipliers},
    {"energy", "energy J", kBoth, Kind::Real, [](const Sample& s) { return obs(s).energy; }},
    {"energy_rel_error", "energy_rel_error (H-H0)/|H0|", kBoth, Kind::Real,
     [](const Sample& s) { return obs(s).energy_error; }},
    {"vertical_momentum", "vertical_momentum kg m^2/s about the reference point", kBoth, Kind::Real,
     [](const Sample& s) { return obs(s).vertical_momentum; }},
    {"vertical_momentum_rel_error", "vertical_momentum_rel_error (Lz-Lz0)/|L0|", kBoth, Kind::Real,
     [](const Sample& s) { return obs(s).vertical_momentum_error; }},
    {"chart", "", kBoth, Kind::Chart},
};

// Shortest text that reads back to the same double, in std::to_chars' layout
// (shortest_double.hpp: Dragonbox's digits, half the instructions of
// libstdc++'s to_chars, which took 29% of a recorded heavy-top run), written
// straight into the row's buffer; or in fmt's layout (Digits::Fmt).
template <Digits digits>
void put(fmt::memory_buffer& b, double x, bool first) {
  if constexpr (digits == Digits::Fmt) {
    if (!first) b.push_back(',');
    fmt::format_to(fmt::appender(b), "{}", x);
  } else {
    const std::size_t at = b.size();
    b.resize(at + 1 + record_detail::kShortestMaxBytes);  // no initialisation: only room
    char* p = b.data() + at;
    if (!first) *p++ = ',';
    b.resize(static_cast<std::size_t>(record_detail::write_shortest(p, x) - b.data()));
  }
}

bool shown(const Column& c, File file, bool with_chart) {
  return (c.files & file) && (c.kind != Kind::Chart || with_chart);
}

}  // namespace

std::span<const Column> all() { return kColumns; }

const Table kSingleBody{kColumns, Digits::ToChars};

const Table& single_body() { return kSingleBody; }

std::string units_line(const Table& table) {
  std::string s = "# units:";
  bool first = true;
  for (const Column& c : table.columns) {
    if (c.units.empty()) continue;
    s += first ? " " : "; ";
    s += c.units;
    first = false;
  }
  return s;
}

std::string header(const Table& table, File file, const std::vector<std::string>& multiplier_names,
                   bool with_chart) {
  std::string s;
  auto add = [&](std::string_view name) {
    if (!s.empty()) s += ',';
    s += name;
  };
  for (const Column& c : table.columns) {
    if (!shown(c, file, with_chart)) continue;
    if (c.kind == Kind::Multipliers || c.kind == Kind::Values)
      for (const std::string& m : multiplier_names) add(m);
    else
      add(c.name);
  }
  return s;
}

namespace {

template <Digits digits>
void append_row_as(fmt::memory_buffer& b, std::span<const Column> columns, File file, const Sample& s,
                   bool with_chart) {
  bool first = true;
  for (const Column& c : columns) {
    if (!shown(c, file, with_chart)) continue;
    switch (c.kind) {
      case Kind::Real: put<digits>(b, c.value(s), first); break;
      case Kind::Integer:
        if (!first) b.push_back(',');
        fmt::format_to(fmt::appender(b), "{}", c.integer(s));
        break;
      case Kind::Multipliers: {
        const auto& m = s.observation->multipliers;
        for (int i = 0; i < m.size(); ++i) put<digits>(b, m(i), first && i == 0);
        if (m.size() == 0) continue;  // no column: `first` stays as it was
        break;
      }
      case Kind::Values: {
        const std::span<const double> v = s.values;
        for (std::size_t i = 0; i < v.size(); ++i) put<digits>(b, v[i], first && i == 0);
        if (v.empty()) continue;
        break;
      }
      case Kind::Chart:
        if (!first) b.push_back(',');
        b.append(s.chart.data(), s.chart.data() + s.chart.size());
        break;
    }
    first = false;
  }
  b.push_back('\n');
}

}  // namespace

void append_row(fmt::memory_buffer& b, const Table& table, File file, const Sample& s, bool with_chart) {
  // The layout is chosen once a row, not once a number. The single-body
  // table goes in as the constant array it is: the compiler then sees its
  // columns (a recorded step's row costs 0.5% fewer instructions).
  if (&table == &kSingleBody)
    append_row_as<Digits::ToChars>(b, kColumns, file, s, with_chart);
  else if (table.digits == Digits::Fmt)
    append_row_as<Digits::Fmt>(b, table.columns, file, s, with_chart);
  else
    append_row_as<Digits::ToChars>(b, table.columns, file, s, with_chart);
}

std::vector<NpyField> npy_fields(const Table& table, File file, const std::vector<std::string>& multiplier_names,
                                 bool with_chart) {
  std::vector<NpyField> f;
  for (const Column& c : table.columns) {
    if (!shown(c, file, with_chart)) continue;
    switch (c.kind) {
      case Kind::Real: f.push_back({std::string(c.name), "<f8", 8}); break;
      case Kind::Integer: f.push_back({std::string(c.name), "<i8", 8}); break;
      case Kind::Multipliers:
      case Kind::Values:
        for (const std::string& m : multiplier_names) f.push_back({m, "<f8", 8});
        break;
      case Kind::Chart: f.push_back({std::string(c.name), fmt::format("|S{}", kChartBytes), kChartBytes}); break;
    }
  }
  return f;
}

namespace {
// x's bytes at the end of b (resize, then copy: cheaper than append's loop).
template <typename T>
void put_binary(fmt::memory_buffer& b, T x) {
  const std::size_t at = b.size();
  b.resize(at + sizeof(T));
  std::memcpy(b.data() + at, &x, sizeof(T));
}

void append_binary_row_of(fmt::memory_buffer& b, std::span<const Column> columns, File file, const Sample& s,
                          bool with_chart) {
  for (const Column& c : columns) {
    if (!shown(c, file, with_chart)) continue;
    switch (c.kind) {
      case Kind::Real: put_binary(b, c.value(s)); break;
      case Kind::Integer: put_binary(b, static_cast<std::int64_t>(c.integer(s))); break;
      case Kind::Multipliers: {
        const auto& m = s.observation->multipliers;
        for (int i = 0; i < m.size(); ++i) put_binary(b, m(i));
        break;
      }
      case Kind::Values: {
        const std::size_t at = b.size(), bytes = s.values.size() * sizeof(double);
        b.resize(at + bytes);
        if (bytes) std::memcpy(b.data() + at, s.values.data(), bytes);
        break;
      }
      case Kind::Chart: {
        char name[kChartBytes] = {};  // NumPy's S type: padded with zero bytes
        std::memcpy(name, s.chart.data(), std::min(s.chart.size(), kChartBytes));
        b.append(name, name + kChartBytes);
        break;
      }
    }
  }
}

}  // namespace

void append_binary_row(fmt::memory_buffer& b, const Table& table, File file, const Sample& s, bool with_chart) {
  // As append_row: the single-body table as its constant array.
  if (&table == &kSingleBody)
    append_binary_row_of(b, kColumns, file, s, with_chart);
  else
    append_binary_row_of(b, table.columns, file, s, with_chart);
}

void append_numbers(std::vector<double>& row, const Table& table, File file, const Sample& s, bool with_chart,
                    std::vector<std::string>& charts) {
  for (const Column& c : table.columns) {
    if (!shown(c, file, with_chart)) continue;
    switch (c.kind) {
      case Kind::Real: row.push_back(c.value(s)); break;
      case Kind::Integer: row.push_back(static_cast<double>(c.integer(s))); break;
      case Kind::Multipliers: {
        const auto& m = s.observation->multipliers;
        for (int i = 0; i < m.size(); ++i) row.push_back(m(i));
        break;
      }
      case Kind::Values: row.insert(row.end(), s.values.begin(), s.values.end()); break;
      case Kind::Chart: {
        auto it = std::find(charts.begin(), charts.end(), s.chart);
        if (it == charts.end()) it = charts.insert(charts.end(), std::string(s.chart));
        row.push_back(static_cast<double>(it - charts.begin()));
        break;
      }
    }
  }
}

bool is_multiplier(std::string_view n) { return n.rfind("lambda_", 0) == 0 || n.rfind("mu_", 0) == 0; }
bool is_force_multiplier(std::string_view n) { return n.rfind("lambda_", 0) == 0; }

}  // namespace rigidae::columns
