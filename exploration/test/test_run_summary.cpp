#include <gtest/gtest.h>

#include <algorithm>

#include "exploration/run_summary.h"

namespace exploration {
namespace {

// The summary is read by scripts as JSON: a final text with quotes, backslashes or line breaks
// (a room's name, a path) must stay one valid string.
TEST(RunSummary, TheFinalTextIsOneEscapedJsonString) {
  EXPECT_EQ(jsonEscape("plain text"), "plain text");
  EXPECT_EQ(jsonEscape("a \"door\" at C:\\x\nnext\t\x01"), "a \\\"door\\\" at C:\\\\x\\nnext\\t\\u0001");
  Coordinator coordinator;
  const std::string json = runSummaryJson(coordinator, true, "done: \"all\" rooms", 12.5, 2.5);
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.substr(json.size() - 2), "}\n");
  EXPECT_NE(json.find("\"complete\": true"), std::string::npos);
  EXPECT_NE(json.find("\"real_time_factor\": 5"), std::string::npos);
  EXPECT_NE(json.find("\"text\": \"done: \\\"all\\\" rooms\"}"), std::string::npos) << json;
  EXPECT_EQ(std::count(json.begin(), json.end(), '\n'), 1);
  const std::string failed = runSummaryJson(coordinator, false, "", 0.0, 0.0);
  EXPECT_NE(failed.find("\"complete\": false"), std::string::npos);
  EXPECT_NE(failed.find("\"places\": 0"), std::string::npos);
}

}  // namespace
}  // namespace exploration
