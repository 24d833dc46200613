// SPDX-License-Identifier: BSD-3-Clause
// A bad model file gets "file:line: what is wrong": unknown node, zero-length element,
// duplicate ids, unknown keys, singular kinematics (naming coordinates and deformations),
// a massless mechanism (naming the coordinates), wrong coordinate counts.
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "common/input_error.hpp"
#include "common/toml_text_check.hpp"
#include "plant/lti/state_space_builder.hpp"
#include "plant/model/linearisation.hpp"
#include "plant/model/model_parser.hpp"

using namespace flexloop::plant;
using flexloop::common::InputError;

namespace {

const std::string kHead = R"([model]
dimension = 2
[[node]]
id = "1"
position = [0.0, 0.0]
[[node]]
id = "2"
position = [1.0, 0.0]
mass = 1.0
)";

std::string error_of(const std::string& text) {
  try {
    const auto m = model::parse_model(text, "bad.toml");
    const auto lin = model::linearise(m);
    lti::build_state_space(m, lin, {}, {});
  } catch (const flexloop::common::InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("model errors: unknown node, with file and line") {
  const auto msg = error_of(kHead + R"([[element]]
id = "s"
type = "truss"
nodes = ["1", "3"]
stiffness = 1.0
[coordinates]
fixed = ["y.1", "y.2", "x.1"]
dynamic = ["e1.s"]
)");
  CHECK_THAT(msg, Catch::Contains("bad.toml:13") && Catch::Contains("unknown node '3'"));
}

TEST_CASE("model errors: zero-length element and duplicate ids") {
  CHECK_THAT(error_of(kHead + R"([[element]]
id = "s"
type = "truss"
nodes = ["1", "1"]
)"),
             Catch::Contains("bad.toml:10") && Catch::Contains("zero-length element"));
  CHECK_THAT(error_of(kHead + R"([[node]]
id = "2"
position = [3.0, 0.0]
)"),
             Catch::Contains("bad.toml:10") && Catch::Contains("duplicate node id '2'"));
}

TEST_CASE("model errors: unknown key and bad values name the line") {
  CHECK_THAT(
      error_of(
          kHead +
          "[[element]]\nid = \"s\"\ntype = \"truss\"\nnodes = [\"1\", \"2\"]\nstifness = 3.0\n"),
      Catch::Contains("bad.toml:14") && Catch::Contains("unknown key 'stifness'"));
  CHECK_THAT(error_of("[model]\ndimension = 4\n"),
             Catch::Contains("bad.toml:2") && Catch::Contains("2 or 3"));
  CHECK_THAT(error_of("[model\n"), Catch::Contains("bad.toml:1"));
}

TEST_CASE("model errors: coordinate counts that do not close") {
  // y.2 neither fixed nor generalised: two dependent coordinates, one equation.
  CHECK_THAT(error_of(kHead + R"([[element]]
id = "s"
type = "truss"
nodes = ["1", "2"]
stiffness = 1.0
[coordinates]
fixed_nodes = ["1"]
dynamic = ["e1.s"]
)"),
             Catch::Contains("2 dependent nodal coordinates but 1"));
}

TEST_CASE("model errors: a singular kinematic Jacobian names the coordinates and deformations") {
  // The truss is along x, so its elongation cannot determine y.2 (with x.2 generalised).
  const auto msg = error_of(kHead + R"([[element]]
id = "s"
type = "truss"
nodes = ["1", "2"]
mode = "rigid"
[coordinates]
fixed_nodes = ["1"]
dynamic = ["x.2"]
)");
  CHECK_THAT(msg, Catch::Contains("singular") && Catch::Contains("y.2") && Catch::Contains("e1.s"));
}

TEST_CASE("model errors: a massless dynamic coordinate is condensed, a massless mechanism named") {
  // Node 2 has no mass: e1.a is a massless dynamic coordinate. With stiffness it follows
  // statically (condensed out of the state); released (no stiffness) it is a mechanism, refused.
  const auto text = [](const std::string& element_a) {
    return R"([model]
dimension = 2
[[node]]
id = "1"
position = [0.0, 0.0]
[[node]]
id = "2"
position = [1.0, 0.0]
[[node]]
id = "3"
position = [2.0, 0.0]
mass = 1.0
[[element]]
id = "a"
type = "truss"
nodes = ["1", "2"]
)" + element_a +
           R"(
[[element]]
id = "b"
type = "truss"
nodes = ["1", "3"]
stiffness = 1.0
[coordinates]
fixed = ["x.1", "y.1", "y.2", "y.3"]
dynamic = ["e1.a", "e1.b"]
)";
  };
  const auto m = model::parse_model(text("stiffness = 1.0"), "massless.toml");
  const auto lin = model::linearise(m);
  lti::Condensation c;
  const auto ss = lti::build_state_space(m, lin, {}, {"pos:e1.a", "pos:e1.b"}, &c);
  CHECK(c.massless_count == 1);
  CHECK(ss.states == std::vector<std::string>{"pos:e1.b", "vel:e1.b"});
  CHECK(c.condensed == std::vector<std::string>{"e1.a"});
  const std::string msg = error_of(text("mode = \"released\""));
  CHECK_THAT(msg, Catch::Contains("massless mechanism") && Catch::Contains("e1.a") &&
                      Catch::Contains("mass matrix"));
}

TEST_CASE("model file: [configuration] sets the operating point, and names bad labels") {
  const std::string base = kHead + R"([[element]]
id = "s"
type = "truss"
nodes = ["1", "2"]
stiffness = 10.0
[coordinates]
fixed = ["x.1", "y.1", "y.2"]
dynamic = ["e1.s"]
)";
  const auto m = model::parse_model(
      base + "[configuration]\nq = { \"e1.s\" = 0.02 }\nqd = { \"e1.s\" = -0.5 }\n", "cfg.toml");
  const auto op = model::model_operating_point(m);
  CHECK(op.q(0) == 0.02);
  CHECK(op.qd(0) == -0.5);
  CHECK(op.qdd(0) == 0.0);
  CHECK_THAT(
      error_of(base + "[configuration]\nq = { \"x.2\" = 1.0 }\n"),
      Catch::Contains("bad.toml:19") && Catch::Contains("'x.2' is not a generalised coordinate"));
}

TEST_CASE("model file: text that is not valid UTF-8 is refused with its line, before toml++") {
  // tests/fuzz found this: invalid UTF-8 in a comment reached __builtin_unreachable in toml++.
  const std::string bad_comment = kHead + "# lens \xC2 frame\n[[element]]\n";
  const std::string e = error_of(bad_comment);
  CHECK(e.find("bad.toml:10") != std::string::npos);
  CHECK(e.find("not valid UTF-8") != std::string::npos);
}

TEST_CASE("UTF-8 validation: valid text passes, each kind of bad sequence is found where it is") {
  using flexloop::common::first_invalid_utf8;
  CHECK_FALSE(flexloop::common::first_invalid_utf8("plain ASCII\n"));
  CHECK_FALSE(flexloop::common::first_invalid_utf8(
      "\xC2\xA7 3, \xCE\xBC"
      "m, \xE2\x88\x9E, \xF0\x9F\x98\x80"));  // §, µ, ∞, U+1F600
  CHECK_FALSE(
      flexloop::common::first_invalid_utf8("\xF4\x8F\xBF\xBF"));  // U+10FFFF, the last code point
  const char* bad[] = {
      "\x80",              // lone continuation byte
      "\xC0\xAF",          // overlong '/'
      "\xC1\xBF",          // overlong
      "\xE0\x80\xAF",      // overlong 3-byte
      "\xED\xA0\x80",      // UTF-16 surrogate U+D800
      "\xF0\x80\x80\xAF",  // overlong 4-byte
      "\xF4\x90\x80\x80",  // above U+10FFFF
      "\xF5\x80\x80\x80",  // lead byte never used
      "\xE2\x88",          // truncated at the end
      "\xE2\x28\xA1",      // bad continuation
  };
  for (const char* b : bad) {
    const std::string text = std::string("a\nb\n") + b + "\n";
    const auto err = flexloop::common::first_invalid_utf8(text);
    REQUIRE(err);
    CHECK(err->line == 3);
    CHECK(err->offset == 4);
  }
}

TEST_CASE("TOML text check: non-ASCII only in comments and string values, else refused by line") {
  // Debian's toml++ 3.3 has undefined behaviour on '°', 'µ', 'Ä', ... wherever it tests them for
  // whitespace (tests/fuzz found two): common/toml_text_check.hpp keeps them where it is safe.
  using flexloop::common::toml_text_problem;
  const char* fine[] = {
      "x = 1  # 5 \xC2\xB5m\n",                       // comment
      "unit = \"m/s\xC2\xB2\"\n",                     // basic string value
      "unit = '\xC2\xB0' # and a quote \" in it\n",   // literal string, quote in a comment
      "note = \"\"\"first\n\xC3\x84 second\"\"\"\n",  // multi-line basic
      "note = '''\\\n\xC3\x84'''\n",                  // multi-line literal: no escapes there
      "x = \"a\\\"\xC3\x84\"\n",                      // escaped quote inside a value
      "a = [\"\xCE\xA9\", '\xCE\xBC']\n",             // values in an array
  };
  for (const char* text : fine) {
    INFO(text);
    CHECK_FALSE(flexloop::common::toml_text_problem(text));
  }
  struct Bad {
    const char* text;
    std::size_t line;
    const char* says;
  };
  const Bad bad[] = {
      {"x = 1\n\xC3\x84\n", 2, "not valid TOML"},
      {"x = [1.0, 2\xC2\xB0]\n", 1, "outside a string or comment"},
      {"\n\"\xC3\x84pfel\" = 1\n", 2, "key with non-ASCII"},
      {"a.\"\xCE\xBC\".b = 1\n", 1, "key with non-ASCII"},
      {"[node.'\xC3\x84']\n", 1, "key with non-ASCII"},
      {"x = \"\"\"\\\xC3\x84\"\"\"\n", 1, "after a backslash"},
      {"x = \"\"\"one \\\n\n   \xC3\x84\"\"\"\n", 3, "after a backslash"},
      {"ok = 'a'\nbad = \xC3\x84\n", 2, "outside a string or comment"},
      // A quote inside a bare token starts no string (toml++ reads on through the token).
      {"x = 8.3'''rot \xCF\xB9'''\n", 1, "on a line that is not valid TOML"},
      {"0=0={'{\xEF\xB3\xBF'\n", 1, "outside a string or comment"},
      {"[a]\nb = 1 2\n# \xC2\xB5\n", 3, "after line 2"},
      {"x = -k'\xDD\xBD'\n", 1, "outside a string or comment"},
  };
  for (const Bad& b : bad) {
    INFO(b.text);
    const auto p = flexloop::common::toml_text_problem(b.text);
    REQUIRE(p);
    CHECK(p->line == b.line);
    CHECK(p->what.find(b.says) != std::string::npos);
  }
}
