// PLY point clouds: io::fileKind (our PLY header parser) and io::loadCloud (our PLY
// cloud reader).
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/file_kind.h>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  plantnbv::fuzz::useSmallLimits();
  const std::string path = plantnbv::fuzz::writeInput(data, size, ".ply");
  plantnbv::fuzz::run([&] { plantnbv::io::fileKind(path); });
  plantnbv::fuzz::run([&] {
    plantnbv::CloudXYZL cloud;
    plantnbv::io::loadCloud(path, cloud);
  });
  return 0;
}
