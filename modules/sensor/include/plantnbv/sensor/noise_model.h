#pragma once
/// \file noise_model.h
/// \brief The depth noise of the simulated sensor: axial Gaussian noise that grows with
/// range, lateral jitter of the beam, and dropout at grazing angles and on depth edges.
/// Off by default: the paper's simulated L515 was noise-free (section 4.1).

#include <cstdint>
#include <string>

namespace plantnbv {

/// \brief Parameters of the noise model, with L515-like defaults.
///
/// For a pixel whose ray first meets a surface at range r (metres, along the ray):
///  1. Lateral jitter: the ray is cast through (u + du, v + dv) instead of (u, v), du and
///     dv ~ N(0, lateral_sigma_px^2) (the MEMS mirror's pointing jitter); the point
///     stays on the jittered ray.
///  2. Dropout: the pixel gives no return with probability p_graze(theta), theta the
///     angle between the ray and the surface normal: 0 up to grazing_start_rad, rising
///     linearly to 1 at grazing_end_rad. Ray-facing surfels (no normal) never drop here.
///  3. Depth edges: a pixel whose range differs from a 4-neighbour's by more than
///     edge_jump_m (a neighbour without a hit counts as infinitely far) gives no return
///     with probability edge_dropout_probability (mixed pixels are invalidated).
///  4. Axial noise: the range becomes r + n, n ~ N(0, sigma(r)^2) with
///     sigma(r) = axial_sigma_m + axial_sigma_per_m * r, along the (jittered) ray.
/// The range limits of the intrinsics apply to the true range r, before step 4.
///
/// Defaults: sigma(r) from the L515 datasheet's depth noise (1 sigma) of 2.5 mm at 1 m
/// and 15.5 mm at 9 m, linear in between (0.875 mm + 1.625 mm/m * r); jitter, grazing
/// and edge parameters are our estimates (the datasheet gives none): 0.2 px, 70-85 deg,
/// 1 cm and 0.5.
///
/// Determinism: every draw is a function of (seed, frame index, pixel index) only (a
/// counter-based generator, plantnbv::deriveSeed), so clouds do not depend on the thread
/// count or the order in which pixels are processed.
struct NoiseConfig {
  /// Off by default (the paper's sensor was noise-free).
  bool enabled = false;
  /// Seed of the noise; frame n after setNoise() draws from deriveSeed(seed, n).
  std::uint64_t seed = 0;
  /// Axial noise at range 0 (metres, 1 sigma), >= 0. Default 0.875 mm.
  double axial_sigma_m = 0.000875;
  /// Growth of the axial noise with range (metres per metre), >= 0. Default 1.625e-3.
  double axial_sigma_per_m = 0.001625;
  /// Lateral jitter of the ray (pixels, 1 sigma), >= 0. Default 0.2.
  double lateral_sigma_px = 0.2;
  /// Incidence angle where grazing dropout starts (rad), in [0, pi/2]. Default 70 deg.
  double grazing_start_rad = 1.2217304763960306;
  /// Incidence angle where every return drops (rad), in [grazing_start_rad, pi/2].
  /// Default 85 deg.
  double grazing_end_rad = 1.4835298641951802;
  /// Range jump to a neighbour that marks a depth edge (metres), > 0. Default 0.01.
  double edge_jump_m = 0.01;
  /// Probability that a pixel on a depth edge gives no return, in [0, 1]. Default 0.5.
  double edge_dropout_probability = 0.5;

  /// \brief sigma(r) in metres for a range in metres.
  double axialSigma(double range_m) const
  {
    return axial_sigma_m + axial_sigma_per_m * range_m;
  }
  /// \brief p_graze(theta): dropout probability for an incidence angle (rad) in
  /// [0, pi/2].
  double grazingDropoutProbability(double incidence_rad) const;

  /// \brief Checks every field (also when disabled).
  /// \throws InvalidArgumentError naming the first bad field and its value.
  void validate() const;
  /// \brief One line per field, for logs.
  std::string toString() const;
};

} // namespace plantnbv
