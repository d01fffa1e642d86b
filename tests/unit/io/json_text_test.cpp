// json_string: what summary.json, the results folder's first summary and patterns.json write
// names, paths and messages with must stay one valid JSON string whatever the text holds.
#include "velum/io/json_text.hpp"

#include <gtest/gtest.h>

namespace velum {
namespace {

TEST(JsonString, QuotesPlainText) {
  EXPECT_EQ(json_string("gore 1"), "\"gore 1\"");
  EXPECT_EQ(json_string(""), "\"\"");
}

TEST(JsonString, EscapesQuotesBackslashesAndControlCharacters) {
  EXPECT_EQ(json_string("a \"b\" c:\\d"), R"("a \"b\" c:\\d")");
  EXPECT_EQ(json_string("line\nnext"), R"("line\nnext")");
  EXPECT_EQ(json_string("tab\there\x01"), R"("tab\u0009here\u0001")");
}

TEST(JsonString, KeepsUtf8AsItIs) {
  EXPECT_EQ(json_string("Fallschirm \xC3\xBC"), "\"Fallschirm \xC3\xBC\"");
}

}  // namespace
}  // namespace velum
