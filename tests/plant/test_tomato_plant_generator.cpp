#include <array>
#include <cmath>
#include <set>
#include <thread>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/tomato_plant_generator.h>

#include "plant_test_util.h"

using plantnbv::defaultPlantConfig;
using plantnbv::InvalidArgumentError;
using plantnbv::kDefaultPlantCount;
using plantnbv::PartLabel;
using plantnbv::Plant;
using plantnbv::TomatoPlantGenerator;
using plantnbv::test::defaultPlant;
using plantnbv::test::meshHash;

namespace {

std::vector<std::uint64_t> hashDefaultSet(int threads)
{
  std::vector<std::uint64_t> hashes(kDefaultPlantCount);
  auto work = [&](int first) {
    for (int i = first; i < kDefaultPlantCount; i += threads)
      hashes[i] = meshHash(TomatoPlantGenerator(defaultPlantConfig(i)).generate().mesh);
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back(work, t);
  for (auto& t : pool)
    t.join();
  return hashes;
}

double horizontalDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  return (a - b).head<2>().norm();
}

void expectBotanyInRanges(const Plant& plant)
{
  const auto& a = plant.anatomy;
  EXPECT_GE(a.stem_height_m, 0.45);
  EXPECT_LE(a.stem_height_m, 0.70);
  // The paper's 0.7 m tall ROIs from the base hold the whole plant; nothing goes below
  // the base (into the pot).
  EXPECT_LE(a.top_height_m, 0.70);
  EXPECT_GE(a.top_height_m, a.stem_height_m - 1e-6);
  Eigen::Vector3f lo, hi;
  plant.mesh.bounds(lo, hi);
  EXPECT_GE(lo.z(), -1e-6);
  EXPECT_NEAR(hi.z(), a.top_height_m, 1e-6);
  // Stem: base at the origin, radius 2.5-4.5 mm.
  if (a.stem_axis.size() < 2 || a.leaves.size() < 5 || a.trusses.empty()) {
    ADD_FAILURE() << "stem axis, leaves or trusses missing";
    return;
  }
  EXPECT_EQ(a.stem_axis.front(), Eigen::Vector3d::Zero());
  EXPECT_NEAR(a.stem_axis.back().z(), a.stem_height_m, 1e-12);
  for (std::size_t k = 0; k + 1 < a.stem_radius_m.size(); ++k) {
    EXPECT_GE(a.stem_radius_m[k], 0.0025);
    EXPECT_LE(a.stem_radius_m[k], 0.0045);
  }

  for (std::size_t k = 0; k < a.leaves.size(); ++k) {
    const auto& leaf = a.leaves[k];
    SCOPED_TRACE("leaf " + std::to_string(k));
    EXPECT_EQ(leaf.node.leaf_index, static_cast<int>(k));
    EXPECT_GE(leaf.length_m, 0.15);
    EXPECT_LE(leaf.length_m, 0.40);
    EXPECT_GE(leaf.full_leaflet_count, 5);
    EXPECT_LE(leaf.full_leaflet_count, 9);
    EXPECT_EQ(leaf.full_leaflet_count % 2, 1);
    EXPECT_EQ(static_cast<int>(leaf.leaflets.size()), leaf.full_leaflet_count);
    if (leaf.leaflets.empty())
      continue;
    for (std::size_t j = 0; j < leaf.leaflets.size(); ++j) {
      const auto& l = leaf.leaflets[j];
      EXPECT_EQ(l.terminal, j + 1 == leaf.leaflets.size());
      EXPECT_GE(l.length_m, 0.03);
      EXPECT_LE(l.length_m, 0.09);
      EXPECT_GE(l.width_m, 0.02);
      EXPECT_LE(l.width_m, 0.04);
    }
    if (k > 0) {
      EXPECT_GT(leaf.node.position.z(), a.leaves[k - 1].node.position.z());
      // Spiral phyllotaxis: about 137.5 deg from leaf to leaf (+-2.5 per plant, +-4
      // per leaf each).
      const Eigen::Vector3d p = a.leaves[k - 1].node.petiole_direction;
      const Eigen::Vector3d q = leaf.node.petiole_direction;
      double turn =
          std::atan2(p.x() * q.y() - p.y() * q.x(), p.x() * q.x() + p.y() * q.y());
      turn = (turn < 0 ? turn + 2 * M_PI : turn) * 180.0 / M_PI;
      EXPECT_NEAR(turn, 137.5, 10.6);
    }
  }

  for (const auto& truss : a.trusses) {
    // The peduncle leaves the stem between the leaf below and the next one.
    EXPECT_GT(truss.attachment.z(), a.leaves[truss.leaf_below].node.stem_point.z());
    EXPECT_LT(truss.attachment.z(), a.leaves[truss.leaf_below + 1].node.stem_point.z());
    EXPECT_GE(truss.fruits.size(), 2u);
    EXPECT_LE(truss.fruits.size(), 6u);
    for (std::size_t f = 0; f < truss.fruits.size(); ++f) {
      EXPECT_GE(truss.fruits[f].radius_m, 0.012);
      EXPECT_LE(truss.fruits[f].radius_m, 0.030);
      for (std::size_t g = f + 1; g < truss.fruits.size(); ++g)
        EXPECT_GT((truss.fruits[f].center - truss.fruits[g].center).norm(),
                  truss.fruits[f].radius_m + truss.fruits[g].radius_m);
    }
  }
}

} // namespace

// Generation itself is single-threaded; running plants on 1 and 2 threads at once checks
// that it keeps no shared state (caches, statics) that could make results depend on it.
TEST(TomatoPlantGenerator, SameConfigGivesBitIdenticalMeshAcrossRunsAndThreads)
{
  const auto run1 = hashDefaultSet(1);
  const auto run2 = hashDefaultSet(1);
  const auto two_threads = hashDefaultSet(2);
  EXPECT_EQ(run1, run2);
  EXPECT_EQ(run1, two_threads);
  // The hash sees the differences: ten plants, ten hashes.
  EXPECT_EQ(std::set<std::uint64_t>(run1.begin(), run1.end()).size(),
            static_cast<std::size_t>(kDefaultPlantCount));
}

TEST(TomatoPlantGenerator, SeedVariesThePlantAndVariationZeroRemovesIt)
{
  TomatoPlantGenerator::Config a;
  a.seed = 11;
  TomatoPlantGenerator::Config b = a;
  b.seed = 12;
  EXPECT_NE(meshHash(TomatoPlantGenerator(a).generate().mesh),
            meshHash(TomatoPlantGenerator(b).generate().mesh));
  a.variation = b.variation = 0.0;
  EXPECT_EQ(meshHash(TomatoPlantGenerator(a).generate().mesh),
            meshHash(TomatoPlantGenerator(b).generate().mesh));
}

TEST(TomatoPlantGenerator, MeshIsValidLabelledAndWithoutDegenerateTriangles)
{
  for (int i = 0; i < kDefaultPlantCount; ++i) {
    SCOPED_TRACE("plant " + std::to_string(i));
    const auto& mesh = defaultPlant(i).mesh;
    EXPECT_NO_THROW(mesh.validate());
    ASSERT_EQ(mesh.labels.size(), mesh.triangles.size());
    ASSERT_EQ(mesh.node_ids.size(), mesh.triangles.size());
    for (const auto& v : mesh.vertices)
      ASSERT_TRUE(v.allFinite());
    std::array<std::size_t, 7> per_label{};
    std::size_t degenerate = 0;
    for (std::size_t t = 0; t < mesh.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] ||
          mesh.triangleArea(t) < 1e-10)
        ++degenerate;
      ++per_label[static_cast<std::size_t>(mesh.labels[t])];
    }
    EXPECT_EQ(degenerate, 0u);
    EXPECT_EQ(per_label[static_cast<int>(PartLabel::unknown)], 0u);
    EXPECT_EQ(per_label[static_cast<int>(PartLabel::background)], 0u);
    for (PartLabel l : {PartLabel::stem, PartLabel::petiole, PartLabel::leaflet,
                        PartLabel::peduncle, PartLabel::fruit})
      EXPECT_GT(per_label[static_cast<int>(l)], 0u) << plantnbv::partLabelName(l);
    // Every part has its own name.
    EXPECT_EQ(
        std::set<std::string>(mesh.node_names.begin(), mesh.node_names.end()).size(),
        mesh.node_names.size());
  }
}

TEST(TomatoPlantGenerator, FullSizeDefaultPlantsHave100kTo500kTriangles)
{
  for (int i = 0; i < kDefaultPlantCount; ++i) {
    EXPECT_GE(defaultPlant(i).mesh.size(), 100000u) << "plant " << i;
    EXPECT_LE(defaultPlant(i).mesh.size(), 500000u) << "plant " << i;
  }
}

TEST(TomatoPlantGenerator, BotanyStaysInTheDocumentedRanges)
{
  for (int i = 0; i < kDefaultPlantCount; ++i) {
    SCOPED_TRACE("default plant " + std::to_string(i));
    expectBotanyInRanges(defaultPlant(i));
  }
  // More seeds at every stage: the clamps hold whatever the draws.
  for (int k = 0; k < 24; ++k) {
    TomatoPlantGenerator::Config c;
    c.seed = 100 + k;
    c.growth_stage = k / 23.0;
    c.mesh_detail = 0.5; // the botany does not depend on it; faster
    SCOPED_TRACE("seed " + std::to_string(c.seed));
    expectBotanyInRanges(TomatoPlantGenerator(c).generate());
  }
}

TEST(TomatoPlantGenerator, LeafNodesAreWherePetiolesLeaveTheStem)
{
  for (int i = 0; i < kDefaultPlantCount; ++i) {
    const auto& a = defaultPlant(i).anatomy;
    for (const auto& leaf : a.leaves) {
      const auto& node = leaf.node;
      // On the stem surface: one stem radius out from the axis, in the petiole's
      // direction, and the petiole points up and out.
      const double d = horizontalDistance(node.position, node.stem_point);
      EXPECT_GT(d, 0.0022);
      EXPECT_LT(d, 0.0050);
      EXPECT_NEAR(node.petiole_direction.norm(), 1.0, 1e-12);
      EXPECT_GT(node.petiole_direction.z(), 0.0);
      const Eigen::Vector3d out = node.position - node.stem_point;
      EXPECT_GT(
          out.head<2>().normalized().dot(node.petiole_direction.head<2>().normalized()),
          0.99);
    }
  }
}

TEST(TomatoPlantGenerator, GrowthStageMovesTheBotanyTogether)
{
  // The typical plant (variation 0) of three stages.
  std::vector<Plant> plants;
  for (double stage : {0.0, 0.5, 1.0}) {
    TomatoPlantGenerator::Config c;
    c.growth_stage = stage;
    c.variation = 0.0;
    plants.push_back(TomatoPlantGenerator(c).generate());
  }
  auto longestLeaf = [](const Plant& p) {
    double m = 0.0;
    for (const auto& l : p.anatomy.leaves)
      m = std::max(m, l.length_m);
    return m;
  };
  auto largestFruit = [](const Plant& p) {
    double m = 0.0;
    for (const auto& t : p.anatomy.trusses)
      for (const auto& f : t.fruits)
        m = std::max(m, f.radius_m);
    return m;
  };
  auto fruitCount = [](const Plant& p) {
    std::size_t n = 0;
    for (const auto& t : p.anatomy.trusses)
      n += t.fruits.size();
    return n;
  };
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT(plants[k].anatomy.stem_height_m, plants[k + 1].anatomy.stem_height_m);
    EXPECT_LT(plants[k].anatomy.stem_radius_m[0], plants[k + 1].anatomy.stem_radius_m[0]);
    EXPECT_LT(longestLeaf(plants[k]), longestLeaf(plants[k + 1]));
    EXPECT_LT(largestFruit(plants[k]), largestFruit(plants[k + 1]));
    EXPECT_LT(fruitCount(plants[k]), fruitCount(plants[k + 1]));
  }
  EXPECT_LT(plants[0].anatomy.trusses.size(), plants[2].anatomy.trusses.size());
}

TEST(TomatoPlantGenerator, SimplifiedKeepsTheTerminalAndHalfTheLeafletsAndTheRest)
{
  for (int i = 0; i < kDefaultPlantCount; ++i) {
    SCOPED_TRACE("plant " + std::to_string(i));
    const Plant& full = defaultPlant(i);
    const Plant& simple = defaultPlant(i, true);
    ASSERT_EQ(full.anatomy.leaves.size(), simple.anatomy.leaves.size());
    std::size_t full_leaflets = 0, kept_leaflets = 0;
    for (std::size_t k = 0; k < full.anatomy.leaves.size(); ++k) {
      const auto& lf = full.anatomy.leaves[k];
      const auto& ls = simple.anatomy.leaves[k];
      EXPECT_EQ(ls.full_leaflet_count, lf.full_leaflet_count);
      const int n = lf.full_leaflet_count;
      EXPECT_EQ(static_cast<int>(ls.leaflets.size()), (n + 1) / 2);
      ASSERT_FALSE(ls.leaflets.empty());
      EXPECT_TRUE(ls.leaflets.back().terminal);
      // The kept leaflets are the same leaflets, not new ones.
      for (const auto& kept : ls.leaflets) {
        bool found = false;
        for (const auto& l : lf.leaflets)
          found = found || (l.base == kept.base && l.tip == kept.tip);
        EXPECT_TRUE(found);
      }
      EXPECT_EQ(ls.node.position, lf.node.position);
      EXPECT_EQ(ls.axis, lf.axis);
      full_leaflets += lf.leaflets.size();
      kept_leaflets += ls.leaflets.size();
    }
    const double share = static_cast<double>(kept_leaflets) / full_leaflets;
    EXPECT_GT(share, 0.5);
    EXPECT_LE(share, 0.6);

    // Leaflet triangles shrink in the same proportion; every other part is identical,
    // the stem even at the same triangle indices.
    std::vector<std::size_t> count_full(7), count_simple(7);
    for (auto l : full.mesh.labels)
      ++count_full[static_cast<int>(l)];
    for (auto l : simple.mesh.labels)
      ++count_simple[static_cast<int>(l)];
    EXPECT_EQ(count_simple[static_cast<int>(PartLabel::leaflet)] * full_leaflets,
              count_full[static_cast<int>(PartLabel::leaflet)] * kept_leaflets);
    for (PartLabel l :
         {PartLabel::stem, PartLabel::petiole, PartLabel::peduncle, PartLabel::fruit})
      EXPECT_EQ(count_simple[static_cast<int>(l)], count_full[static_cast<int>(l)]);
    for (std::size_t t = 0; t < full.mesh.size(); ++t) {
      if (full.mesh.labels[t] != PartLabel::stem)
        continue;
      ASSERT_EQ(simple.mesh.labels[t], PartLabel::stem);
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(simple.mesh.vertices[simple.mesh.triangles[t][c]],
                  full.mesh.vertices[full.mesh.triangles[t][c]]);
    }
    EXPECT_EQ(simple.anatomy.stem_axis, full.anatomy.stem_axis);
    ASSERT_EQ(simple.anatomy.trusses.size(), full.anatomy.trusses.size());
    for (std::size_t t = 0; t < full.anatomy.trusses.size(); ++t)
      for (std::size_t f = 0; f < full.anatomy.trusses[t].fruits.size(); ++f)
        EXPECT_EQ(simple.anatomy.trusses[t].fruits[f].center,
                  full.anatomy.trusses[t].fruits[f].center);
  }
}

TEST(TomatoPlantGenerator, MeshDetailScalesTrianglesNotTheAnatomy)
{
  TomatoPlantGenerator::Config c = defaultPlantConfig(4);
  const Plant normal = TomatoPlantGenerator(c).generate();
  c.mesh_detail = 0.5;
  const Plant coarse = TomatoPlantGenerator(c).generate();
  const double ratio = static_cast<double>(coarse.mesh.size()) / normal.mesh.size();
  EXPECT_GT(ratio, 0.15);
  EXPECT_LT(ratio, 0.4);
  ASSERT_EQ(coarse.anatomy.leaves.size(), normal.anatomy.leaves.size());
  for (std::size_t k = 0; k < normal.anatomy.leaves.size(); ++k)
    EXPECT_LT(
        (coarse.anatomy.leaves[k].node.position - normal.anatomy.leaves[k].node.position)
            .norm(),
        0.002);
}

TEST(TomatoPlantGenerator, SettersRejectValuesOutOfRangeNamingThem)
{
  TomatoPlantGenerator g;
  auto expectMessage = [](auto&& call, const std::string& part) {
    try {
      call();
      ADD_FAILURE() << "no exception for " << part;
    } catch (const InvalidArgumentError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectMessage([&] { g.setGrowthStage(1.5); }, "growth_stage 1.5");
  expectMessage([&] { g.setGrowthStage(-0.1); }, "growth_stage");
  expectMessage([&] { g.setGrowthStage(NAN); }, "growth_stage nan");
  expectMessage([&] { g.setVariation(2.0); }, "variation 2");
  expectMessage([&] { g.setDivergenceAngle(0.0); }, "divergence_angle_rad 0");
  expectMessage([&] { g.setMeshDetail(0.1); }, "mesh_detail 0.1");
  expectMessage([] { defaultPlantConfig(kDefaultPlantCount); }, "10");
  expectMessage([] { defaultPlantConfig(-1); }, "-1");

  // A rejected config leaves the previous one in place.
  g.setGrowthStage(0.25);
  TomatoPlantGenerator::Config bad;
  bad.growth_stage = 0.75;
  bad.mesh_detail = 10.0;
  EXPECT_THROW(g.setConfig(bad), InvalidArgumentError);
  EXPECT_THROW(TomatoPlantGenerator{bad}, InvalidArgumentError);
  EXPECT_EQ(g.getConfig().growth_stage, 0.25);
  EXPECT_EQ(g.getConfig().mesh_detail, 1.0);
}

TEST(TomatoPlantGenerator, DefaultSetSpansTheGrowthStages)
{
  const auto set = plantnbv::defaultPlantSet();
  ASSERT_EQ(set.size(), static_cast<std::size_t>(kDefaultPlantCount));
  for (int i = 0; i < kDefaultPlantCount; ++i) {
    EXPECT_EQ(set[i].seed, static_cast<std::uint64_t>(i));
    EXPECT_DOUBLE_EQ(set[i].growth_stage, i / 9.0);
    EXPECT_FALSE(set[i].simplified);
  }
  EXPECT_TRUE(plantnbv::defaultPlantSet(true)[3].simplified);
  EXPECT_EQ(defaultPlant(3).name, "tomato_seed3");
  EXPECT_EQ(defaultPlant(3, true).name, "tomato_seed3_simplified");
  EXPECT_NE(set[0].toString().find("growth_stage: 0"), std::string::npos);
}
