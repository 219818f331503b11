#pragma once
// One factory per scheme file; the table in registry.cpp lists them.
#include <memory>

#include "rigidae/schemes/scheme.hpp"

namespace rigidae::schemes {

std::unique_ptr<ConstraintScheme> make_ggl(const SchemeSettings& settings);
std::unique_ptr<ConstraintScheme> make_index1(const SchemeSettings& settings);
std::unique_ptr<ConstraintScheme> make_index2(const SchemeSettings& settings);
std::unique_ptr<ConstraintScheme> make_index3(const SchemeSettings& settings);
std::unique_ptr<ConstraintScheme> make_baumgarte(const SchemeSettings& settings);
std::unique_ptr<ConstraintScheme> make_projection(const SchemeSettings& settings);

}  // namespace rigidae::schemes
