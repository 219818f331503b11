#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <cstdlib>
#include <system_error>

#include "scratch_dir.hpp"

namespace {

// Removes the output folders of a test case that passed (scratch_dir.hpp).
struct ScratchCleaner : doctest::IReporter {
  explicit ScratchCleaner(const doctest::ContextOptions&) {}
  void report_query(const doctest::QueryData&) override {}
  void test_run_start() override {}
  void test_run_end(const doctest::TestRunStats&) override {}
  void test_case_start(const doctest::TestCaseData&) override {}
  void test_case_reenter(const doctest::TestCaseData&) override {}
  void test_case_end(const doctest::CurrentTestCaseStats& stats) override {
    auto& dirs = rigidae::test::scratch_dirs_of_this_case();
    const char* keep = std::getenv("RIGIDAE_KEEP_TEST_OUTPUT");
    const bool keep_all = keep != nullptr && *keep != '\0' && *keep != '0';
    if (stats.testCaseSuccess && !keep_all) {
      std::error_code ignored;  // a folder already gone is fine
      for (const auto& d : dirs) std::filesystem::remove_all(d, ignored);
    }
    dirs.clear();
  }
  void test_case_exception(const doctest::TestCaseException&) override {}
  void subcase_start(const doctest::SubcaseSignature&) override {}
  void subcase_end() override {}
  void log_assert(const doctest::AssertData&) override {}
  void log_message(const doctest::MessageData&) override {}
  void test_case_skipped(const doctest::TestCaseData&) override {}
};

}  // namespace

REGISTER_LISTENER("scratch_cleaner", 1, ScratchCleaner);
