#pragma once
/// \file occupancy_map_snapshot.h
/// \brief OccupancyMapSnapshot: a compact, read-only copy of an OccupancyMap, from which
/// maps equal to it node for node are made.

#include <cstddef>
#include <memory>
#include <string>

#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/octree/update_region.h>

namespace plantnbv {

/// \brief A map kept for later: its configuration, threads, update region and its
/// tree's nodes in one buffer, depth first, as OctoMap's .ot files hold them (each
/// node's log-odds and its children's mask: 5 bytes a node, against OctoMap's node and
/// child array in memory). restore() makes a new map with the same tree, node for node
/// (log-odds, inner nodes and pruning included), so that the same frames then make the
/// same map in both.
///
/// For keeping many maps that are read back now and then (InitialViewCache): a kept
/// snapshot is one allocation outside the heap's small blocks instead of a tree of
/// small ones among those the running maps allocate and free.
class OccupancyMapSnapshot {
public:
  /// \brief A snapshot of `map` as it is now (O(tree size)).
  explicit OccupancyMapSnapshot(const OccupancyMap& map);

  /// \brief A new map with the snapshot's configuration, threads, update region and
  /// tree (its InsertStats those of a new map).
  std::unique_ptr<OccupancyMap> restore() const;

  /// \brief The configuration of the map it was taken of.
  const OccupancyMap::Config& getConfig() const { return config_; }
  /// \brief The update region of that map (null: none).
  const std::shared_ptr<const UpdateRegion>& getUpdateRegion() const { return region_; }
  /// \brief The bytes holding the tree's nodes (5 a node; 0 for an empty map).
  std::size_t nodeBytes() const { return nodes_.size(); }

private:
  OccupancyMap::Config config_;
  int threads_ = 0;
  std::shared_ptr<const UpdateRegion> region_;
  std::string nodes_; ///< OcTree::writeData
};

} // namespace plantnbv
