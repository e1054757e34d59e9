// Exemplars: the five built-ins of Fig. 2 and inline JSON documents with errors naming the
// JSON path.
#include <gtest/gtest.h>

#include "host/core/error.h"
#include "host/pattern/exemplar.h"

namespace cutwork {
namespace {
using nlohmann::json;

TEST(Exemplar, BuiltinsAreValidAndRespectTheSafetyGap) {
  ASSERT_EQ(builtin_exemplar_names(), (std::vector<std::string>{"packing", "flowers", "stripes", "circles", "mix"}));
  for (const auto& name : builtin_exemplar_names()) {
    const Exemplar ex = builtin_exemplar(name);
    // Enough elements for r_N = 0.3 neighbourhoods of ~6–12 members around several centres.
    EXPECT_GE(ex.elements.size(), 30u) << name;
    EXPECT_LE(ex.elements.size(), 70u) << name;
    EXPECT_DOUBLE_EQ(ex.size(), 1.0);
    for (size_t i = 0; i < ex.elements.size(); ++i) {
      EXPECT_TRUE(ex.contains(ex.elements[i].position)) << name;
      EXPECT_GE(ex.distance_to_boundary(ex.elements[i].position), ex.elements[i].scale - 1e-12) << name;
      for (size_t j = i + 1; j < ex.elements.size(); ++j) {
        const double d = (ex.elements[i].position - ex.elements[j].position).norm();
        EXPECT_GE(d, 1.3 * (ex.elements[i].scale + ex.elements[j].scale) - 1e-12) << name << " " << i << " " << j;
      }
    }
    // Deterministic.
    const Exemplar again = builtin_exemplar(name);
    ASSERT_EQ(again.elements.size(), ex.elements.size());
    for (size_t i = 0; i < ex.elements.size(); ++i) EXPECT_EQ(again.elements[i].position, ex.elements[i].position);
  }
  EXPECT_EQ(builtin_exemplar("stripes").symmetry, 2);
  EXPECT_EQ(builtin_exemplar("circles").symmetry, 4);
  EXPECT_EQ(builtin_exemplar("mix").type_names.size(), 3u);
  EXPECT_THROW(builtin_exemplar("dots"), InputError);
}

TEST(Exemplar, BuiltinTypesCycleOverTheStencils) {
  const Exemplar mix = builtin_exemplar("mix");
  EXPECT_EQ(map_exemplar_types(mix, {"star", "circle"}), (std::vector<int>{0, 1, 0}));
  EXPECT_EQ(map_exemplar_types(mix, {"flower"}), (std::vector<int>{0, 0, 0}));
}

TEST(Exemplar, InlineRectangleAndPolygon) {
  const json doc = json::parse(R"({
    "domain": [2, 1],
    "elements": [{"position": [0.5, 0.5], "scale": 0.1, "type": "circle"},
                 {"position": [1.5, 0.5], "scale": 0.2, "type": "star", "angle": 0.3},
                 {"position": [1.0, 0.5], "scale": 0.1}],
    "symmetry": 2})");
  const Exemplar ex = parse_exemplar(doc, "scene.json", "/pattern/exemplar");
  EXPECT_EQ(ex.domain.size(), 4u);
  EXPECT_DOUBLE_EQ(ex.size(), 2.0);
  EXPECT_DOUBLE_EQ(ex.area(), 2.0);
  EXPECT_EQ(ex.symmetry, 2);
  ASSERT_EQ(ex.elements.size(), 3u);
  EXPECT_DOUBLE_EQ(ex.elements[1].angle, 0.3);
  EXPECT_EQ(map_exemplar_types(ex, {"star", "circle"}, "scene.json", "/pattern/exemplar"),
            (std::vector<int>{1, 0, 0}));  // circle, star, (none: the first stencil)

  // A clockwise polygon is reoriented.
  const json poly = json::parse(R"({"domain": [[0,0],[0,1],[1,1],[1,0]],
                                     "elements": [{"position": [0.5, 0.5], "scale": 0.1}]})");
  const Exemplar p = parse_exemplar(poly, "s", "/e");
  EXPECT_GT(p.area(), 0);
  EXPECT_NEAR(p.distance_to_boundary(Vec2(0.5, 0.5)), 0.5, 1e-15);
  EXPECT_NEAR(p.distance_to_boundary(Vec2(1.5, 0.5)), -0.5, 1e-15);
}

TEST(Exemplar, InlineErrorsNameTheJsonPath) {
  auto expect_error = [](const char* text, const std::string& fragment) {
    try {
      parse_exemplar(json::parse(text), "scene.json", "/pattern/exemplar");
      ADD_FAILURE() << "expected InputError for " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expect_error(R"({"elements": [{"position": [0,0], "scale": 1}]})", "/pattern/exemplar/domain: is required");
  expect_error(R"({"domain": [0, 1], "elements": []})", "/pattern/exemplar/domain: width and height");
  expect_error(R"({"domain": [1, 1], "elements": []})", "/pattern/exemplar/elements: is required");
  expect_error(R"({"domain": [1, 1], "elements": [{"scale": 1}]})", "/pattern/exemplar/elements/0/position: is required");
  expect_error(R"({"domain": [1, 1], "elements": [{"position": [2, 0.5], "scale": 0.1}]})",
               "/pattern/exemplar/elements/0/position: (2, 0.5) lies outside");
  expect_error(R"({"domain": [1, 1], "elements": [{"position": [0.5, 0.5], "scale": -1}]})",
               "/pattern/exemplar/elements/0/scale: must be > 0");
  expect_error(R"({"domain": [1, 1], "elements": [{"position": [0.5, 0.5], "scale": 1, "colour": 3}]})",
               "/pattern/exemplar/elements/0");
  expect_error(R"({"domain": [[0,0],[1,1],[1,0],[0,1]], "elements": [{"position": [0.5, 0.5], "scale": 0.1}]})",
               "/pattern/exemplar/domain: the polygon is not simple");
  expect_error(R"({"domain": [1, 1], "elements": [{"position": [0.5, 0.5], "scale": 0.1}], "symmetry": 20})",
               "/pattern/exemplar/symmetry");
  // An unknown type is caught when mapping onto the scene's stencils.
  const Exemplar ex = parse_exemplar(
      json::parse(R"({"domain": [1, 1], "elements": [{"position": [0.5, 0.5], "scale": 0.1},
                                                      {"position": [0.2, 0.2], "scale": 0.1, "type": "moon"}]})"),
      "scene.json", "/pattern/exemplar");
  try {
    map_exemplar_types(ex, {"circle", "star"}, "scene.json", "/pattern/exemplar");
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/pattern/exemplar/elements/1/type: 'moon' is not a stencil of this "
                                         "scene (stencils: circle, star)"),
              std::string::npos)
        << e.what();
  }
}

TEST(Exemplar, JsonRoundTrip) {
  const Exemplar ex = builtin_exemplar("mix");
  const Exemplar back = parse_exemplar(exemplar_to_json(ex), "x", "");
  ASSERT_EQ(back.elements.size(), ex.elements.size());
  EXPECT_EQ(back.type_names, ex.type_names);
  for (size_t i = 0; i < ex.elements.size(); ++i) {
    EXPECT_EQ(back.elements[i].position, ex.elements[i].position);
    EXPECT_EQ(back.elements[i].scale, ex.elements[i].scale);
    EXPECT_EQ(back.elements[i].type, ex.elements[i].type);
  }
}

}  // namespace
}  // namespace cutwork
