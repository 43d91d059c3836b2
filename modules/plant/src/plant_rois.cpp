#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/plant_rois.h>

namespace plantnbv {

namespace {

Roi stemCentredRoi(const Plant& plant, const Eigen::Vector3d& size,
                   double center_height_m, const char* name)
{
  if (!std::isfinite(center_height_m)) {
    std::ostringstream s;
    s << name << " ROI: centre height " << center_height_m << " must be finite";
    throw InvalidArgumentError(s.str());
  }
  // The stem axis point at that height, at that height exactly (the stem is not quite
  // vertical, so the interpolated z may differ in the last bits).
  Eigen::Vector3d center = plant.stemPointAtHeight(center_height_m);
  center.z() = plant.base_position.z() + center_height_m;
  return Roi({Box(center, size, name)});
}

} // namespace

Roi wholePlantRoi(const Plant& plant, const Eigen::Vector3d& size, double center_height_m)
{
  return stemCentredRoi(plant, size, center_height_m, "whole_plant");
}

Roi mainStemRoi(const Plant& plant, const Eigen::Vector3d& size, double center_height_m)
{
  return stemCentredRoi(plant, size, center_height_m, "main_stem");
}

std::vector<int> defaultLeafNodeIndices(const Plant& plant)
{
  const int n = static_cast<int>(plant.anatomy.leaves.size());
  if (n < 3) {
    std::vector<int> all(n);
    for (int i = 0; i < n; ++i)
      all[i] = i;
    return all;
  }
  // Low, middle, high; with n >= 3 the rounded positions are distinct.
  std::vector<int> chosen;
  for (double f : {0.2, 0.5, 0.8})
    chosen.push_back(static_cast<int>(std::lround(f * (n - 1))));
  return chosen;
}

Roi leafNodeRoi(const Plant& plant, const std::vector<int>& leaf_indices,
                const Eigen::Vector3d& size)
{
  Roi roi;
  const auto& leaves = plant.anatomy.leaves;
  for (int i : leaf_indices) {
    if (i < 0 || i >= static_cast<int>(leaves.size()))
      throw InvalidArgumentError("leaf node " + std::to_string(i) +
                                 " does not exist (plant '" + plant.name + "' has " +
                                 std::to_string(leaves.size()) + " leaves)");
    roi.addBox(Box(leaves[i].node.position, size, "leaf_node_" + std::to_string(i)));
  }
  return roi;
}

Roi leafNodeRoi(const Plant& plant)
{
  return leafNodeRoi(plant, defaultLeafNodeIndices(plant));
}

Roi fruitRoi(const Plant& plant, double margin_m)
{
  if (!(margin_m >= 0.0) || !std::isfinite(margin_m)) {
    std::ostringstream s;
    s << "fruit ROI: margin " << margin_m << " m must be finite and >= 0";
    throw InvalidArgumentError(s.str());
  }
  Roi roi;
  const auto& trusses = plant.anatomy.trusses;
  for (std::size_t t = 0; t < trusses.size(); ++t) {
    if (trusses[t].fruits.empty())
      continue;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY);
    Eigen::Vector3d hi = -lo;
    for (const Fruit& f : trusses[t].fruits) {
      // 1 um more: mesh vertices on the sphere, rounded to float, stay inside.
      const Eigen::Vector3d reach =
          Eigen::Vector3d::Constant(f.radius_m + margin_m + 1e-6);
      lo = lo.cwiseMin(f.center - reach);
      hi = hi.cwiseMax(f.center + reach);
    }
    roi.addBox(Box::fromMinMax(lo, hi, "truss_" + std::to_string(t)));
  }
  return roi;
}

Roi labelledPartRoi(const Plant& plant, PartLabel label)
{
  const TriangleMesh& mesh = plant.mesh;
  // Union-find over vertex positions: files repeat a shared corner as several vertices.
  std::map<std::array<float, 3>, std::size_t> position_id;
  std::vector<std::size_t> parent;
  auto find = [&parent](std::size_t i) {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  };
  // The part's triangles, each with the position id of its first corner.
  std::vector<std::pair<std::size_t, std::size_t>> part_triangles;
  for (std::size_t t = 0; t < mesh.labels.size(); ++t) {
    if (mesh.labels[t] != label)
      continue;
    std::size_t first = 0;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3f& v = mesh.vertices[mesh.triangles[t][c]];
      const auto [it, added] =
          position_id.emplace(std::array<float, 3>{v.x(), v.y(), v.z()}, parent.size());
      if (added)
        parent.push_back(it->second);
      if (c == 0) {
        part_triangles.emplace_back(t, it->second);
        first = find(it->second);
      } else {
        parent[find(it->second)] = first;
      }
    }
  }
  // Per group (by its root): the lowest and highest corner.
  std::map<std::size_t, std::pair<Eigen::Vector3d, Eigen::Vector3d>> groups;
  for (const auto& [t, corner] : part_triangles) {
    auto [it, added] =
        groups.try_emplace(find(corner), Eigen::Vector3d::Constant(INFINITY),
                           Eigen::Vector3d::Constant(-INFINITY));
    for (auto i : mesh.triangles[t]) {
      it->second.first = it->second.first.cwiseMin(mesh.vertices[i].cast<double>());
      it->second.second = it->second.second.cwiseMax(mesh.vertices[i].cast<double>());
    }
  }
  std::vector<Box> boxes;
  // 1 um more on every side: the box holds its float vertices, and a flat part (a petal
  // in a plane) still has a volume.
  const Eigen::Vector3d grow = Eigen::Vector3d::Constant(1e-6);
  for (const auto& group : groups)
    boxes.push_back(
        Box::fromMinMax(group.second.first - grow, group.second.second + grow));
  std::sort(boxes.begin(), boxes.end(), [](const Box& a, const Box& b) {
    return std::make_tuple(a.center.z(), a.center.x(), a.center.y()) <
           std::make_tuple(b.center.z(), b.center.x(), b.center.y());
  });
  Roi roi;
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    boxes[k].name = std::string(partLabelName(label)) + "_" + std::to_string(k);
    roi.addBox(boxes[k]);
  }
  return roi;
}

Roi plantRoi(const Plant& plant, RoiKind kind)
{
  switch (kind) {
  case RoiKind::whole_plant:
    return wholePlantRoi(plant);
  case RoiKind::main_stem:
    return mainStemRoi(plant);
  case RoiKind::leaf_nodes:
    return leafNodeRoi(plant);
  case RoiKind::fruit:
    return fruitRoi(plant);
  }
  throw InvalidArgumentError("unknown plant ROI kind " +
                             std::to_string(static_cast<int>(kind)));
}

Roi boundingBoxRoi(const Plant& plant)
{
  Eigen::Vector3f lo, hi;
  plant.bounds(lo, hi);
  return Roi({Box::fromMinMax(lo.cast<double>(), hi.cast<double>(), "whole_plant")});
}

} // namespace plantnbv
