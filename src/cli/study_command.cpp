// rigidae study: accuracy studies over a grid of runs, sharded or in one go.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <filesystem>

#include "rigidae/app/command_line.hpp"
#include "commands.hpp"
#include "output_folder.hpp"
#include "plot_script.hpp"
#include "rigidae/app/study.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/core/text.hpp"

namespace rigidae::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct StudyCommandLine {
  std::string action = "all";  // all, list, run, collect
  std::string file;
  fs::path out;
  std::optional<Shard> shard;
  std::string run_id;
  bool plot = true, partial = false, quiet = false, keep_steps = false, error_estimate = true;
};

constexpr std::array<std::string_view, 3> kSubcommands{"list", "run", "collect"};

StudyCommandLine parse(const CommandLine& cl) {
  StudyCommandLine c;
  std::vector<std::string> words = cl.positional;
  if (!words.empty()) {
    const std::string& first = words.front();
    std::error_code ec;
    if (std::find(kSubcommands.begin(), kSubcommands.end(), first) != kSubcommands.end()) {
      c.action = first;
      words.erase(words.begin());
    } else if (!fs::exists(first, ec)) {
      // Not a file: a misspelt subcommand when a study file follows it or it is close to one.
      const std::string hint = did_you_mean(first, {kSubcommands.begin(), kSubcommands.end()});
      if (words.size() > 1 || (!hint.empty() && fs::path(first).extension() != ".toml"))
        throw InputError(fmt::format("unknown study subcommand '{}'{} (valid: list, run, collect, or none to run "
                                     "and collect; see rigidae study --help)",
                                     text::printable(first), hint));
    }
  }
  if (words.empty()) throw InputError("study needs a study file: rigidae study [list|run|collect] STUDY.toml");
  if (words.size() > 1)
    throw InputError(fmt::format("unexpected argument '{}': study takes one study file", text::printable(words[1])));
  c.file = words.front();
  c.out = cl.text("--out");
  if (cl.has("--shard")) c.shard = parse_shard(cl.text("--shard"));
  c.run_id = cl.text("--run");
  c.plot = !cl.has("--no-plot");
  c.partial = cl.has("--partial");
  c.quiet = cl.has("--quiet");
  c.keep_steps = cl.has("--keep-steps");
  c.error_estimate = !cl.has("--no-error-estimate");
  if ((c.shard || !c.run_id.empty()) && c.action != "run")
    throw InputError("--shard and --run apply to 'rigidae study run' only");
  if (c.shard && !c.run_id.empty()) throw InputError("give either --shard or --run, not both");
  return c;
}

// Progress on stderr: one redrawn line on a terminal, else a line every 10 s.
class ProgressLine {
 public:
  explicit ProgressLine(bool quiet) : quiet_(quiet), tty_(isatty(fileno(stderr))) {}
  void update(const StudyProgress& p) {
    if (quiet_) return;
    const auto now = Clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const bool last = p.done == p.total;
    if (!tty_ && !last && now - last_print_ < std::chrono::seconds(10)) return;
    last_print_ = now;
    const std::string line = fmt::format("[{}/{}] {} skipped (complete), {} failed, {:.0f} s | {}", p.done, p.total,
                                         p.skipped, p.failed, elapsed, p.last);
    if (tty_) fmt::print(stderr, "\r\033[K{}{}", line, last ? "\n" : "");
    else fmt::print(stderr, "{}\n", line);
  }

 private:
  bool quiet_, tty_;
  Clock::time_point start_ = Clock::now(), last_print_{};
};

// A word for sh: as it is when it holds nothing special, else in single quotes.
std::string shell_word(const std::string& s) {
  const bool plain = !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("/._-+=:,@%", c);
  });
  if (plain) return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string absolute_path(const fs::path& p) { return shell_word(fs::absolute(p).lexically_normal().string()); }

int collect(const StudySpec& spec, const StudyCommandLine& c) {
  std::vector<std::string> missing;
  const std::string table = collect_study(spec, c.out, &missing);
  if (!c.quiet) fmt::print("{}results: {}\n", table, (c.out / "results.csv").string());
  if (c.plot) {
    std::vector<std::string> args{c.out.string()};
    if (c.quiet) args.push_back("--quiet");
    run_plot_script("plot_study.py", args);
  }
  if (missing.empty()) return 0;
  fmt::print(stderr, "rigidae: {} {} of the study have no complete folder yet (first: {}); run them with 'rigidae "
                     "study run' and collect again\n",
             missing.size(), missing.size() == 1 ? "run" : "runs", missing.front());
  return c.partial ? 0 : 1;
}

}  // namespace

int study_command(const std::vector<std::string>& args) {
  const CommandInfo& info = command_info("study");
  const CommandLine cl = parse_arguments(args, info);
  if (cl.help) {
    fmt::print("{}", command_help(info));
    return 0;
  }
  StudyCommandLine c = parse(cl);
  const StudySpec spec = load_study(c.file);
  if (c.out.empty()) c.out = fs::path("out") / spec.name;
  std::error_code ec;
  create_output_folder(c.out, /*disposable=*/false);

  const std::vector<StudyRun> plan = plan_study(spec);
  if (c.action == "list") {
    const std::string exe = fs::read_symlink("/proc/self/exe", ec).string();
    for (const StudyRun& r : plan)
      fmt::print("{} study run {} --out {} --run {} --quiet\n", ec ? "rigidae" : shell_word(exe),
                 absolute_path(c.file), absolute_path(c.out), shell_word(r.id(spec)));
    return 0;
  }
  if (c.action == "collect") return collect(spec, c);

  std::vector<StudyRun> todo = plan;
  if (!c.run_id.empty()) {
    todo.clear();
    for (const StudyRun& r : plan)
      if (r.id(spec) == c.run_id) todo.push_back(r);
    if (todo.empty())
      throw InputError(fmt::format("--run '{}': no such run in {} (see 'rigidae study list {}')", c.run_id, c.file,
                                   c.file));
  } else if (c.action == "run") {
    const std::optional<Shard> shard = c.shard ? c.shard : shard_from_slurm();
    if (!shard)
      throw InputError("rigidae study run needs --shard i/N, --run ID, or a Slurm array job (SLURM_ARRAY_TASK_ID)");
    todo = select_shard(plan, *shard);
  }
  ProgressLine progress(c.quiet);
  StudyRunOptions opt;
  opt.out = c.out;
  opt.keep_steps = c.keep_steps;
  opt.error_estimate = c.error_estimate;
  opt.progress = [&](const StudyProgress& p) { progress.update(p); };
  opt.note = [](const std::string& line) { fmt::print(stderr, "rigidae: note: {}\n", line); };
  if (!run_study(spec, todo, opt)) {
    fmt::print(stderr, "\nrigidae: study interrupted; complete runs are kept, rerun the same command to resume\n");
    return 1;
  }
  if (c.action == "all") return collect(spec, c);
  return 0;
}

}  // namespace rigidae::cli
