#include <algorithm>
#include <cmath>

#include <plantnbv/session/memory_estimate.h>

namespace plantnbv {

double estimatedFrameMemoryBytes(const CameraIntrinsics& camera)
{
  return double(camera.width) * camera.height * 32.0;
}

double estimatedViewMemoryBytes(const OccupancyMap::Config& map,
                                const CameraIntrinsics& camera)
{
  // A pyramid of the camera's fields of view out to the range: h^3 tan(a/2) tan(b/2) 4/3.
  const double range = std::min(map.max_range_m, camera.max_range_m);
  const double frustum_m3 = 4.0 / 3.0 * range * range * range *
                            std::tan(camera.horizontalFov() / 2) *
                            std::tan(camera.verticalFov() / 2);
  const double voxel_m3 = map.resolution_m * map.resolution_m * map.resolution_m;
  const double map_bytes = frustum_m3 / voxel_m3 * 32.0;
  return map_bytes + estimatedFrameMemoryBytes(camera);
}

double estimatedGainMemoryBytes(const GainConfig& gain)
{
  return double(gain.rays_x) * gain.rays_y * 24.0;
}

} // namespace plantnbv
