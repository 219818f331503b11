#pragma once
// Command-line options that override a scene file, shared by the commands.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "rigidae/model/scene.hpp"

namespace rigidae::cli {

// "a, b, c"
std::string valid_list(const std::vector<std::string>& v);
double parse_number(const std::string& opt, const std::string& text);
long parse_count(const std::string& opt, const std::string& text);

// True if opt is a scene override; takes_value says whether a value follows.
bool is_scene_option(const std::string& opt, bool& takes_value);
// Applies one override (checked; InputError names the option and what is valid).
void apply_scene_option(Scene& scene, const std::string& opt, const std::string& text);

// Walks a command's arguments: one positional scene file, the scene
// overrides, and the command's own options, handed to `own` with a function
// that takes the option's value (own returns false for an option it does not
// know). Loads the scene and applies the overrides in order.
using NextValue = std::function<std::string()>;
Scene parse_command_line(const std::vector<std::string>& args, const std::string& command,
                         const std::function<bool(const std::string& opt, const NextValue& value)>& own);

// After the overrides: the time grid they left is within the limits
// (|end| <= kMaxTimeMagnitude, at most kMaxOutputIntervals output intervals).
void check_time_grid(const Scene& scene);

// The help lines of the overrides every command accepts.
extern const char* kSceneOptionsHelp;

}  // namespace rigidae::cli
