#include <istream>
#include <sstream>
#include <streambuf>

#include <octomap/OcTree.h>

#include <plantnbv/octree/occupancy_map_snapshot.h>

namespace plantnbv {

namespace {

/// An input stream buffer over bytes that it does not own (std::istringstream would
/// copy them).
class BytesBuffer : public std::streambuf {
public:
  explicit BytesBuffer(const std::string& bytes)
  {
    char* begin = const_cast<char*>(bytes.data()); // only read
    setg(begin, begin, begin + bytes.size());
  }
};

} // namespace

OccupancyMapSnapshot::OccupancyMapSnapshot(const OccupancyMap& map)
    : config_(map.getConfig()), threads_(map.getNumberOfThreads()),
      region_(map.getUpdateRegion())
{
  std::ostringstream s;
  map.getOcTree().writeData(s); // nothing for an empty tree
  nodes_ = s.str();
}

std::unique_ptr<OccupancyMap> OccupancyMapSnapshot::restore() const
{
  auto map = std::make_unique<OccupancyMap>(config_);
  map->setNumberOfThreads(threads_);
  map->setUpdateRegion(region_);
  if (!nodes_.empty()) { // readData would make a root of nothing
    BytesBuffer buffer(nodes_);
    std::istream s(&buffer);
    map->tree_->readData(s);
  }
  return map;
}

} // namespace plantnbv
