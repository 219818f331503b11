// rigidae compare SCENE: every combination side by side, as a table, a CSV
// and (with --plot) figures drawn by tools/plot_compare.py.
#include <fmt/format.h>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "commands.hpp"
#include "rigidae/app/compare.hpp"
#include "rigidae/core/error.hpp"
#include "plot_script.hpp"
#include "output_folder.hpp"
#include "scene_options.hpp"

namespace rigidae::cli {

const char* kCompareHelp = R"(Options of 'compare' (runs every applicable coordinates x equations x scheme):
  --repeat N              wall time is the median of N runs (default 3)
  --only LIST             comma-separated patterns of combinations to run:
                          'quaternion/*/ggl' globs the whole name, a bare word
                          ('ggl', 'linear', 'index*') matches any one part
                          ('euler' matches both Euler angles and the Euler form)
  --skip LIST             patterns of combinations to leave out
  --reference auto|exact|tight
                          the reference: 'exact' the closed-form solution (free
                          body, symmetric Lagrange top), 'tight' a run of
                          quaternion/euler/ggl at --reference-rtol checked against
                          Euler angles; 'auto' (default) exact when there is one
  --reference-rtol X      tolerance of the tight reference runs (default
                          rtol/100, clamped to [1e-13, 1e-12])
  --out DIR               output folder (default: out/NAME-compare)
  --plot                  draw figures with tools/plot_compare.py into DIR/figures
                          (keeps the step files, which the figures read)
  --keep-steps            keep each run's steps.csv (default: only summary.json,
                          trajectory.csv and events.csv stay)
  --quiet                 no progress lines, no table on stdout
  and every scene override of 'solve' except --coordinates/--equations/--scheme.
Exit code 0 when every run finished, failed combinations included (they are
rows of the table); 1 when the reference could not be computed.
)";

namespace {

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) items.push_back(item);
  return items;
}

}  // namespace

int compare_command(const std::vector<std::string>& args) {
  CompareOptions opt;
  bool quiet = false, plot = false;
  const Scene scene = parse_command_line(args, "compare", [&](const std::string& a, const NextValue& value) {
    if (a == "--quiet") quiet = true;
    else if (a == "--plot") plot = opt.keep_steps = true;
    else if (a == "--keep-steps") opt.keep_steps = true;
    else if (a == "--out") opt.out = value();
    else if (a == "--repeat") {
      const long n = parse_count(a, value());
      if (n > 1000) throw InputError("option --repeat: at most 1000 repeats");
      opt.repeat = static_cast<int>(n);
    } else if (a == "--only") opt.only = split_list(value());
    else if (a == "--skip") opt.skip = split_list(value());
    else if (a == "--reference") opt.reference = value();  // checked by compare_scene
    else if (a == "--reference-rtol") {
      const double x = parse_number(a, value());
      if (!(x > 0 && x < 1)) throw InputError(fmt::format("option --reference-rtol: {} is outside (0, 1)", x));
      opt.reference_rtol = x;
    } else if (a == "--coordinates" || a == "--equations" || a == "--scheme")
      throw InputError(fmt::format("option {} does not apply to compare, which runs every combination; select "
                                   "with --only/--skip (e.g. --only 'quaternion/*/ggl')",
                                   a));
    else return false;
    return true;
  });
  if (opt.out.empty()) opt.out = std::filesystem::path("out") / fmt::format("{}-compare", scene.name.empty() ? "scene" : scene.name);

  create_output_folder(opt.out, /*disposable=*/false);

  const CompareReport report = compare_scene(scene, opt, [&](const std::string& line) {
    if (!quiet) fmt::print(stderr, "{}\n", line);
  });
  write_compare_outputs(report, opt.out);
  if (!quiet) fmt::print("{}", format_compare_table(report));
  if (!quiet) fmt::print("outputs: {}/ (compare.csv, compare.txt, compare.md, one folder per combination)\n", opt.out.string());

  if (plot) {
    std::vector<std::string> plot_args{opt.out.string()};
    if (quiet) plot_args.push_back("--quiet");
    run_plot_script("plot_compare.py", plot_args);
  }
  if (!report.reference.ok) {
    fmt::print(stderr, "rigidae: error: {}\n", report.reference.message);
    return 1;
  }
  return 0;
}

}  // namespace rigidae::cli
