// compare's integrator ranking (app/compare.hpp, rank_integrators; issue 23
// item 4): at each power of ten between the largest and the smallest row
// error, each integrator's fastest row reaching it and the fastest of all,
// checked against a table of rows whose answer is worked out by hand; a
// failed row takes no part; a mechanism is ranked by its position error.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>

#include "rigidae/app/compare.hpp"

TEST_SUITE_BEGIN("unit");

using namespace rigidae;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

CompareRow row(const std::string& scheme, const std::string& integrator, double error, double wall,
               RunStatus status = RunStatus::Success) {
  CompareRow r;
  r.combination = {Coordinates::Quaternion, Equations::Euler, scheme, integrator,
                   integrator == "arkode-erk" ? "fehlberg78" : ""};
  r.outcome.run.status = status;
  r.error_max_rad = error;
  r.accuracy.position_m.max = error * 10;  // what a mechanism is ranked by
  r.wall_median = wall;
  return r;
}

// Errors 2e-4 ... 2e-7 rad: levels 1e-3, 1e-4, 1e-5, 1e-6.
CompareReport report() {
  CompareReport r;
  r.reference.ok = true;
  r.rows = {row("ggl", "ida", 3e-5, 0.050),                  // 0
            row("index1", "ida", 2e-4, 0.010),               // 1
            row("index1", "arkode-erk", 2e-7, 0.002),        // 2
            row("index1", "cvode-adams", 1e-4, 0.003),       // 3: exactly at 1e-4 counts
            row("index1", "cvode-bdf", kNaN, 0.001, RunStatus::Failed),  // 4: no part
            row("projection", "arkode-erk", 2e-7, 0.0025)};  // 5
  return r;
}

}  // namespace

TEST_CASE("compare ranking: each integrator's fastest row at each error level, and the fastest") {
  const IntegratorRanking k = rank_integrators(report());
  CHECK(k.unit == "rad");
  REQUIRE(k.integrators == std::vector<std::string>{"ida", "arkode-erk:fehlberg78", "cvode-adams", "cvode-bdf"});
  REQUIRE(k.levels.size() == 4);
  const std::vector<double> levels{1e-3, 1e-4, 1e-5, 1e-6};
  // Per level: the row of ida, arkode-erk, cvode-adams, cvode-bdf, and the fastest integrator.
  const std::vector<std::vector<int>> rows{{1, 2, 3, -1}, {0, 2, 3, -1}, {-1, 2, -1, -1}, {-1, 2, -1, -1}};
  for (std::size_t i = 0; i < 4; ++i) {
    CAPTURE(i);
    CHECK(k.levels[i].level == doctest::Approx(levels[i]).epsilon(1e-15));
    CHECK(k.levels[i].row == rows[i]);
    CHECK(k.levels[i].fastest == 1);
  }
  // Without the explicit rows (integrators ida, cvode-adams, cvode-bdf; rows
  // 0 ida/ggl, 1 ida/index1, 2 cvode-adams, 3 the failed cvode-bdf):
  // errors 2e-4 ... 3e-5, levels 1e-3 and 1e-4, cvode-adams the fastest at
  // both, IDA's ggl row its best to 1e-4.
  CompareReport without = report();
  without.rows.erase(without.rows.begin() + 5);
  without.rows.erase(without.rows.begin() + 2);
  const IntegratorRanking w = rank_integrators(without);
  REQUIRE(w.integrators == std::vector<std::string>{"ida", "cvode-adams", "cvode-bdf"});
  REQUIRE(w.levels.size() == 2);
  CHECK(w.levels[0].row == std::vector<int>{1, 2, -1});
  CHECK(w.levels[1].row == std::vector<int>{0, 2, -1});
  CHECK(w.levels[0].fastest == 1);
  CHECK(w.levels[1].fastest == 1);
}

TEST_CASE("compare ranking: the printed table marks the fastest and names its row") {
  const std::string text = format_integrator_ranking(report());
  CHECK(text.find("integrators to each error (largest error on the grid, rad, rotation)") != std::string::npos);
  CHECK(text.find("0.002*") != std::string::npos);
  CHECK(text.find("quaternion/euler/index1@arkode-erk:fehlberg78") != std::string::npos);
  // The first level's line: ida 0.01, erk 0.002*, adams 0.003, bdf none.
  const std::size_t at = text.find("1e-03");
  REQUIRE(at != std::string::npos);
  const std::string line = text.substr(at, text.find('\n', at) - at);
  CHECK(line.find(" 0.01 ") < line.find(" 0.002* "));
  CHECK(line.find(" 0.002* ") < line.find(" 0.003 "));
  CHECK(line.find(" 0.003 ") != std::string::npos);
  CHECK(line.find(" - ") != std::string::npos);
  // One integrator, or no reference: nothing to rank.
  CompareReport one = report();
  one.rows.resize(2);
  CHECK(format_integrator_ranking(one).empty());
  CompareReport unreferenced = report();
  unreferenced.reference.ok = false;
  CHECK(format_integrator_ranking(unreferenced).empty());
}

TEST_CASE("compare ranking: no level below the reference's own accuracy") {
  // A row that is the reference's own run (--reference-rtol at the scene's
  // rtol) shows an error of round-off: 1e-19 rad against the reference it
  // is. The levels stop at the reference's accuracy (its cross-check's
  // 2.9e-10 rad: down to 1e-9), where every row that beats it is ranked.
  CompareReport r = report();
  r.rows.push_back(row("ggl", "ida", 1e-19, 0.2));  // 6
  r.reference.accuracy_rad = 2.9e-10;
  const IntegratorRanking k = rank_integrators(r);
  REQUIRE(k.levels.size() == 7);  // 1e-3 ... 1e-9
  CHECK(k.levels.back().level == doctest::Approx(1e-9).epsilon(1e-15));
  CHECK(k.levels.back().row == std::vector<int>{6, -1, -1, -1});
  // A mechanism: the reference's position accuracy in m.
  r.positions = true;
  r.reference.accuracy_m = 3e-6;
  const IntegratorRanking m = rank_integrators(r);
  CHECK(m.levels.back().level == doctest::Approx(1e-5).epsilon(1e-15));
}

TEST_CASE("compare ranking: a mechanism is ranked by its centre-of-mass error in m") {
  CompareReport r = report();
  r.positions = true;
  const IntegratorRanking k = rank_integrators(r);
  CHECK(k.unit == "m");
  REQUIRE(k.levels.size() == 4);  // 2e-3 ... 2e-6 m
  CHECK(k.levels.front().level == doctest::Approx(1e-2).epsilon(1e-15));
  CHECK(k.levels.back().level == doctest::Approx(1e-5).epsilon(1e-15));
}

TEST_SUITE_END();
