#include "tools/common/results_table.h"

#include <gtest/gtest.h>

namespace dynapath::cli {
namespace {

TEST(ResultsTableTest, AlignsColumnsNumbersToTheRight) {
  const std::string csv =
      "Approach,Size,Difficulty,AvgSuccessRate\n"
      "BFS Oracle,20,Hard,1\n"
      "fedAsynQ_EqAvg,20,Hard,0.875\n";
  EXPECT_EQ(ResultsTable(csv),
            "Approach        Size  Difficulty  AvgSuccessRate\n"
            "--------------  ----  ----------  --------------\n"
            "BFS Oracle        20  Hard                     1\n"
            "fedAsynQ_EqAvg    20  Hard                 0.875\n");
}

TEST(ResultsTableTest, CrlfAndHeaderOnly) {
  EXPECT_EQ(ResultsTable("A,B\r\n1,x\r\n"), "A  B\n-  -\n1  x\n");
  EXPECT_EQ(ResultsTable("Approach,Size\n"), "Approach  Size\n--------  ----\n");
  EXPECT_EQ(ResultsTable(""), "");
}

}  // namespace
}  // namespace dynapath::cli
