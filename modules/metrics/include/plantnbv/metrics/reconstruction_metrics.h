#pragma once
/// \file reconstruction_metrics.h
/// \brief Accuracy of a reconstruction against a reference cloud: Chamfer distance and
/// precision / recall / F1 at a distance threshold (the paper's section 3.4 metrics).

#include <cstddef>
#include <memory>
#include <vector>

#include <plantnbv/common/pcl_fwd.h>

namespace plantnbv {

/// \brief Everything `ReconstructionMetrics::compute` measures. Distances in metres.
struct MetricsResult {
  /// Mean over R of the distance to the nearest point of T (accuracy direction).
  double mean_dist_reconstruction_to_reference = 0.0;
  /// Mean over T of the distance to the nearest point of R (completeness direction).
  double mean_dist_reference_to_reconstruction = 0.0;
  /// The sum of the two directional means (the paper's Chamfer distance).
  double chamfer = 0.0;
  /// Share of R closer than rho to T (strict <).
  double precision = 0.0;
  /// Share of T closer than rho to R (strict <).
  double recall = 0.0;
  /// Harmonic mean of precision and recall; 0 when both are 0.
  double f1 = 0.0;
  double rho = 0.0;                      ///< the threshold used
  std::size_t reference_points = 0;      ///< finite points of T
  std::size_t reconstruction_points = 0; ///< finite points of R
  /// False when R or T has no finite point. Then precision, recall and F1 are 0, the
  /// directional means and the Chamfer distance are +infinity (nothing to be near).
  bool valid = false;
};

/// \brief Compares a reconstruction R with a reference T by nearest-neighbour distances.
///
/// Each cloud gets one search tree, built when it is set and reused by every compute(): a
/// campaign sets the reference once per plant and the reconstruction once per view.
/// The tree is a KD-tree over the points in Morton (Z-order) order: midpoint splits that
/// cycle the axes, leaves of at most 64 points, and the tight bounding box of each child
/// for pruning. It is the tree of search::MortonKdTree (morton_kdtree.h), the same
/// implementation, which offers it to PCL as a pcl::search::Search. Here the queries run
/// in the spatially coherent order of the query cloud's own tree and start from the
/// smallest subtree that must hold the answer (figures: docs/performance.md).
///
/// Distances are exact: every per-point distance is the true nearest-neighbour distance,
/// computed in double precision from the clouds' float coordinates as
/// sqrt(dx * dx + dy * dy + dz * dz); pruning never drops a candidate that could be
/// nearer. compute() is parallel over points (OpenMP) and its result does not depend on
/// the thread count: points are summed in fixed blocks of the tree order, and the block
/// sums in block order. Non-finite points are ignored.
///
/// \code
/// ReconstructionMetrics metrics;
/// metrics.setReference(ground_truth);   // builds T's tree
/// metrics.setThreshold(0.003);
/// metrics.setReconstruction(occupied);  // builds R's tree
/// MetricsResult m = metrics.compute();
/// \endcode
/// Not thread-safe to set clouds or parameters while computing; compute() and
/// computeDistances() themselves may be called from several threads at once.
class ReconstructionMetrics {
public:
  ReconstructionMetrics();
  ~ReconstructionMetrics();
  /// \brief Moves the clouds' trees and the settings (not copyable: the trees are owned).
  ReconstructionMetrics(ReconstructionMetrics&&) noexcept;
  /// \brief Moves the clouds' trees and the settings.
  ReconstructionMetrics& operator=(ReconstructionMetrics&&) noexcept;

  /// \brief The reference T (ground truth). Its finite points are copied into T's tree
  /// (about 18 bytes per point); the cloud is not kept, so changing it afterwards has no
  /// effect until it is set again. Setting a cloud again rebuilds its tree.
  /// \throws InvalidArgumentError if null or with 2^32 - 1 points or more.
  void setReference(const CloudXYZConstPtr& reference);
  /// \brief The reconstruction R, as setReference(). \throws InvalidArgumentError as
  /// above.
  void setReconstruction(const CloudXYZConstPtr& reconstruction);

  /// \param[in] rho precision/recall threshold in metres (default 0.003, the paper's map
  /// resolution); \throws InvalidArgumentError unless finite and > 0.
  void setThreshold(double rho);
  /// \brief The precision/recall threshold rho in metres.
  double getThreshold() const { return rho_; }

  /// \param[in] threads OpenMP threads for building the trees (clouds of 32k points and
  /// more; set it before the clouds) and for compute() and computeDistances(); 0
  /// (default) = OpenMP's default. The results do not depend on it.
  /// \throws InvalidArgumentError if negative.
  void setNumberOfThreads(int threads);
  /// \brief The OpenMP threads; 0 = OpenMP's default.
  int getNumberOfThreads() const { return threads_; }

  /// \brief Whether compute() keeps the distances it found for the next compute(), which
  /// then searches only for what changed: the reconstruction's new points, and for the
  /// reference its points' distances to those (and a full search for the few whose
  /// nearest point left the reconstruction). For a reconstruction that grows view by
  /// view against one reference (a trial's evaluation); the results are the same to the
  /// bit either way. Keeps 48-96 bytes per reconstruction point and 8 per reference
  /// point; setting a reference forgets what was kept; a reconstruction of 2^31 points
  /// or more is searched in full. Default false.
  void setReuseDistances(bool reuse);
  /// \brief Whether compute() reuses distances (setReuseDistances).
  bool getReuseDistances() const;
  /// \brief Computes all metrics. \throws InvalidArgumentError if a cloud was not set.
  MetricsResult compute() const;

  /// \brief Per-point nearest-neighbour distances (metres) in the clouds' point order:
  /// R to T and T to R. NaN for non-finite points; +infinity for finite points when the
  /// other cloud has no finite point. \throws InvalidArgumentError if a cloud was not
  /// set.
  void computeDistances(std::vector<double>& reconstruction_to_reference,
                        std::vector<double>& reference_to_reconstruction) const;
  /// \brief As computeDistances, T to R only (what recall needs, at half the cost).
  void computeDistances(std::vector<double>& reference_to_reconstruction) const;
  /// \brief As computeDistances (T to R), where only the distances below
  /// `max_distance_m` matter (recall at a threshold): those are exact, every other is
  /// +infinity. Faster where R covers little of T: the search for a point of T stops at
  /// the bound. \throws InvalidArgumentError if a cloud was not set or the bound is
  /// not > 0 (NaN included).
  void computeDistancesBelow(double max_distance_m,
                             std::vector<double>& reference_to_reconstruction) const;

private:
  /// The OpenMP threads to use: threads_, or OpenMP's default for 0.
  int threadCount() const;
  /// computeDistances (T to R) with distances from `max_distance_m` on given as
  /// +infinity; `caller` names the call in the error for a missing cloud.
  void referenceDistances(const char* caller, double max_distance_m,
                          std::vector<double>& reference_to_reconstruction) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
  double rho_ = 0.003;
  int threads_ = 0;
};

/// \brief The number of views after which a metric curve first reaches `tau`
/// (curve[i] is the value after view i + 1, so the answer is 1-based): the smallest
/// i + 1 with curve[i] >= tau, or -1 if there is none. NaN entries never reach, and
/// nothing reaches a NaN `tau`.
int viewsToReach(const std::vector<double>& curve, double tau);

/// \brief How much two clouds' axis-aligned bounding boxes overlap, in [0, 1]: the
/// volume of their intersection over the smaller box's volume, each box grown by
/// `margin_m` (metres, >= 0) on every side, so that a flat cloud or a single point has a
/// volume. 1 when one box holds the other; 0 when they are apart or a cloud has no
/// finite point. A low value means two clouds that can hardly be compared: another
/// frame, another yaw, another plant.
double boundingBoxOverlap(const CloudXYZ& a, const CloudXYZ& b, double margin_m);

} // namespace plantnbv
