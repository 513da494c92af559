// FirstInvalidUtf8: well-formed UTF-8 as RFC 3629 defines it.
#include "server/http/utf8.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace seamap::server {
namespace {

TEST(Utf8, WellFormedTextPasses) {
  for (const std::string& text :
       std::vector<std::string>{"", "plain ascii", "caf\xc3\xa9", "\xe2\x82\xac 5", "\xf0\x9f\x90\x9f fish",
                                "\xef\xbf\xbf", "\xf4\x8f\xbf\xbf", std::string("nul\0inside", 10)})
    EXPECT_FALSE(FirstInvalidUtf8(text)) << text;
}

TEST(Utf8, TheFirstBadByteIsFound) {
  struct Case {
    std::string text;
    size_t at;
    const char* what;
  };
  for (const Case& c : std::vector<Case>{
           {"ab\xff", 2, "FF never appears"},
           {"\x80", 0, "a lone continuation byte"},
           {"caf\xc3", 3, "cut short"},
           {"caf\xc3(", 3, "a bad continuation"},
           {"\xc0\xaf", 0, "overlong '/'"},
           {"\xc1\xbf", 0, "overlong"},
           {"\xe0\x80\xaf", 0, "overlong in three bytes"},
           {"\xf0\x80\x80\xaf", 0, "overlong in four bytes"},
           {"x\xed\xa0\x80", 1, "a UTF-16 surrogate"},
           {"\xf4\x90\x80\x80", 0, "past U+10FFFF"},
           {"\xf5\x80\x80\x80", 0, "F5"},
           {"ok \xe2\x82\xac then \xe2\x82", 12, "the second euro is cut short"},
       })
    EXPECT_EQ(FirstInvalidUtf8(c.text), c.at) << c.what;
}

}  // namespace
}  // namespace seamap::server
