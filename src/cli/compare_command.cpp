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
#include "rigidae/app/command_line.hpp"
#include "output_folder.hpp"
#include "reference_csv.hpp"

namespace rigidae::cli {

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
  const CommandInfo& info = command_info("compare");
  const CommandLine cl = parse_arguments(args, info);
  if (cl.help) {
    fmt::print("{}", command_help(info));
    return 0;
  }
  const Scene scene = scene_from(cl, info);
  CompareOptions opt;
  const bool quiet = cl.has("--quiet"), plot = cl.has("--plot");
  opt.out = cl.text("--out");
  opt.keep_steps = plot || cl.has("--keep-steps");  // the figures read the step files
  if (const auto* n = cl.last("--repeat")) opt.repeat = static_cast<int>(std::get<long long>(*n));
  if (cl.has("--only")) opt.only = split_list(cl.text("--only"));
  if (cl.has("--skip")) opt.skip = split_list(cl.text("--skip"));
  if (const auto* x = cl.last("--reference-rtol")) opt.reference_rtol = std::get<double>(*x);
  if (const auto* x = cl.last("--run-timeout")) opt.run_timeout = std::get<double>(*x);
  opt.keep_going = cl.has("--keep-going");
  opt.error_estimate = !cl.has("--no-error-estimate");
  if (opt.out.empty()) opt.out = std::filesystem::path("out") / fmt::format("{}-compare", scene.name.empty() ? "scene" : scene.name);

  create_output_folder(opt.out, /*disposable=*/false);

  const CompareReport report = compare_scene(scene, opt, [&](const std::string& line) {
    if (!quiet) fmt::print(stderr, "{}\n", line);
  });
  write_compare_outputs(report, opt.out);
  write_reference_csv(report.reference, opt.out / "reference.csv");  // error against time, for the figures
  if (!quiet) fmt::print("{}", format_compare_table(report));
  if (!quiet)
    fmt::print("outputs: {}/ (compare.csv, compare.txt, compare.md, {}one folder per combination)\n", opt.out.string(),
               report.reference.ok ? "reference.csv, " : "");

  if (plot && !report.rows.empty()) {
    std::vector<std::string> plot_args{opt.out.string()};
    if (quiet) plot_args.push_back("--quiet");
    run_plot_script("plot_compare.py", plot_args);
  }
  bool drawn = true;
  if (cl.has("--view") && !report.rows.empty())
    drawn = draw_command_run("view", {opt.out.string(), "--scene", scene.source}) == 0;
  if (!report.stopped.empty()) fmt::print(stderr, "rigidae: compare stopped: {}\n", report.stopped);
  if (!report.reference.ok && !report.interrupted) {
    fmt::print(stderr, "rigidae: error: {}\n", report.reference.message);
    return 1;
  }
  return report.interrupted || !drawn ? 1 : 0;
}

}  // namespace rigidae::cli
