#include "core/nav/csv_table.h"

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;
using ::seamap::testing::WriteFile;
using Fields = std::vector<std::string>;

TEST(CsvTable, DetectsSeparatorFromHeader) {
  EXPECT_EQ(DetectSeparator("a,b,c"), ',');
  EXPECT_EQ(DetectSeparator("a;b;c"), ';');
  EXPECT_EQ(DetectSeparator("a\tb\tc"), '\t');
  EXPECT_EQ(DetectSeparator("a  b c"), ' ');
  EXPECT_EQ(DetectSeparator("\"x,y\";b;c"), ';');  // commas inside quotes do not count
}

TEST(CsvTable, SplitsQuotedFields) {
  EXPECT_EQ(SplitFields(R"(a, "b, c" ,"say ""hi""",)", ','), (Fields{"a", "b, c", "say \"hi\"", ""}));
  EXPECT_EQ(SplitFields("  a \t b   c ", ' '), (Fields{"a", "b", "c"}));
  EXPECT_EQ(SplitFields("1;;3", ';'), (Fields{"1", "", "3"}));
  EXPECT_EQ(SplitFields("\"my photo.jpg\" 1 2", ' '), (Fields{"my photo.jpg", "1", "2"}));
}

TEST(CsvTable, SkipsBomCommentsBlankLinesAndCrLf) {
  TempDir dir;
  auto path = WriteFile(dir / "nav.csv", "\xEF\xBB\xBF# made by hand\r\nimage,alt\r\n\r\n  \r\na.jpg,1.5\r\n# x\r\n");
  const auto lines = ReadTextLines(path.string());
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].number, 2);
  EXPECT_EQ(lines[0].text, "image,alt");
  EXPECT_EQ(lines[1].number, 5);
  EXPECT_EQ(lines[1].text, "a.jpg,1.5");
}

TEST(CsvTable, ReadsOldMacLineEnds) {
  TempDir dir;
  auto path = WriteFile(dir / "nav.csv", "image,alt\ra.jpg,1\rb.jpg,2\r");
  const auto table = ParseCsv(ReadTextLines(path.string()));
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.rows[1].line, 3);
  EXPECT_EQ(table.rows[1].fields, (Fields{"b.jpg", "2"}));
}

TEST(CsvTable, TrailingSeparatorInTheHeaderAddsNoColumn) {
  const auto table = ParseCsv({{1, "image,alt,"}, {2, "a.jpg,1"}, {3, "b.jpg,2,"}});
  EXPECT_EQ(table.header, (Fields{"image", "alt"}));
  EXPECT_EQ(table.rows[1].fields, (Fields{"b.jpg", "2", ""}));
}

TEST(CsvTable, MissingAndEmptyFilesAreFatal) {
  TempDir dir;
  const std::string missing = (dir / "nope.csv").string();
  try {
    ReadTextLines(missing);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), missing);
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
  const auto empty = WriteFile(dir / "empty.csv", "");
  EXPECT_THROW(ReadTextLines(empty.string()), InputError);
  const auto comments = WriteFile(dir / "comments.csv", "# only\n\n");
  EXPECT_THROW(ReadTextLines(comments.string()), InputError);
  EXPECT_THROW(ReadTextLines(dir.path().string()), InputError);  // a folder
}

}  // namespace
}  // namespace seamap
