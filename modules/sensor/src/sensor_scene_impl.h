#pragma once
/// \file sensor_scene_impl.h
/// \brief SensorScene's Embree state, shared by the module's sources (not installed).

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include <plantnbv/sensor/sensor_scene.h>

namespace plantnbv {
namespace detail {

/// \brief The process-wide Embree device (created on first use, never destroyed before
/// the scenes that use it: each scene holds a reference).
std::shared_ptr<RTCDeviceTy> embreeDevice();

/// \brief Throws plantnbv::Error with `what` and the device's pending error, if any.
void checkEmbree(RTCDevice device, const char* what);

} // namespace detail

/// \brief What a geometry id maps to.
struct SceneGeometry {
  enum class Kind { triangles, surfels, oriented_surfels } kind = Kind::triangles;
  /// Label per primitive (triangle or surfel).
  std::vector<std::uint32_t> labels;
  std::size_t primitives = 0;
};

struct SensorScene::Impl {
  std::shared_ptr<RTCDeviceTy> device;
  RTCScene scene = nullptr;
  std::vector<SceneGeometry> geometries;
  bool committed = false;
  Eigen::Vector3f min{Eigen::Vector3f::Constant(std::numeric_limits<float>::max())};
  Eigen::Vector3f max{Eigen::Vector3f::Constant(-std::numeric_limits<float>::max())};

  Impl();
  ~Impl();
  /// Label of primitive `prim` of geometry `geom` (as PartLabel's value).
  std::uint32_t label(unsigned int geom, unsigned int prim) const
  {
    return geometries[geom].labels[prim];
  }
};

} // namespace plantnbv
