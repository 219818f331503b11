// Output folders a rejected command leaves no trace of (output_folder.hpp).
#include "output_folder.hpp"

#include <fmt/format.h>

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "rigidae/core/error.hpp"

namespace rigidae::cli {

namespace {

namespace fs = std::filesystem;

struct Created {
  fs::path dir;  // the outermost folder this process created
  bool disposable;
};

std::vector<Created>& created() {
  static std::vector<Created> list;
  return list;
}

}  // namespace

void create_output_folder(const fs::path& dir, bool disposable) {
  std::error_code ec;
  // The outermost missing ancestor is what this process creates.
  fs::path first_missing;
  for (fs::path p = dir; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    first_missing = p;
    if (p == p.parent_path()) break;
  }
  fs::create_directories(dir, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create output folder: {}", dir.string(), ec.message()));
  if (!first_missing.empty()) created().push_back({first_missing, disposable});
  // A folder that exists but cannot be written is bad input for every
  // command alike (exit 2, nothing run), not a failure found midway.
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw InputError(fmt::format("{}: output folder is not writable: {} (give another --out, or make it writable)",
                                 dir.string(), std::strerror(errno)));
}

void remove_rejected_output_folders() noexcept {
  for (const Created& c : created()) {
    std::error_code ec;
    if (c.disposable) {
      fs::remove_all(c.dir, ec);
      continue;
    }
    // Only empty folders, innermost first: a folder with results stays.
    std::vector<fs::path> dirs{c.dir};
    for (auto it = fs::recursive_directory_iterator(c.dir, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec))
      if (it->is_directory(ec)) dirs.push_back(it->path());
    for (auto d = dirs.rbegin(); d != dirs.rend(); ++d)
      if (fs::is_empty(*d, ec)) fs::remove(*d, ec);
  }
  created().clear();
}

}  // namespace rigidae::cli
