#pragma once
/// \file viewpoint_sampler.h
/// \brief The interface of candidate-view samplers (the paper's Stage II, section 2.2).

#include <memory>
#include <vector>

#include <plantnbv/common/pose.h>
#include <plantnbv/common/random.h>

namespace plantnbv {

/// \brief Draws candidate viewpoints (camera body frame: x forward, y left, z up,
/// docs/architecture.md, "Conventions").
///
/// A sampler is a value-like description of where the camera may go; the randomness
/// comes from the caller's Rng, so a planner that owns the Rng makes its draws
/// reproducible from its seed. `sample` is const: a sampler may be shared.
class ViewpointSampler {
public:
  using Ptr = std::shared_ptr<ViewpointSampler>;            ///< shared sampler
  using ConstPtr = std::shared_ptr<const ViewpointSampler>; ///< shared, read-only

  virtual ~ViewpointSampler() = default;

  /// \brief Appends nothing, fills `out` (cleared first) with freshly drawn candidates.
  /// \param[in,out] rng the source of randomness (advanced by the draws).
  /// \param[out] out the candidates, in the sampler's documented order.
  virtual void sample(Rng& rng, std::vector<Viewpoint>& out) const = 0;
};

} // namespace plantnbv

namespace plantnbv {

/// \brief The same given viewpoints at every step: a robot's reachable poses, or views
/// from another planner, ranked by the gain (the Rng is not used).
class ViewpointListSampler : public ViewpointSampler {
public:
  /// \param[in] viewpoints the candidates every sample() gives, in this order (camera
  /// body poses in the world).
  explicit ViewpointListSampler(std::vector<Viewpoint> viewpoints)
      : viewpoints_(std::move(viewpoints))
  {
  }
  /// \brief The viewpoints given.
  const std::vector<Viewpoint>& getViewpoints() const { return viewpoints_; }
  void sample(Rng&, std::vector<Viewpoint>& out) const override { out = viewpoints_; }

private:
  std::vector<Viewpoint> viewpoints_;
};

} // namespace plantnbv
