#pragma once
/// \file initial_view_cache.h
/// \brief InitialViewCache: the map after v0, shared by trials that start alike (a
/// campaign's planners and studies on one plant and pose), so that v0 is captured and
/// integrated once.

#include <cstddef>
#include <memory>
#include <string>

#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/octree/update_region.h>
#include <plantnbv/sensor/sensor_scene.h>

namespace plantnbv {

/// \brief Maps after v0, each kept for one scene, one key (a string that Trial makes of
/// everything else its map after v0 depends on: the camera, v0, the map's parameters,
/// the depth rounding) and one update region (compared brick for brick; none matches
/// none). Trial::setInitialViewCache uses it: a map found here is the map that
/// integrating v0 gives, so a trial that starts from it has the same steps and scores.
///
/// Keeps the last `capacity` maps added, as OccupancyMapSnapshot (5 bytes a node); it
/// holds their scenes, so that a scene's address stays its own. Thread-safe: trials on
/// several threads may share one.
class InitialViewCache {
public:
  using Ptr = std::shared_ptr<InitialViewCache>; ///< shared cache

  /// \param[in] capacity maps kept (>= 1). \throws InvalidArgumentError if 0.
  explicit InitialViewCache(std::size_t capacity = 16);
  ~InitialViewCache();

  /// \brief A new map equal to the one kept for `scene`, `key` and `region` (null: no
  /// update region), or null when none is kept.
  std::unique_ptr<OccupancyMap> find(const SensorScene::ConstPtr& scene,
                                     const std::string& key,
                                     const UpdateRegion* region) const;
  /// \brief Keeps a snapshot of `map` for `scene`, `key` and the map's update region; a
  /// map already kept for them stays (they are the same map).
  void add(const SensorScene::ConstPtr& scene, const std::string& key,
           const OccupancyMap& map);
  /// \brief The maps kept.
  std::size_t size() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace plantnbv
