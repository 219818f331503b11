#pragma once
// A scene's text with one span replaced, parsed: the loader's error message,
// or "no error". For tests of positioned errors on edited shipped scenes.
#include <string>

#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"

namespace rigidae::test {

inline std::string parse_error_with(std::string text, std::size_t at, std::size_t length,
                                    const std::string& replacement, const std::string& file) {
  text.replace(at, length, replacement);
  try {
    io::parse_scene(text, file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace rigidae::test
