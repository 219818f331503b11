#pragma once
// Runs the real rigidae binary, as a user would, for the command-line tests.
#include <doctest/doctest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "scratch_dir.hpp"

namespace rigidae::test {

struct CliResult {
  int exit_code;       // -1 if the process did not exit normally (a crash)
  std::string output;  // stdout and stderr
};

// `args` go through the shell: quote anything unusual.
inline CliResult run_cli(const std::string& args) {
  const std::string cmd = std::string(RIGIDAE_CLI) + " " + args + " 2>&1";
  CliResult r{-1, {}};
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// A folder of its own under the system's temporary directory, emptied
// (scratch_dir.hpp: removed when the test passes).
inline std::filesystem::path fresh_temp_dir(const std::string& name) {
  return scratch_dir("rigidae_cli_tests", name);
}

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A CSV file the CLI wrote (compare.csv, ...) as one map per row, column ->
// cell: '#' comment lines and blank lines are passed over, the first other
// line is the header (quoted cells hold no commas in these files).
inline std::vector<std::map<std::string, std::string>> read_csv_rows(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  REQUIRE(in);
  auto split = [](const std::string& l) {
    std::vector<std::string> out;
    std::stringstream ss(l);
    std::string cell;
    while (std::getline(ss, cell, ',')) out.push_back(cell);
    return out;
  };
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) {
      header = split(line);
      continue;
    }
    const std::vector<std::string> cells = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < header.size() && k < cells.size(); ++k) row[header[k]] = cells[k];
    rows.push_back(row);
  }
  return rows;
}

}  // namespace rigidae::test
