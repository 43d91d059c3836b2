#include <algorithm>
#include <list>
#include <mutex>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/initial_view_cache.h>
#include <plantnbv/octree/occupancy_map_snapshot.h>

namespace plantnbv {

struct InitialViewCache::Impl {
  struct Entry {
    SensorScene::ConstPtr scene;
    std::string key;
    std::shared_ptr<const OccupancyMapSnapshot> map;

    bool matches(const SensorScene* s, const std::string& k, const UpdateRegion* r) const
    {
      const UpdateRegion* own = map->getUpdateRegion().get();
      return scene.get() == s && key == k && (own == r || (own && r && *own == *r));
    }
  };
  std::size_t capacity = 0;
  mutable std::mutex mutex;
  std::list<Entry> entries; ///< the last added first

  std::shared_ptr<const OccupancyMapSnapshot>
  findLocked(const SensorScene* s, const std::string& k, const UpdateRegion* r) const
  {
    for (const Entry& e : entries)
      if (e.matches(s, k, r))
        return e.map;
    return nullptr;
  }
};

InitialViewCache::InitialViewCache(std::size_t capacity) : impl_(std::make_unique<Impl>())
{
  if (capacity == 0)
    throw InvalidArgumentError("InitialViewCache: the capacity must be at least 1");
  impl_->capacity = capacity;
}

InitialViewCache::~InitialViewCache() = default;

std::unique_ptr<OccupancyMap> InitialViewCache::find(const SensorScene::ConstPtr& scene,
                                                     const std::string& key,
                                                     const UpdateRegion* region) const
{
  std::shared_ptr<const OccupancyMapSnapshot> kept;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    kept = impl_->findLocked(scene.get(), key, region);
  }
  return kept ? kept->restore() : nullptr; // outside the lock: other trials go on
}

void InitialViewCache::add(const SensorScene::ConstPtr& scene, const std::string& key,
                           const OccupancyMap& map)
{
  // Taken outside the lock; callers add after find() missed, so a map kept meanwhile
  // (two trials starting together) is rare and its snapshot simply dropped.
  auto snapshot = std::make_shared<const OccupancyMapSnapshot>(map);
  std::lock_guard<std::mutex> lock(impl_->mutex);
  if (impl_->findLocked(scene.get(), key, map.getUpdateRegion().get()))
    return;
  impl_->entries.push_front({scene, key, std::move(snapshot)});
  if (impl_->entries.size() > impl_->capacity)
    impl_->entries.pop_back();
}

std::size_t InitialViewCache::size() const
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->entries.size();
}

} // namespace plantnbv
