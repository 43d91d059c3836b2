// PCD point clouds: io::loadCloud (our PCD reader: ascii, binary, binary_compressed).
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/io/cloud_io.h>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  plantnbv::fuzz::useSmallLimits();
  const std::string path = plantnbv::fuzz::writeInput(data, size, ".pcd");
  plantnbv::fuzz::run([&] {
    plantnbv::CloudXYZL cloud;
    plantnbv::io::loadCloud(path, cloud);
  });
  return 0;
}
