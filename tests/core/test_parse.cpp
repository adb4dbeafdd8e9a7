// Strict text-to-number parsing (core/parse.hpp): the whole text or nothing, never NaN or infinity.
#include <gtest/gtest.h>

#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/core/parse.hpp"

namespace hydrolux::parse {
namespace {

TEST(Parse, Numbers) {
  EXPECT_EQ(number("1.5"), 1.5);
  EXPECT_EQ(number("+4"), 4.0);
  EXPECT_EQ(number("-2e-3"), -2e-3);
  EXPECT_EQ(number(".5"), 0.5);
  EXPECT_EQ(number("1.5e+2"), 150.0);
  for (const char* bad : {"", " ", " 1", "1 ", "1,5", "0x10", "inf", "-inf", "nan", "NaN", "infinity", "1e999",
                          "-1e999", "++1", "+-1", "1.5.2", "abc", "1e", "e5", "\t2", "2\n"})
    EXPECT_EQ(number(bad), std::nullopt) << "'" << bad << "'";
  EXPECT_EQ(number("1e-320"), 1e-320);  // subnormal: finite, accepted
}

TEST(Parse, Integers) {
  EXPECT_EQ(integer("1024"), 1024);
  EXPECT_EQ(integer("1e3"), 1000);
  EXPECT_EQ(integer("-7"), -7);
  EXPECT_EQ(integer("9007199254740992"), 9007199254740992LL);  // 2^53
  EXPECT_EQ(integer("+9007199254740992"), 9007199254740992LL);
  EXPECT_EQ(integer("9007199254740991"), 9007199254740991LL);
  EXPECT_EQ(integer("-4503599627370497"), -4503599627370497LL);
  EXPECT_EQ(integer("5e15"), 5000000000000000LL);  // exponent forms stay whole numbers above 2^52 too
  EXPECT_EQ(integer("9.007199254740992e15"), 9007199254740992LL);
  EXPECT_EQ(integer("90071992547409910e-1"), 9007199254740991LL);
  // Issue 23: 2^53 + 1 and 2^53 + 3 round onto representable doubles (2^53, 2^53 + 4); read as
  // doubles they were accepted as 2^53, a different seed than the one given.
  for (const char* bad : {"1.5", "1e-3", "9007199254740993", "9007199254740994", "9007199254740995",
                          "-9007199254740993", "9007199254740992.5", "4503599627370496.5", "9007199254740990.5",
                          "9007199254740993e0", "1e30", "abc", "", "nan"})
    EXPECT_EQ(integer(bad), std::nullopt) << bad;
}

TEST(Parse, ComplexNumbers) {
  EXPECT_EQ(complex_number("1.333"), std::complex<double>(1.333, 0));
  EXPECT_EQ(complex_number("1.333+1e-8i"), std::complex<double>(1.333, 1e-8));
  EXPECT_EQ(complex_number("1.333-0.5i"), std::complex<double>(1.333, -0.5));
  EXPECT_EQ(complex_number("1.5e+2+3e-2i"), std::complex<double>(150, 0.03));
  EXPECT_EQ(complex_number("-1-2i"), std::complex<double>(-1, -2));
  for (const char* bad : {"", "i", "1+i", "1.333+", "1.333i", "+i", "1+-2i", "1++2i", "1+2j", "nan+1i", "1+infi",
                          "1e999+1i"})
    EXPECT_EQ(complex_number(bad), std::nullopt) << bad;
}

TEST(Parse, Pairs) {
  EXPECT_EQ(pair("256,240.5", ','), (std::array<double, 2>{256, 240.5}));
  EXPECT_EQ(pair("640x480", 'x'), (std::array<double, 2>{640, 480}));
  EXPECT_EQ(pair("640X480", 'x'), (std::array<double, 2>{640, 480}));
  for (const char* bad : {"", "640", "640x", "x480", "640x480x2", "a,b", "1,,2"})
    EXPECT_EQ(pair(bad, bad[0] && std::string(bad).find(',') != std::string::npos ? ',' : 'x'), std::nullopt) << bad;
}

TEST(Parse, RangesAndLists) {
  EXPECT_EQ(range_or_list("0:180:3", 0, 180, 10), (std::vector<double>{0, 90, 180}));
  EXPECT_EQ(range_or_list("5:5:1", 0, 180, 10), (std::vector<double>{5}));
  EXPECT_EQ(range_or_list("0,10,90", 0, 180, 10), (std::vector<double>{0, 10, 90}));
  EXPECT_EQ(range_or_list("1e3:0:2", 0, 1e3, 10), (std::vector<double>{1000, 0}));
  // Rounding never leaves [A, B] (found by fuzz_numbers: ".4:0:4" gave -5.6e-17 < 0, and
  // "0.7:180:7" 180.00000000000003 > 180), and huge ends do not overflow to NaN.
  for (const char* text : {".4:0:4", "0.7:180:7", "0.1:179.9:1000", "180:0:999"})
    for (double v : range_or_list(text, 0, 180, 1000)) EXPECT_TRUE(v >= 0 && v <= 180) << text << " " << v;
  EXPECT_EQ(range_or_list("0.7:180:7", 0, 180, 10).back(), 180.0);
  for (double v : range_or_list("-1e308:1e308:3", -1e308, 1e308, 10)) EXPECT_TRUE(std::isfinite(v));
  for (const char* bad : {"", "0:180", "0:180:0", "0:180:11", "0:180:2.5", "0:200:3", "1,2,", ",1", "0:1:2:3",
                          "a:b:3", "1,2,3,4,5,6,7,8,9,10,11", "-1,0",
                          // Issue 37: one value cannot span A to B; values repeated or out of order
                          // (a span too narrow for N distinct doubles repeats them).
                          "0:180:1", "10,10,20", "0,90,45", "90,0,45", "0:1e-323:10"})
    EXPECT_THROW((void)range_or_list(bad, 0, 180, 10), Error) << bad;
  EXPECT_EQ(range_or_list("90,45,0", 0, 180, 10), (std::vector<double>{90, 45, 0}));
}

}  // namespace
}  // namespace hydrolux::parse

// Messages quote what the user gave: control characters and invalid UTF-8 are escaped so that a
// message stays one line and cannot drive the terminal; valid UTF-8 (accented file names) stays.
TEST(Printable, EscapesControlsAndInvalidUtf8) {
  using hydrolux::printable;
  EXPECT_EQ(printable("plain/path.png"), "plain/path.png");
  EXPECT_EQ(printable("a\nb\rc\td"), "a\\nb\\rc\\td");
  EXPECT_EQ(printable("\x1b[2J"), "\\x1b[2J");
  EXPECT_EQ(printable(std::string("nul\0x", 5)), "nul\\x00x");
  EXPECT_EQ(printable("del\x7f"), "del\\x7f");
  EXPECT_EQ(printable("gr\xc3\xa4" "ben/\xe6\xb0\xb4.png"), "gr\xc3\xa4" "ben/\xe6\xb0\xb4.png");  // Gräben/水.png
  EXPECT_EQ(printable("\xc2\x9b" "31m"), "\\xc2\\x9b31m");  // C1 control CSI
  EXPECT_EQ(printable("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(printable("\xe6\xb0"), "\\xe6\\xb0");              // a sequence cut short
  EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");              // overlong '/'
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");     // a surrogate
}

TEST(Printable, EscapesBackslashesAndInvisibleCharacters) {
  using hydrolux::printable;
  EXPECT_EQ(printable("a\\nb"), "a\\\\nb");                              // a real backslash
  EXPECT_EQ(printable("evil\xe2\x80\xae" "gnp.exe"), "evil\\xe2\\x80\\xaegnp.exe");  // U+202E
  EXPECT_EQ(printable("zero\xe2\x80\x8bwidth"), "zero\\xe2\\x80\\x8bwidth");         // U+200B
  EXPECT_EQ(printable("iso\xe2\x81\xa6late"), "iso\\xe2\\x81\\xa6late");             // U+2066
  EXPECT_EQ(printable("dash\xe2\x80\x94ok"), "dash\xe2\x80\x94ok");                   // U+2014 stays
}

// A message that names parameters between braces: what() says the library's names, said() a door's
// spelling, each quantity the range follows from too; braces doubled stand for themselves, and a
// brace that encloses no name is left as it is.
TEST(Parse, ErrorsSpellTheParametersTheyName) {
  const hydrolux::Spelling flags = [](std::string_view q) { return hydrolux::Param::flag_of(q); };
  const hydrolux::DomainError far("far_m", 5, 10.01, 1e4, "beyond {near_m}");
  EXPECT_STREQ(far.what(), "far_m = 5 is outside [10.01, 10000] (beyond near_m)");
  EXPECT_EQ(far.said(flags), "--far-m 5 is outside the valid range [10.01, 10000] m (beyond --near-m)");
  const hydrolux::DomainError of("wavelength_nm", 100, 200, 1000, "water (IAPWS R9-97)");
  EXPECT_EQ(of.said(flags), "--wavelength-nm 100 is outside the valid range [200, 1000] nm of water (IAPWS R9-97)");
  const hydrolux::ParamError both("{number_per_cm3} and {lwc_g_m3} replace one another");
  EXPECT_STREQ(both.what(), "number_per_cm3 and lwc_g_m3 replace one another");
  EXPECT_EQ(both.said(flags), "--number-per-cm3 and --lwc-g-m3 replace one another");
  const std::string user = "gamma:{nodes} {} {x-y} }";
  EXPECT_EQ(hydrolux::spell_quantities(hydrolux::escape_braces(user), flags), user);
  EXPECT_EQ(hydrolux::spell_quantities("{} {x-y} { {a_b}", flags), "{} {x-y} { --a-b");
  EXPECT_EQ(hydrolux::spell_quantities("{mode=} {=} {mode=half-dome} {a==b} {-a}",
                                       [](std::string_view q) { return "<" + std::string(q) + ">"; }),
            "<mode=> {=} <mode=half-dome> {a==b} {-a}");
}
