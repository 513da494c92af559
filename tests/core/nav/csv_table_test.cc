#include "core/nav/csv_table.h"

#include <chrono>

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

TEST(CsvTable, LongLinesAndFieldsAreBoundedAndReported) {
  TempDir dir;
  const std::string huge(10 << 20, 'c');  // 10 MB
  const std::string field(kMaxFieldBytes + 1, '7');
  const auto path =
      WriteFile(dir / "nav.csv", "image,alt\na.jpg,1\nb.jpg," + huge + "\n# " + huge + "\nc.jpg,2\n" + field + ",3\n");
  const auto lines = ReadTextLines(path.string());
  ASSERT_EQ(lines.size(), 5u);  // the long comment is dropped
  EXPECT_EQ(lines[2].overlong, huge.size() + 6);
  EXPECT_TRUE(lines[2].text.empty());
  const auto table = ParseCsv(lines, path.string());
  ASSERT_EQ(table.rows.size(), 4u);
  EXPECT_EQ(table.rows[1].line, 3);
  EXPECT_EQ(table.rows[1].problem, "line is 10485766 bytes long (limit 65536)");
  EXPECT_EQ(table.rows[2].fields, (Fields{"c.jpg", "2"}));
  EXPECT_EQ(table.rows[3].problem, "field 1 is 4097 bytes long (limit 4096)");
  EXPECT_TRUE(table.rows[3].fields.empty());
}

TEST(CsvTable, ALongHeaderOrColumnNameIsFatalAndNamed) {
  TempDir dir;
  const auto long_line = WriteFile(dir / "a.csv", "# comment\nimage,alt," + std::string(10 << 20, 'c') + "\na,1\n");
  try {
    ReadTextLines(long_line.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_LT(std::string(e.what()).size(), 300u);
    EXPECT_NE(std::string(e.what()).find("bytes long (limit 65536)"), std::string::npos) << e.what();
  }
  const auto long_name = WriteFile(dir / "b.csv", "image,alt," + std::string(kMaxFieldBytes + 1, 'c') + "\na,1,2\n");
  try {
    ParseCsv(ReadTextLines(long_name.string()), long_name.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), long_name.string());
    EXPECT_NE(std::string(e.what()).find("column 3's name is 4097 bytes long (limit 4096)"), std::string::npos)
        << e.what();
  }
}

TEST(CsvTable, LinesOfQuotesSplitInLinearTime) {
  std::string line;
  while (line.size() < kMaxLineBytes - 2) line += "a\"";
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 200; ++i) ASSERT_EQ(SplitFields(line, ',').size(), 1u);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);
}

TEST(CsvTable, ShortenKeepsMessagesShort) {
  EXPECT_EQ(Shorten("abc"), "abc");
  EXPECT_EQ(Shorten(std::string(100, 'x'), 4), "xxxx... (100 bytes)");
}

}  // namespace
}  // namespace seamap
