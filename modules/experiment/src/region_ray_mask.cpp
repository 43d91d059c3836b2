#include <plantnbv/experiment/region_ray_mask.h>

namespace plantnbv {

RayMask regionRayMask(const UpdateRegion& region, const CameraIntrinsics& K,
                      const Pose& T_W_O, double range_m)
{
  RayMask mask(K, T_W_O, range_m);
  // The rays stay in the cube of half-side range_m around the optical centre: the
  // bricks outside it are out of reach, and where it leaves the region's bounds a ray
  // may reach space the region holds entirely.
  double bounds_lo[3], bounds_hi[3], lo[3], hi[3];
  region.getBounds(bounds_lo, bounds_hi);
  bool inside = true;
  for (int a = 0; a < 3; ++a) {
    lo[a] = T_W_O.position[a] - range_m;
    hi[a] = T_W_O.position[a] + range_m;
    inside = inside && lo[a] >= bounds_lo[a] && hi[a] <= bounds_hi[a];
  }
  if (!inside)
    mask.addAll();
  else
    region.forEachBrick(lo, hi, [&](const double* brick_lo, const double* brick_hi) {
      mask.addBox(brick_lo, brick_hi);
    });
  return mask;
}

} // namespace plantnbv
