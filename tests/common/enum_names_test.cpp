// EnumNames (core/common/enum_names.hpp): both directions from one table, and the error of an unknown name.
#include <gtest/gtest.h>

#include "core/common/enum_names.hpp"

namespace wish {
namespace {

enum class Colour { Red, Green, Blue };
constexpr EnumNames<Colour, 3> kColourNames{{{{Colour::Red, "red"}, {Colour::Green, "green"}, {Colour::Blue, "blue"}}}};

TEST(EnumNames, NamesAndParsesEveryEntry) {
  for (Colour c : {Colour::Red, Colour::Green, Colour::Blue})
    EXPECT_EQ(kColourNames.parse(kColourNames.name(c), "colour", "colour"), c);
  static_assert(std::string_view(kColourNames.name(Colour::Green)) == "green");  // usable at compile time
  EXPECT_EQ(kColourNames.expected(), "red, green or blue");
}

TEST(EnumNames, AnUnknownNameIsAnInvalidParameterNamingTheChoices) {
  try {
    (void)kColourNames.parse("mauve", "colour", "colour");
    FAIL() << "parsed an unknown name";
  } catch (const InvalidInputError& e) {
    EXPECT_EQ(e.code(), "invalid_parameter");
    EXPECT_STREQ(e.what(), "unknown colour 'mauve' (expected red, green or blue)");
    EXPECT_EQ(std::get<std::string>(e.details().at("colour")), "mauve");
  }
  try {
    (void)kColourNames.parse("", "colour", "colour", "feature_spec");
    FAIL() << "parsed an empty name";
  } catch (const InvalidInputError& e) {
    EXPECT_EQ(e.code(), "feature_spec");
  }
}

}  // namespace
}  // namespace wish
