// parseRegressSuite: paths resolved against the suite's folder, tolerances merged over the suite-wide ones,
// and bad suites refused naming the file, the case and the key.
#include <gtest/gtest.h>

#include "tools/regress_suite.h"

namespace ropecast::tools {
namespace {

// The message of the SuiteError that parsing `text` throws ("" when it parses).
std::string refusal(const std::string& text) {
  try {
    parseRegressSuite(text, "dir/suite.json");
  } catch (const SuiteError& e) {
    return e.what();
  }
  return "";
}

TEST(RegressSuite, ResolvesPathsAgainstTheSuiteFolder) {
  const RegressSuite suite = parseRegressSuite(
      R"({"cases": [{"name": "a", "input": "data/s.rcast", "options": ["--size", "8x8"], "golden": "g/a.png"},
                    {"name": "b", "input": "procedural:sphere:16", "golden": "/abs/b.png"}]})",
      "dir/suite.json");
  ASSERT_EQ(suite.cases.size(), 2u);
  EXPECT_EQ(suite.cases[0].input, "dir/data/s.rcast");
  EXPECT_EQ(suite.cases[0].golden, "dir/g/a.png");
  EXPECT_EQ(suite.cases[0].options, (std::vector<std::string>{"--size", "8x8"}));
  EXPECT_EQ(suite.cases[1].input, "procedural:sphere:16");
  EXPECT_EQ(suite.cases[1].golden, "/abs/b.png");
  EXPECT_TRUE(suite.cases[1].options.empty());
}

TEST(RegressSuite, CaseTolerancesOverrideTheSuiteWideOnes) {
  const RegressSuite suite = parseRegressSuite(
      R"({"tolerances": {"min_psnr_db": 35, "max_failing_share": 0.01},
          "cases": [{"name": "a", "input": "procedural:sphere:16", "golden": "a.png",
                     "tolerances": {"max_failing_share": 0}},
                    {"name": "b", "input": "procedural:sphere:16", "golden": "b.png"}]})",
      "suite.json");
  const RegressTolerances builtIn;
  EXPECT_EQ(suite.cases[0].tolerances.minPsnrDb, 35.0);
  EXPECT_EQ(suite.cases[0].tolerances.maxFailingShare, 0.0);
  EXPECT_EQ(suite.cases[0].tolerances.maxPixelError, builtIn.maxPixelError);
  EXPECT_EQ(suite.cases[1].tolerances.maxFailingShare, 0.01);
  EXPECT_EQ(suite.cases[1].tolerances.failingPixelError, builtIn.failingPixelError);
}

TEST(RegressSuite, RefusesBadSuitesNamingTheKey) {
  EXPECT_NE(refusal("{\"cases\": [").find("dir/suite.json: not valid JSON"), std::string::npos);
  EXPECT_NE(refusal(R"({"cases": [{"max_abs": 1e999}]})").find("dir/suite.json: not valid JSON"),
            std::string::npos);
  EXPECT_EQ(refusal("{\"cases\": []}"), "dir/suite.json: expected \"cases\": a non-empty array of cases");
  EXPECT_EQ(refusal(R"({"cases": [{"name": "a", "input": "x", "golden": "a.png"}], "cases": [{"name": "b",
                        "input": "x", "golden": "b.png"}]})"),
            "dir/suite.json: the key \"cases\" is given twice in one object (only the last would count)");
  EXPECT_NE(refusal(R"({"cases": [{"name": "a", "input": "procedural:sphere:8", "golden": "a.jpg"}]})")
                .find("case 'a'.golden: dir/a.jpg: expected a PNG file"),
            std::string::npos);
  EXPECT_EQ(refusal(R"({"cases": [{"name": "a", "golden": "a.png"}]})"),
            "dir/suite.json: case 'a': missing \"input\"");
  EXPECT_EQ(refusal(R"({"cases": [{"name": "a/b", "input": "x", "golden": "a.png"}]})"),
            "dir/suite.json: cases[0].name: 'a/b': expected letters, digits, '_', '-' and '.', not starting "
            "with '.' (names become file names)");
  EXPECT_NE(refusal(R"({"cases": [{"name": ".hidden", "input": "x", "golden": "a.png"}]})")
                .find("not starting with '.'"),
            std::string::npos);
  EXPECT_EQ(
      refusal(R"({"cases": [{"name": "a", "input": "x", "golden": "a.png", "options": "--size 8x8"}]})"),
      "dir/suite.json: case 'a'.options: expected an array of strings");
  EXPECT_EQ(refusal(R"({"case": [], "cases": [{"name": "a", "input": "x", "golden": "a.png"}]})"),
            "dir/suite.json: unknown key 'case' (expected cases, tolerances, description)");
  EXPECT_EQ(
      refusal(
          R"({"tolerances": {"min_psnr_db": -1}, "cases": [{"name": "a", "input": "x", "golden": "a.png"}]})"),
      "dir/suite.json: tolerances.min_psnr_db: expected a number in [0, inf), got -1");
  EXPECT_EQ(refusal(R"({"cases": [{"name": "a", "input": "x", "golden": "a.png"},
                                   {"name": "a", "input": "x", "golden": "b.png"}]})"),
            "dir/suite.json: cases[1].name: 'a' names two cases");
}

}  // namespace
}  // namespace ropecast::tools
