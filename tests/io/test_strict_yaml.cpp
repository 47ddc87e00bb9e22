/// @file test_strict_yaml.cpp
/// @brief The one YAML reader (io::YamlMap): the readers sim, render, massid and LCM use
/// (u64, vectors, lists of maps, raw nodes, nodes without a file, empty values).

#include <gtest/gtest.h>

#include <functional>

#include "io/strict_yaml.h"
#include "io_test_util.h"

namespace vid::io::test {
namespace {

TEST(StrictYaml, U64VectorsAndStrings) {
  const YamlMap y = YamlMap::load_string(
      "seed: 18446744073709551615\nneg: -1\nv: [1, 2, 3.5]\nw: [1, 2]\nnames: [loop, 3]\nflag: true\n",
      "t.yaml");
  EXPECT_EQ(y.get_u64("seed"), 18446744073709551615ull);
  EXPECT_EQ(y.get_u64("missing", 7u), 7u);
  EXPECT_EQ(config_error([&] { y.get_u64("neg"); }), "t.yaml:2: key 'neg': expected a non-negative integer, got '-1'");
  EXPECT_EQ(y.get_vec3("v"), Eigen::Vector3d(1, 2, 3.5));
  EXPECT_EQ(y.get_vec3("missing", Eigen::Vector3d(4, 5, 6)), Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(config_error([&] { y.get_vec3("w"); }), "t.yaml:4: key 'w': expected 3 numbers, got 2");
  EXPECT_EQ(y.get_vec2("w", Eigen::Vector2d::Zero()), Eigen::Vector2d(1, 2));
  EXPECT_EQ(y.get_strings("names"), (std::vector<std::string>{"loop", "3"}));
  EXPECT_TRUE(y.get_bool("flag"));
  EXPECT_EQ(y.line("w"), 4);
  EXPECT_EQ(y.line("missing"), 0);
  EXPECT_EQ(y.first_unknown(), std::nullopt);
}

TEST(StrictYaml, AKeyGivenTwiceIsAnError) {
  // yaml-cpp keeps the first of two equal keys; an override appended to a file would be ignored.
  EXPECT_EQ(config_error([] { YamlMap::load_string("a: 1\nb: 2\na: 3\n", "d.yaml"); }),
            "d.yaml:3: key 'a': given twice (first at line 1)");
  EXPECT_EQ(config_error([] { YamlMap::load_string("m:\n  x: 1\n  x: 2\n", "n.yaml"); }),
            "n.yaml:3: key 'x': given twice (first at line 2)");
  EXPECT_EQ(config_error([] { YamlMap::load_string("l:\n  - {x: 1, x: 2}\n", "s.yaml"); }),
            "s.yaml:2: key 'x': given twice (first at line 2)");
  EXPECT_EQ(YamlMap::load_string("m: {x: 1}\nn: {x: 2}\n", "ok.yaml").get_map("n").get_int("x"), 2);
}

TEST(StrictYaml, ListsOfMapsNameTheirIndex) {
  const YamlMap y = YamlMap::load_string("runs:\n  - {a: 1}\n  - {a: x}\nnot_list: 3\n", "l.yaml");
  const std::vector<YamlMap> runs = y.get_maps("runs");
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].get_int("a"), 1);
  EXPECT_EQ(config_error([&] { runs[1].get_int("a"); }), "l.yaml:3: key 'runs[1].a': expected an integer, got 'x'");
  EXPECT_EQ(config_error([&] { runs[1].get_int("b"); }), "l.yaml: missing required key 'runs[1].b'");
  EXPECT_TRUE(y.get_maps("absent").empty());
  EXPECT_EQ(config_error([&] { y.get_maps("not_list"); }), "l.yaml:4: key 'not_list': expected a list, got '3'");
  EXPECT_EQ(config_error([&] { y.check_unknown(); }), "");
}

TEST(StrictYaml, EmptyValuesCountAsAbsentAndSectionsDefault) {
  const YamlMap y = YamlMap::load_string("a:\nb: ~\nc: {x: 1}\nd: 5\n", "e.yaml");
  EXPECT_FALSE(y.has("a"));
  EXPECT_FALSE(y.has("b"));
  EXPECT_EQ(y.get_double("a", 2.0), 2.0);
  EXPECT_EQ(config_error([&] { y.get_double("b"); }), "e.yaml: missing required key 'b'");
  const YamlMap a = y.get_map_or_empty("a");  // empty value = all defaults
  EXPECT_EQ(a.get_int("x", 9), 9);
  EXPECT_EQ(a.full_key("x"), "a.x");
  EXPECT_EQ(y.get_map_or_empty("c").get_int("x"), 1);
  EXPECT_FALSE(y.get_raw("zz").IsDefined());
  EXPECT_EQ(y.get_raw("d").Scalar(), "5");
  EXPECT_EQ(y.first_unknown(), std::optional<std::string>("b"));
  EXPECT_EQ(config_error([&] { y.check_unknown(); }), "e.yaml:2: unknown key 'b'");
}

TEST(StrictYaml, FromNodeWrapsParsedTrees) {
  const YAML::Node root = YamlMap::parse_string("s:\n  k: 1\nl: [1]\n", "n.yaml");
  const YamlMap s = YamlMap::from_node(root["s"], "n.yaml", "s");
  EXPECT_EQ(s.get_int("k"), 1);
  EXPECT_EQ(config_error([&] { s.get_int("zz"); }), "n.yaml: missing required key 's.zz'");
  EXPECT_EQ(YamlMap::from_node(YAML::Node(), "n.yaml", "none").keys().size(), 0u);
  EXPECT_EQ(config_error([&] { YamlMap::from_node(root["l"], "n.yaml", "l"); }),
            "n.yaml:3: key 'l': expected a mapping, got a sequence");
  EXPECT_NE(config_error([&] { YamlMap::parse_string("a: [1\n", "bad.yaml"); }).find("bad.yaml:"), std::string::npos);
}

}  // namespace
}  // namespace vid::io::test
