#include "hoidslam/report/table.h"

#include <gtest/gtest.h>

namespace hoidslam::report {
namespace {

Table Sample() {
  Table table;
  table.title = "ATE RMSE (m)";
  table.note = "median of 5 runs";
  table.header = {"sequence", "hoid2d", "none"};
  table.rows = {{"walking_xyz", "0.0035", "0.0073"}, {"a|b", "failed", "x, \"y\""}};
  return table;
}

TEST(Table, MarkdownHasTitleHeaderRuleRowsAndNote) {
  EXPECT_EQ(Sample().ToMarkdown(),
            "### ATE RMSE (m)\n\n"
            "| sequence | hoid2d | none |\n"
            "|---|---|---|\n"
            "| walking_xyz | 0.0035 | 0.0073 |\n"
            "| a\\|b | failed | x, \"y\" |\n"
            "\n*median of 5 runs*\n");
}

TEST(Table, CsvQuotesCellsWithCommasAndQuotes) {
  EXPECT_EQ(Sample().ToCsv(),
            "sequence,hoid2d,none\r\n"
            "walking_xyz,0.0035,0.0073\r\n"
            "a|b,failed,\"x, \"\"y\"\"\"\r\n");
}

}  // namespace
}  // namespace hoidslam::report
