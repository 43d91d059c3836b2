#pragma once
// Every leaf of a map, for exact comparisons of two maps in the tests.

#include <algorithm>
#include <tuple>
#include <vector>

#include <octomap/OcTree.h>

#include <plantnbv/octree/occupancy_map.h>

namespace plantnbv {
namespace test {

/// Key (x, y, z), depth and log-odds of a leaf.
using OcTreeLeaf = std::tuple<unsigned, unsigned, unsigned, unsigned, float>;

/// Every leaf of the map's octree, sorted.
inline std::vector<OcTreeLeaf> octreeLeaves(const OccupancyMap& map)
{
  std::vector<OcTreeLeaf> out;
  const octomap::OcTree& tree = map.getOcTree();
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it)
    out.emplace_back(it.getKey()[0], it.getKey()[1], it.getKey()[2], it.getDepth(),
                     it->getLogOdds());
  std::sort(out.begin(), out.end());
  return out;
}

} // namespace test
} // namespace plantnbv
