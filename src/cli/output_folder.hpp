#pragma once
// Output folders a command creates, so that a command rejected as bad input
// (exit 2) leaves none behind: the error is in the input, and an empty (or
// header-only) folder would only look like a result.
#include <filesystem>

namespace rigidae::cli {

// Creates `dir` (and parents) if missing; throws InputError naming it when
// it cannot. `disposable`: what the command writes there before a rejection
// is worthless (a solve's header-only CSV files) and goes with the folder;
// otherwise the folder is removed only if still empty.
void create_output_folder(const std::filesystem::path& dir, bool disposable);

// Called once, when the command was rejected: removes the folders created
// above by this process (never one that existed before).
void remove_rejected_output_folders() noexcept;

}  // namespace rigidae::cli
