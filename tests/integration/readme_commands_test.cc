// The README's command line against the binary's: every subcommand
// `seamap --help` lists is in the README's list of subcommands and has a
// section of its own (a "### `seamap NAME`" heading), and the list names no
// command the binary lacks.
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/testing/temp_dir.h"

namespace seamap::testing {
namespace {

std::string ReadReadme() {
  std::ifstream in(std::string(SEAMAP_SOURCE_DIR) + "/README.md");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The names of the "commands:" block of `seamap --help` ("  NAME  what it does").
std::set<std::string> HelpCommands(const std::string& help) {
  std::set<std::string> names;
  std::istringstream lines(help);
  std::string line;
  bool in_commands = false;
  const std::regex entry("^  ([a-z][a-z-]*)( .*)?$");
  while (std::getline(lines, line)) {
    if (line == "commands:") {
      in_commands = true;
    } else if (in_commands) {
      std::smatch m;
      if (!std::regex_match(line, m, entry)) break;
      names.insert(m[1]);
    }
  }
  return names;
}

// The backticked names from "subcommands:" to the next full stop in the README.
std::set<std::string> ReadmeList(const std::string& readme) {
  std::set<std::string> names;
  const size_t start = readme.find("subcommands:");
  if (start == std::string::npos) return names;
  const std::string list = readme.substr(start, readme.find('.', start) - start);
  const std::regex name("`([a-z][a-z-]*)`");
  for (std::sregex_iterator it(list.begin(), list.end(), name), end; it != end; ++it) names.insert((*it)[1]);
  return names;
}

// The commands named in "### " headings as `seamap NAME`.
std::set<std::string> ReadmeSections(const std::string& readme) {
  std::set<std::string> names;
  std::istringstream lines(readme);
  std::string line;
  const std::regex name("`seamap ([a-z][a-z-]*)`");
  while (std::getline(lines, line)) {
    if (line.rfind("### ", 0) != 0) continue;
    for (std::sregex_iterator it(line.begin(), line.end(), name), end; it != end; ++it) names.insert((*it)[1]);
  }
  return names;
}

std::string Join(const std::set<std::string>& names) {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

std::set<std::string> Minus(const std::set<std::string>& a, const std::set<std::string>& b) {
  std::set<std::string> rest;
  for (const std::string& n : a)
    if (!b.count(n)) rest.insert(n);
  return rest;
}

TEST(ReadmeCommands, ParsersReadTheirFormats) {
  EXPECT_EQ(HelpCommands("usage: x\n\ncommands:\n  build     builds\n  trajectory-eval compares\n\nRun ...\n"),
            (std::set<std::string>{"build", "trajectory-eval"}));
  EXPECT_EQ(ReadmeList("with subcommands: `build`, `georef-eval`. `seamap x --help` prints"),
            (std::set<std::string>{"build", "georef-eval"}));
  EXPECT_EQ(ReadmeSections("### `seamap a`, `seamap b-c`: two\ntext `seamap d`\n## `seamap e`\n"),
            (std::set<std::string>{"a", "b-c"}));
}

TEST(ReadmeCommands, ListAndSectionsMatchSeamapHelp) {
  std::string help;
  ASSERT_EQ(RunCommand(SeamapBinary() + " --help", &help), 0) << help;
  const std::set<std::string> commands = HelpCommands(help);
  ASSERT_GE(commands.size(), 10u) << "no command list in seamap --help:\n" << help;

  const std::string readme = ReadReadme();
  ASSERT_FALSE(readme.empty()) << "cannot read " << SEAMAP_SOURCE_DIR << "/README.md";
  const std::set<std::string> listed = ReadmeList(readme);
  EXPECT_TRUE(Minus(commands, listed).empty())
      << "README.md's list of subcommands lacks what seamap --help lists: " << Join(Minus(commands, listed));
  EXPECT_TRUE(Minus(listed, commands).empty())
      << "README.md lists subcommands seamap --help does not: " << Join(Minus(listed, commands));
  const std::set<std::string> sections = ReadmeSections(readme);
  EXPECT_TRUE(Minus(commands, sections).empty())
      << "README.md has no \"### `seamap NAME`\" section for: " << Join(Minus(commands, sections));
  EXPECT_TRUE(Minus(sections, commands).empty())
      << "README.md has sections for commands seamap --help does not list: " << Join(Minus(sections, commands));
}

}  // namespace
}  // namespace seamap::testing
