#pragma once
/// \file reconstruction_evaluator.h
/// \brief Scores a reconstruction against a plant's ground truth at the evaluation
/// levels of the paper (section 3.3): whole plant, main stem, leaf nodes (and fruits).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/common/box.h>
#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/plant/plant.h>

namespace plantnbv {

/// \brief One evaluation level: a name (a column prefix in steps.csv, e.g. "leaf_nodes")
/// and its ROI. With `average_boxes`, each box is scored on its own and the scores are
/// averaged (the paper's leaf nodes: one score per node, averaged over the three);
/// otherwise the union of the boxes is scored once.
struct EvaluationLevel {
  std::string name;           ///< e.g. "whole_plant", "main_stem", "leaf_nodes"
  Roi roi;                    ///< the boxes scored (world frame, metres)
  bool average_boxes = false; ///< score each box alone and average (leaf nodes)
};

/// \brief The scores of one level. Precision, recall and F1 at rho = the resolution
/// (strict <); Chamfer = the mean of the two mean nearest-neighbour distances (metres).
/// With averaged boxes: P, R and F1 are the means over all boxes (a box without
/// reconstruction scores 0), Chamfer the mean over the boxes where it is defined.
/// Chamfer is NaN where no box has points on both sides.
struct LevelScore {
  /// Share of the reconstruction's voxels closer than rho to ground truth, in [0, 1].
  double precision = 0.0;
  /// Share of the ground-truth voxels closer than rho to the reconstruction, in [0, 1].
  double recall = 0.0;
  double f1 = 0.0;                  ///< harmonic mean of precision and recall
  double chamfer = 0.0;             ///< Chamfer distance (metres); NaN where undefined
  std::size_t reference_points = 0; ///< ground-truth voxels in the level's boxes
  std::size_t reconstruction_points = 0; ///< occupied voxels in the level's boxes
};

/// \brief How much of one organ of the whole plant the reconstruction holds.
struct OrganRecall {
  PartLabel organ = PartLabel::unknown; ///< which organ
  /// Ground-truth voxels holding this organ's surface (a voxel where two organs meet
  /// counts for both).
  std::size_t reference_points = 0;
  /// Share of them closer than rho to the reconstruction, in [0, 1]; NaN when the plant
  /// has no surface of this organ (no fruit yet, or an unlabelled model).
  double recall = 0.0;
};

/// \brief The organs computeOrganRecall reports, in its order: stem, petiole, leaflet,
/// peduncle, fruit, flower.
const std::vector<PartLabel>& evaluatedOrgans();

/// \brief The voxels behind one level's scores, sorted by outcome (metres, world frame),
/// e.g. to colour a picture of a reconstruction.
struct VoxelOutcomes {
  /// Reconstruction voxels closer than rho to ground truth: precision's hits.
  std::vector<Eigen::Vector3f> correct;
  /// The other reconstruction voxels the level scores: precision's misses.
  std::vector<Eigen::Vector3f> wrong;
  /// Ground-truth voxels with no reconstruction voxel closer than rho: recall's misses.
  std::vector<Eigen::Vector3f> missed;
};

/// \brief Ground truth computed once per plant and pose, then scores for any number of
/// reconstructions (docs/architecture.md, "Conventions"):
/// - ground truth: the plant's mesh sampled (groundTruthSampleCount points, seeded), or
///   its scan points, reduced to the centres of the voxels they fall in, on OctoMap's
///   lattice at the map's resolution (VoxelGridFilter with voxel centres), so that a
///   perfectly observed voxel is at distance 0 from its ground truth;
/// - reconstruction: the occupied voxel centres of the map (same lattice), less the
///   background's voxels (setBackground);
/// - both cropped to each level's boxes (RoiCrop, closed boxes), then
///   ReconstructionMetrics with rho = resolution.
///
/// \code
/// ReconstructionEvaluator evaluator;
/// evaluator.setResolution(0.003);
/// evaluator.setGroundTruth(plant);
/// evaluator.setLevels({{"whole_plant", wholePlantRoi(plant)}, ...});
/// std::vector<LevelScore> scores;
/// evaluator.compute(occupied_centres, scores);
/// \endcode
class ReconstructionEvaluator {
public:
  ReconstructionEvaluator();
  ~ReconstructionEvaluator();
  ReconstructionEvaluator(const ReconstructionEvaluator&) = delete;
  ReconstructionEvaluator& operator=(const ReconstructionEvaluator&) = delete;

  /// \brief Voxel size of ground truth and rho (metres, > 0). Default 0.003. Call before
  /// setGroundTruth. \throws InvalidArgumentError otherwise.
  void setResolution(double resolution_m);
  /// \brief Voxel size of ground truth and rho (metres).
  double getResolution() const { return resolution_m_; }
  /// \brief Seed of the surface sampling. Default 0.
  void setSeed(std::uint64_t seed) { seed_ = seed; }
  /// \brief Threads of the sampling and the metrics (0: OpenMP's default). On two or
  /// more, compute() scores the levels' parts (and the organs' recall) side by side, one
  /// thread each. Results do not depend on it.
  void setNumberOfThreads(int threads);

  /// \brief Samples and voxelizes the plant (mesh, or scan points if it has no mesh).
  /// \throws InvalidArgumentError if the plant has neither.
  void setGroundTruth(const Plant& plant);
  /// \brief The levels, in the order compute() reports them. Crops the ground truth
  /// once per box. \throws InvalidArgumentError for an empty ROI or a repeated name, or
  /// if setGroundTruth was not called.
  void setLevels(const std::vector<EvaluationLevel>& levels);
  /// \brief The levels, in the order compute() reports them.
  const std::vector<EvaluationLevel>& getLevels() const { return levels_; }

  /// \brief The scene's surfaces that are not the plant (for a trial, the floor and
  /// support of plantSceneBackground). The reconstruction's voxels that such a surface
  /// passes through, or the voxels next to them (which take the sensor's noise), are
  /// left out of the scores unless they hold ground truth, as a segmentation of the
  /// plant would leave them out. Without this, a support whose top face lies on the
  /// bottom face of a level's box scores as false positives wherever the lattice puts
  /// its voxel centres inside the box. At rho = the resolution a match is the same
  /// voxel (up to the float rounding of neighbours exactly rho apart), so what is left
  /// out is almost only false positives. Default: none. May be called before or after
  /// setLevels.
  /// \throws FormatError for a malformed mesh.
  void setBackground(const TriangleMesh& background);
  /// \brief How many voxels of the levels' boxes setBackground leaves out (0 before).
  std::size_t backgroundVoxelCount() const;

  /// \brief The ground-truth voxel centres (the whole plant, uncropped).
  const CloudXYZ& getGroundTruth() const;

  /// \brief Scores of `reconstruction` (world frame; non-finite points ignored) for each
  /// level, in order. The reference trees are built once, in setLevels; a call builds
  /// only the reconstruction's. Not thread-safe (it reuses per-box state): one evaluator
  /// per thread.
  void compute(const CloudXYZ& reconstruction, std::vector<LevelScore>& scores) const;

  /// \brief Recall per organ (evaluatedOrgans(), in order) over the whole plant,
  /// uncropped, as compute() scores recall (background left out, distance < rho): which
  /// organs a reconstruction misses. The organs are the part labels of the ground
  /// truth's samples (the mesh's triangles, or a scan's labels). Not thread-safe, as
  /// compute().
  void computeOrganRecall(const CloudXYZ& reconstruction,
                          std::vector<OrganRecall>& recalls) const;
  /// \brief compute() and computeOrganRecall() of one reconstruction, its background
  /// left out once: what a trial scores after each view. The same results as the two
  /// calls.
  void compute(const CloudXYZ& reconstruction, std::vector<LevelScore>& scores,
               std::vector<OrganRecall>& recalls) const;
  /// \brief The voxels that compute() scores at level `level` (index into the levels),
  /// by outcome: the background left out, cropped to the union of the level's boxes
  /// (as one, also for a level with average_boxes), matched at distance < rho.
  /// \throws InvalidArgumentError for a level index out of range.
  void classify(const CloudXYZ& reconstruction, std::size_t level,
                VoxelOutcomes& outcomes) const;

private:
  /// `reconstruction` less the background's voxels (setBackground).
  CloudXYZConstPtr withoutBackground(const CloudXYZ& reconstruction) const;
  /// compute() (scores) and computeOrganRecall() (recalls) of a reconstruction without
  /// its background; either may be null.
  void score(const CloudXYZConstPtr& cloud, std::vector<LevelScore>* scores,
             std::vector<OrganRecall>* recalls) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<EvaluationLevel> levels_;
  double resolution_m_ = 0.003;
  std::uint64_t seed_ = 0;
  int threads_ = 0;
};

} // namespace plantnbv
