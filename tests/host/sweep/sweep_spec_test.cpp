// Sweep files: axis kinds, grid / Latin hypercube / random expansion (counts, bounds,
// determinism per seed), and bad axes rejected with the variant and the scene's JSON path named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "host/core/error.h"
#include "host/sweep/sweep_spec.h"

namespace cutwork {
namespace {

using nlohmann::json;

SweepSpec spec_of(const std::string& text) { return parse_sweep(json::parse(text), "sweep.json", "."); }

// Expects `f` to throw an InputError: one line, starting with "sweep.json: ", with every fragment.
template <typename F>
void expect_rejected(F&& f, std::initializer_list<const char*> fragments) {
  try {
    f();
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_EQ(msg.rfind("sweep.json: ", 0), 0u) << msg;
    for (const char* f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "missing '" << f << "' in: " << msg;
  }
}

TEST(SweepSpec, GridIsEveryCombinationLastAxisFastest) {
  const SweepSpec s = spec_of(R"({"base": "plate", "axes": [
      {"path": "/material/thickness", "values": [0.002, 0.003]},
      {"path": "/structure/w_S", "range": [100, 300], "count": 3}]})");
  const auto points = expand_axes(s);
  ASSERT_EQ(points.size(), 6u);
  const double w[] = {100, 200, 300};
  for (size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(points[k][0].get<double>(), k < 3 ? 0.002 : 0.003);
    EXPECT_DOUBLE_EQ(points[k][1].get<double>(), w[k % 3]);
  }
  const std::vector<SweepVariant> v = expand_sweep(s);
  ASSERT_EQ(v.size(), 6u);
  EXPECT_EQ(v[0].id, "v001");
  EXPECT_EQ(v[5].id, "v006");
  EXPECT_EQ(v[4].scene["material"]["thickness"].get<double>(), 0.003);
  EXPECT_DOUBLE_EQ(v[4].scene["structure"]["w_S"].get<double>(), 200);
}

TEST(SweepSpec, RangesHitTheirEndsExactlyLinearOrLog) {
  const SweepSpec s = spec_of(R"({"base": "plate", "axes": [
      {"path": "/structure/w_S", "range": [10, 1000], "count": 3, "spacing": "log"},
      {"path": "/pattern/seed", "range": [1, 4], "count": 4, "integer": true}]})");
  const auto g0 = s.axes[0].grid(), g1 = s.axes[1].grid();
  ASSERT_EQ(g0.size(), 3u);
  EXPECT_EQ(g0[0].get<double>(), 10);
  EXPECT_NEAR(g0[1].get<double>(), 100, 1e-12);
  EXPECT_EQ(g0[2].get<double>(), 1000);
  ASSERT_EQ(g1.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(g1[size_t(i)].is_number_integer());
    EXPECT_EQ(g1[size_t(i)].get<int>(), i + 1);
  }
  EXPECT_EQ(expand_axes(s).size(), 12u);
}

// One sample in each of n strata of every axis, inside the bounds; the same seed gives the same
// samples, another seed other ones.
TEST(SweepSpec, LatinHypercubeFillsEveryStratumOnceAndIsDeterministicPerSeed) {
  const std::string axes = R"("axes": [
      {"path": "/structure/beta", "distribution": "uniform", "min": 0.1, "max": 0.5},
      {"path": "/structure/w_S", "distribution": "log_uniform", "min": 10, "max": 1000},
      {"path": "/material/thickness", "distribution": "normal", "mean": 0.003, "sd": 0.0002}])";
  const int n = 12;
  const auto sampled = [&](int seed) {
    return expand_axes(spec_of(R"({"base": "plate", "sampling": "latin_hypercube", "samples": 12, "seed": )" +
                               std::to_string(seed) + "," + axes + "}"));
  };
  const auto a = sampled(7), b = sampled(7), c = sampled(8);
  ASSERT_EQ(a.size(), size_t(n));
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  std::set<int> beta_strata, w_strata, h_strata;
  for (const auto& p : a) {
    const double beta = p[0].get<double>(), w = p[1].get<double>(), h = p[2].get<double>();
    EXPECT_GE(beta, 0.1);
    EXPECT_LT(beta, 0.5);
    EXPECT_GE(w, 10);
    EXPECT_LT(w, 1000);
    beta_strata.insert(int(std::floor((beta - 0.1) / 0.4 * n)));
    w_strata.insert(int(std::floor(std::log(w / 10) / std::log(100.0) * n)));
    h_strata.insert(int(std::floor(0.5 * std::erfc(-(h - 0.003) / 0.0002 / std::sqrt(2.0)) * n)));
  }
  EXPECT_EQ(beta_strata.size(), size_t(n));
  EXPECT_EQ(w_strata.size(), size_t(n));
  EXPECT_EQ(h_strata.size(), size_t(n));
  EXPECT_EQ(*beta_strata.begin(), 0);
  EXPECT_EQ(*beta_strata.rbegin(), n - 1);
}

TEST(SweepSpec, LatinHypercubeOfAListTakesEachValueEquallyOften) {
  const SweepSpec s = spec_of(R"({"base": "plate", "sampling": "latin_hypercube", "samples": 6, "seed": 3,
      "axes": [{"path": "/stencils/0/kind", "values": ["circle", "star", "flower"]}]})");
  std::map<std::string, int> counts;
  for (const auto& p : expand_axes(s)) counts[p[0].get<std::string>()] += 1;
  EXPECT_EQ(counts, (std::map<std::string, int>{{"circle", 2}, {"flower", 2}, {"star", 2}}));
}

TEST(SweepSpec, RandomSamplesStayInBoundsAndRepeatPerSeed) {
  const std::string doc = R"({"base": "plate", "sampling": "random", "samples": 50, "seed": 11, "axes": [
      {"path": "/structure/beta", "distribution": "uniform", "min": 0.2, "max": 0.3}]})";
  const auto a = expand_axes(spec_of(doc)), b = expand_axes(spec_of(doc));
  ASSERT_EQ(a.size(), 50u);
  EXPECT_EQ(a, b);
  for (const auto& p : a) {
    EXPECT_GE(p[0].get<double>(), 0.2);
    EXPECT_LT(p[0].get<double>(), 0.3);
  }
}

TEST(SweepSpec, BadAxisPathIsRejectedNamingTheVariant) {
  // An unknown key is caught when the first variant is validated as a scene.
  const SweepSpec s = spec_of(R"({"base": "plate", "axes": [{"path": "/material/thicknes", "values": [0.002]}]})");
  expect_rejected([&] { expand_sweep(s); }, {"variant v001", "/material/thicknes = 0.002", "thicknes"});
  // A pointer into nothing is caught with the axis.
  expect_rejected([] { spec_of(R"({"base": "plate", "axes": [{"path": "/nothing/here", "values": [1]}]})"); },
                  {"/axes/0/path", "/nothing/here", "no object or array at /nothing"});
  expect_rejected([] { spec_of(R"({"base": "plate", "axes": [{"path": "/stencils/5/kind", "values": ["star"]}]})"); },
                  {"/axes/0/path", "no object or array at /stencils/5"});
  expect_rejected([] { spec_of(R"({"base": "plate", "axes": [{"path": "/stencils/3", "values": [{"kind": "star"}]}]})"); },
                  {"/axes/0/path", "index '3'", "array of 1 entries"});
  expect_rejected([] { spec_of(R"({"base": "plate", "axes": [{"path": "material", "values": [1]}]})"); },
                  {"/axes/0/path", "not a JSON pointer"});
}

TEST(SweepSpec, BadValueIsRejectedNamingTheVariantAndPath) {
  const SweepSpec s = spec_of(R"({"base": "plate", "axes": [
      {"path": "/material/thickness", "values": [0.003, -1]},
      {"path": "/structure/w_S", "values": [100]}]})");
  expect_rejected([&] { expand_sweep(s); },
                  {"variant v002", "/material/thickness = -1, /structure/w_S = 100", "/material/thickness: "});
  const SweepSpec k = spec_of(R"({"base": "plate", "axes": [{"path": "/structure/objective", "values": ["compliance", "bogus"]}]})");
  expect_rejected([&] { expand_sweep(k); }, {"variant v002", "/structure/objective"});
}

TEST(SweepSpec, MalformedSweepsAreRejectedWithTheirPath) {
  expect_rejected([] { spec_of(R"({"axes": [{"path": "/structure/w_S", "values": [1]}]})"); }, {"/base"});
  expect_rejected([] { spec_of(R"({"base": "plate", "axes": []})"); }, {"/axes"});
  expect_rejected([] { spec_of(R"({"base": "nosuchscene", "axes": [{"path": "/structure/w_S", "values": [1]}]})"); },
                  {"nosuchscene"});
  expect_rejected([] { spec_of(R"({"base": "plate", "axes": [{"path": "/structure/beta", "distribution": "uniform", "min": 0.1, "max": 0.2}]})"); },
                  {"/axes/0/distribution", "latin_hypercube"});
  expect_rejected([] { spec_of(R"({"base": "plate", "axes": [{"path": "/structure/w_S", "range": [1, 2]}]})"); },
                  {"/axes/0/count"});
  expect_rejected([] { spec_of(R"({"base": "plate", "sampling": "latin_hypercube", "axes": [{"path": "/structure/w_S", "values": [1]}]})"); },
                  {"/samples"});
  expect_rejected([] { spec_of(R"({"base": "plate", "axes": [{"path": "/structure/w_S", "values": [1], "range": [1, 2], "count": 2}]})"); },
                  {"/axes/0", "exactly one of"});
  expect_rejected([] { spec_of(R"({"base": "plate", "axis": []})"); }, {"axis"});
}

TEST(SweepSpec, InlineBaseAndScenesOfEveryVariant) {
  const SweepSpec s = spec_of(R"({"name": "inline", "base": {"name": "t", "mesh": {"generator": "sheet"},
      "supports": [{"type": "pinned", "select": {"entity": "boundary_vertices"}}], "loads": [{"type": "self_weight"}]},
      "axes": [{"path": "/material/thickness", "values": [0.001, 0.004]}]})");
  EXPECT_EQ(s.name, "inline");
  std::vector<Scene> scenes;
  const auto v = expand_sweep(s, &scenes);
  ASSERT_EQ(scenes.size(), 2u);
  EXPECT_EQ(scenes[0].material.thickness, 0.001);
  EXPECT_EQ(scenes[1].material.thickness, 0.004);
  EXPECT_EQ(scenes[1].mesh.generator, "sheet");
}

}  // namespace
}  // namespace cutwork
