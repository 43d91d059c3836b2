// The reference gain: OctoMap's own ray keys and tree searches, no shortcuts. Slow on
// purpose; the fast InformationGain is tested against it.

#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <octomap/OcTree.h>

#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/planning/information_gain.h>

#include "gain_rays.h"

namespace plantnbv {

ViewGain referenceInformationGain(const OccupancyMap& map, const Roi& roi,
                                  const GainConfig& config, const Viewpoint& view)
{
  config.validate();
  const octomap::OcTree& tree = map.getOcTree();
  const std::vector<Eigen::Vector3d> dirs = gain_detail::rayDirectionsBody(config);
  const Eigen::Matrix3d R = view.orientation.toRotationMatrix();
  float o[3];
  gain_detail::rayOrigin(view, o);
  const octomap::point3d origin(o[0], o[1], o[2]);
  const bool weighted = config.visibility_weighted;

  auto inRoi = [&](const octomap::OcTreeKey& key) {
    const Eigen::Vector3d centre(tree.keyToCoord(key[0]), tree.keyToCoord(key[1]),
                                 tree.keyToCoord(key[2]));
    return roi.empty() || roi.contains(centre);
  };

  ViewGain result;
  octomap::KeyRay ray;
  std::unordered_set<octomap::OcTreeKey, octomap::OcTreeKey::KeyHash> seen;
  std::unordered_map<octomap::OcTreeKey, double, octomap::OcTreeKey::KeyHash> visibility;
  octomap::OcTreeKey key_origin;
  if (!tree.coordToKeyChecked(origin, key_origin))
    return result; // outside the octree: no ray
  std::vector<octomap::OcTreeKey> keys;
  for (const Eigen::Vector3d& d : dirs) {
    float e[3];
    gain_detail::rayEnd(R, view.position, d, config.raycast_range_m, e);
    const octomap::point3d end(e[0], e[1], e[2]);
    octomap::OcTreeKey key_end;
    if (!tree.coordToKeyChecked(end, key_end))
      continue;
    ++result.rays_cast;
    tree.computeRayKeys(origin, end, ray);
    keys.assign(ray.begin(), ray.end());
    keys.push_back(key_end);
    double vis = 1.0;
    int unknown_left = config.unknown_depth > 0 ? config.unknown_depth : -1;
    for (const octomap::OcTreeKey& key : keys) {
      const octomap::OcTreeNode* node = tree.search(key);
      // An unknown ROI voxel deeper than unknown_depth on this ray does not count; with
      // unknown_only the ray ends at the last one that does.
      bool counts = true, last = false;
      if (!node && unknown_left >= 0 && inRoi(key)) {
        counts = unknown_left > 0;
        unknown_left -= counts ? 1 : 0;
        last = counts && unknown_left == 0 && config.unknown_only;
      }
      if (weighted) {
        if (counts) {
          auto it = visibility.emplace(key, vis).first;
          if (vis > it->second)
            it->second = vis;
        }
        vis *= 1.0 - (node ? node->getOccupancy() : 0.5);
      } else {
        if (counts)
          seen.insert(key);
        if (node && tree.isNodeOccupied(node))
          break; // it counts, nothing behind it does
      }
      if (last)
        break;
    }
  }

  auto term = [&](const octomap::OcTreeKey& key, double weight) {
    if (!inRoi(key))
      return;
    const octomap::OcTreeNode* node = tree.search(key);
    ++result.voxels_seen;
    if (!node)
      ++result.unknown_seen;
    const double bits = !node                 ? 1.0
                        : config.unknown_only ? 0.0
                                              : occupancyEntropy(node->getOccupancy());
    result.gain += weight * bits;
  };
  if (weighted)
    for (const auto& [key, vis] : visibility)
      term(key, vis);
  else
    for (const octomap::OcTreeKey& key : seen)
      term(key, 1.0);
  return result;
}

} // namespace plantnbv
