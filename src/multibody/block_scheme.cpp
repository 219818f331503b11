// The table of per-block schemes (see block_scheme.hpp).
#include "rigidae/multibody/block_scheme.hpp"

#include <array>
#include <string_view>

#include "rigidae/core/error.hpp"

namespace rigidae::multibody {

namespace {

BlockScheme index3(double, double) {
  BlockScheme s{"index3", {}, {}, true, false};
  s.force = {true, false, {1, 0, 0}, {}};
  s.kinematic = {false, true, {}, {1, 0, 0}};
  return s;
}
BlockScheme index2(double, double) {
  BlockScheme s{"index2", {}, {}, false, false};
  s.force = {true, false, {0, 1, 0}, {}};
  s.kinematic = {false, true, {}, {0, 1, 0}};
  return s;
}
BlockScheme index1(double, double) {
  BlockScheme s{"index1", {}, {}, false, false};
  s.force = {true, false, {0, 0, 1}, {}};
  return s;
}
BlockScheme baumgarte(double a, double b) {
  BlockScheme s{"baumgarte", {}, {}, false, false};
  s.force = {true, false, {b * b, 2.0 * a, 1}, {}};
  s.kinematic = {false, true, {}, {a, 1, 0}};
  return s;
}
BlockScheme ggl(double, double) {
  BlockScheme s{"ggl", {}, {}, false, false};
  s.force = {true, true, {0, 1, 0}, {1, 0, 0}};
  s.kinematic = {false, true, {}, {1, 0, 0}};
  return s;
}
BlockScheme projection(double, double) {
  BlockScheme s{"projection", {}, {}, false, true};
  s.force = {true, false, {0, 0, 1}, {}};
  return s;
}

struct Entry {
  std::string_view name;
  BlockScheme (*make)(double, double);
};
constexpr std::array<Entry, 6> kSchemes{{{"index3", index3},
                                         {"index2", index2},
                                         {"index1", index1},
                                         {"baumgarte", baumgarte},
                                         {"ggl", ggl},
                                         {"projection", projection}}};

}  // namespace

BlockScheme make_block_scheme(const std::string& name, double a, double b) {
  for (const Entry& e : kSchemes)
    if (e.name == name) return e.make(a, b);
  std::string valid;
  for (const Entry& e : kSchemes) valid += (valid.empty() ? "" : ", ") + std::string(e.name);
  throw InputError("unknown scheme '" + name + "'; valid schemes: " + valid);
}

}  // namespace rigidae::multibody
