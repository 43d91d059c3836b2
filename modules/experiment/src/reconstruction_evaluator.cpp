#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <omp.h>
#include <set>
#include <vector>

#include <pcl/common/point_tests.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/voxel_lattice.h>
#include <plantnbv/experiment/reconstruction_evaluator.h>
#include <plantnbv/filters/roi_crop.h>
#include <plantnbv/filters/voxel_grid_filter.h>
#include <plantnbv/metrics/reconstruction_metrics.h>
#include <plantnbv/sampling/mesh_sampler.h>

namespace plantnbv {

namespace {

CloudXYZ::Ptr crop(const CloudXYZ::ConstPtr& cloud, const Roi& roi)
{
  RoiCrop<pcl::PointXYZ> filter;
  filter.setRoi(roi);
  filter.setInputCloud(cloud);
  auto out = std::make_shared<CloudXYZ>();
  filter.filter(*out);
  return out;
}

/// A voxel of OctoMap's lattice: its three 16-bit keys (common/voxel_lattice.h, the map's
/// own key arithmetic) packed into one integer.
using VoxelKey = std::uint64_t;

VoxelKey packKey(const int key[3])
{
  return VoxelKey(key[0]) << 32 | VoxelKey(key[1]) << 16 | VoxelKey(key[2]);
}

bool keyOf(const pcl::PointXYZ& p, const VoxelLattice& lattice, VoxelKey& key)
{
  const float xyz[3] = {p.x, p.y, p.z};
  int k[3];
  if (!lattice.coordToKey(xyz, k))
    return false;
  key = packKey(k);
  return true;
}

/// Voxel keys to 32-bit values in one open-addressing table (linear probing, at most
/// half full): the evaluator looks up every sample and every reconstruction voxel, and
/// std::unordered_map's node per key made those lookups the serial part of a view.
/// Only looked up, never iterated: its layout cannot reach a result.
class VoxelKeyMap {
public:
  /// The value of `key`, inserted as 0 if absent.
  std::uint32_t& operator[](VoxelKey key)
  {
    if (2 * (size_ + 1) > slots_.size())
      grow();
    Slot& slot = slots_[findSlot(key)];
    if (slot.key == kEmpty) {
      slot.key = key;
      ++size_;
    }
    return slot.value;
  }
  /// The value of `key`, or nullptr if absent.
  const std::uint32_t* find(VoxelKey key) const
  {
    if (slots_.empty())
      return nullptr;
    const Slot& slot = slots_[findSlot(key)];
    return slot.key == key ? &slot.value : nullptr;
  }
  bool contains(VoxelKey key) const { return find(key) != nullptr; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  void clear()
  {
    slots_.clear();
    size_ = 0;
  }

private:
  static constexpr VoxelKey kEmpty = ~VoxelKey{0}; // packKey's keys use 48 bits
  struct Slot {
    VoxelKey key = kEmpty;
    std::uint32_t value = 0;
  };

  /// The slot holding `key`, or the empty one where it would go.
  std::size_t findSlot(VoxelKey key) const
  {
    const std::size_t mask = slots_.size() - 1;
    // Fibonacci hashing (the product's top bits): neighbouring voxels spread out.
    std::size_t i = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
    while (slots_[i].key != key && slots_[i].key != kEmpty)
      i = (i + 1) & mask;
    return i;
  }

  void grow()
  {
    std::vector<Slot> old(std::max<std::size_t>(64, 2 * slots_.size()));
    old.swap(slots_);
    shift_ = 64 - __builtin_ctzll(slots_.size());
    for (const Slot& slot : old)
      if (slot.key != kEmpty)
        slots_[findSlot(slot.key)] = slot;
  }

  std::vector<Slot> slots_; ///< a power of two of them
  std::size_t size_ = 0;
  int shift_ = 64;
};

} // namespace

const std::vector<PartLabel>& evaluatedOrgans()
{
  static const std::vector<PartLabel> organs = {PartLabel::stem,    PartLabel::petiole,
                                                PartLabel::leaflet, PartLabel::peduncle,
                                                PartLabel::fruit,   PartLabel::flower};
  return organs;
}

struct ReconstructionEvaluator::Impl {
  CloudXYZ::Ptr ground_truth;
  /// Per ground-truth voxel (ground_truth's order), a bit (1 << label) for every part
  /// label of the samples in it.
  std::vector<std::uint32_t> voxel_labels;
  /// The whole ground truth as reference: its tree is built once, in setGroundTruth.
  std::unique_ptr<ReconstructionMetrics> whole;
  TriangleMesh background;
  /// Voxels of the levels' boxes near the background and free of ground truth.
  VoxelKeyMap background_keys;
  /// Where background_keys were looked for (the levels' bounding box).
  Box background_region;

  void updateBackgroundKeys(const std::vector<EvaluationLevel>& levels,
                            double resolution);
  /// Per level, the ROIs scored separately (one per box, or the whole ROI) and the
  /// ground truth cropped to each.
  std::vector<std::vector<Roi>> parts;
  std::vector<std::vector<CloudXYZ::ConstPtr>> reference;
  /// One metrics object per part, its reference tree built once in setLevels (a view
  /// only rebuilds the reconstruction's tree).
  std::vector<std::vector<std::unique_ptr<ReconstructionMetrics>>> metrics;
};

void ReconstructionEvaluator::Impl::updateBackgroundKeys(
    const std::vector<EvaluationLevel>& levels, double resolution)
{
  background_keys.clear();
  if (background.empty() || levels.empty() || !ground_truth)
    return;
  const VoxelLattice lattice(resolution);
  Roi all;
  for (const EvaluationLevel& level : levels)
    for (const Box& box : level.roi.boxes())
      all.addBox(box);
  background_region = all.boundingBox();
  const Eigen::Vector3d lo = background_region.min(), hi = background_region.max();
  VoxelKeyMap truth;
  for (const pcl::PointXYZ& p : *ground_truth) {
    VoxelKey key;
    if (keyOf(p, lattice, key))
      truth[key] = 1;
  }
  // A voxel is background if the triangle meets it or one of its 26 neighbours: the
  // box of three voxels' side around it.
  const Eigen::Vector3d near_size = Eigen::Vector3d::Constant(3.0 * resolution);
  for (const auto& t : background.triangles) {
    const Eigen::Vector3d a = background.vertices[t[0]].cast<double>();
    const Eigen::Vector3d b = background.vertices[t[1]].cast<double>();
    const Eigen::Vector3d c = background.vertices[t[2]].cast<double>();
    const Eigen::Vector3d t_lo = a.cwiseMin(b).cwiseMin(c).array() - resolution;
    const Eigen::Vector3d t_hi = a.cwiseMax(b).cwiseMax(c).array() + resolution;
    const Eigen::Vector3d from = t_lo.cwiseMax(lo), to = t_hi.cwiseMin(hi);
    if ((from.array() > to.array()).any())
      continue;
    int first[3], last[3];
    bool inside = true; // no map voxel lies outside the octree
    for (int i = 0; i < 3; ++i)
      inside = inside && lattice.coordToKey(from[i], first[i]) &&
               lattice.coordToKey(to[i], last[i]);
    if (!inside)
      continue;
    int k[3];
    for (k[0] = first[0]; k[0] <= last[0]; ++k[0])
      for (k[1] = first[1]; k[1] <= last[1]; ++k[1])
        for (k[2] = first[2]; k[2] <= last[2]; ++k[2]) {
          const VoxelKey key = packKey(k);
          if (truth.contains(key) || background_keys.contains(key))
            continue;
          const Eigen::Vector3d centre(lattice.keyToCoord(k[0]), lattice.keyToCoord(k[1]),
                                       lattice.keyToCoord(k[2]));
          if (Box(centre, near_size).overlapsTriangle(a, b, c))
            background_keys[key] = 1;
        }
  }
}

ReconstructionEvaluator::ReconstructionEvaluator() : impl_(std::make_unique<Impl>()) {}
ReconstructionEvaluator::~ReconstructionEvaluator() = default;

void ReconstructionEvaluator::setResolution(double resolution_m)
{
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m))
    throw InvalidArgumentError("evaluation resolution must be a finite size > 0 in "
                               "metres, got " +
                               std::to_string(resolution_m));
  resolution_m_ = resolution_m;
}

void ReconstructionEvaluator::setNumberOfThreads(int threads)
{
  if (threads < 0)
    throw InvalidArgumentError("thread count must be >= 0, got " +
                               std::to_string(threads));
  threads_ = threads;
}

void ReconstructionEvaluator::setGroundTruth(const Plant& plant)
{
  auto samples = std::make_shared<CloudXYZ>();
  std::vector<PartLabel> labels; // one per sample, or empty
  if (!plant.mesh.empty()) {
    MeshSampler sampler;
    // Not owned: the sampler does not outlive this call (a copy cost as much as a
    // tenth of the sampling).
    sampler.setInputMesh(MeshSampler::MeshConstPtr(std::shared_ptr<void>(), &plant.mesh));
    sampler.setNumberOfPoints(
        groundTruthSampleCount(sampler.getSurfaceArea(), resolution_m_));
    sampler.setSeed(seed_);
    sampler.setNumberOfThreads(threads_);
    CloudXYZL labelled; // the same points as the unlabelled draw, with their labels
    sampler.sample(labelled);
    samples->reserve(labelled.size());
    labels.reserve(labelled.size());
    for (const pcl::PointXYZL& p : labelled) {
      samples->push_back(pcl::PointXYZ(p.x, p.y, p.z));
      labels.push_back(static_cast<PartLabel>(p.label));
    }
  } else if (!plant.scan_points.empty()) {
    for (const Eigen::Vector3f& p : plant.scan_points)
      samples->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
    labels = plant.scan_labels;
  } else {
    throw InvalidArgumentError("plant '" + plant.name +
                               "' has neither a mesh nor scan points: no ground truth");
  }
  VoxelGridFilter<pcl::PointXYZ> grid;
  grid.setLeafSize(resolution_m_);
  grid.setOutputVoxelCentres(true);
  grid.setInputCloud(samples);
  impl_->ground_truth = std::make_shared<CloudXYZ>();
  grid.filter(*impl_->ground_truth);

  // The organs of each ground-truth voxel: the labels of the samples in it.
  const VoxelLattice lattice(resolution_m_);
  VoxelKeyMap labels_of;
  if (labels.size() == samples->size())
    for (std::size_t i = 0; i < samples->size(); ++i) {
      VoxelKey key;
      const auto label = static_cast<std::uint32_t>(labels[i]);
      if (label < 32 && keyOf((*samples)[i], lattice, key))
        labels_of[key] |= 1u << label;
    }
  impl_->voxel_labels.assign(impl_->ground_truth->size(), 0u);
  for (std::size_t i = 0; i < impl_->ground_truth->size(); ++i) {
    VoxelKey key;
    if (keyOf((*impl_->ground_truth)[i], lattice, key)) {
      if (const std::uint32_t* bits = labels_of.find(key))
        impl_->voxel_labels[i] = *bits;
    }
  }
  impl_->whole = std::make_unique<ReconstructionMetrics>();
  impl_->whole->setThreshold(resolution_m_);
  impl_->whole->setNumberOfThreads(threads_);
  impl_->whole->setReference(impl_->ground_truth);
  if (!levels_.empty())
    setLevels(std::vector<EvaluationLevel>(levels_)); // re-crop the new ground truth
}

void ReconstructionEvaluator::setLevels(const std::vector<EvaluationLevel>& levels)
{
  if (!impl_->ground_truth)
    throw InvalidArgumentError("ReconstructionEvaluator: set the ground truth before the "
                               "levels");
  std::set<std::string> names;
  for (const EvaluationLevel& level : levels) {
    if (level.name.empty())
      throw InvalidArgumentError("an evaluation level needs a name");
    if (level.roi.empty())
      throw InvalidArgumentError("evaluation level '" + level.name + "' has no ROI box");
    if (!names.insert(level.name).second)
      throw InvalidArgumentError("evaluation level '" + level.name + "' given twice");
  }
  impl_->parts.assign(levels.size(), {});
  impl_->reference.assign(levels.size(), {});
  impl_->metrics.clear();
  impl_->metrics.resize(levels.size());
  for (std::size_t l = 0; l < levels.size(); ++l) {
    if (levels[l].average_boxes)
      for (const Box& box : levels[l].roi.boxes())
        impl_->parts[l].push_back(Roi({box}));
    else
      impl_->parts[l].push_back(levels[l].roi);
    for (const Roi& part : impl_->parts[l]) {
      impl_->reference[l].push_back(crop(impl_->ground_truth, part));
      auto metrics = std::make_unique<ReconstructionMetrics>();
      metrics->setThreshold(resolution_m_);
      metrics->setNumberOfThreads(threads_);
      metrics->setReuseDistances(true); // a trial's reconstruction grows view by view
      metrics->setReference(impl_->reference[l].back());
      impl_->metrics[l].push_back(std::move(metrics));
    }
  }
  levels_ = levels;
  impl_->updateBackgroundKeys(levels_, resolution_m_);
}

void ReconstructionEvaluator::setBackground(const TriangleMesh& background)
{
  background.validate();
  impl_->background = background;
  impl_->updateBackgroundKeys(levels_, resolution_m_);
}

std::size_t ReconstructionEvaluator::backgroundVoxelCount() const
{
  return impl_->background_keys.size();
}

const CloudXYZ& ReconstructionEvaluator::getGroundTruth() const
{
  if (!impl_->ground_truth)
    throw InvalidArgumentError("ReconstructionEvaluator: no ground truth set");
  return *impl_->ground_truth;
}

CloudXYZConstPtr
ReconstructionEvaluator::withoutBackground(const CloudXYZ& reconstruction) const
{
  // Copied once (the metrics and the crop take shared pointers).
  auto kept = std::make_shared<CloudXYZ>();
  if (impl_->background_keys.empty()) {
    *kept = reconstruction;
    return kept;
  }
  const VoxelLattice lattice(resolution_m_);
  kept->reserve(reconstruction.size());
  for (const pcl::PointXYZ& p : reconstruction) {
    VoxelKey key;
    if (impl_->background_region.contains(p.x, p.y, p.z) && keyOf(p, lattice, key) &&
        impl_->background_keys.contains(key))
      continue;
    kept->push_back(p);
  }
  return kept;
}

void ReconstructionEvaluator::compute(const CloudXYZ& reconstruction,
                                      std::vector<LevelScore>& scores) const
{
  score(withoutBackground(reconstruction), &scores, nullptr);
}

void ReconstructionEvaluator::computeOrganRecall(const CloudXYZ& reconstruction,
                                                 std::vector<OrganRecall>& recalls) const
{
  score(withoutBackground(reconstruction), nullptr, &recalls);
}

void ReconstructionEvaluator::compute(const CloudXYZ& reconstruction,
                                      std::vector<LevelScore>& scores,
                                      std::vector<OrganRecall>& recalls) const
{
  score(withoutBackground(reconstruction), &scores, &recalls);
}

void ReconstructionEvaluator::score(const CloudXYZConstPtr& cloud,
                                    std::vector<LevelScore>* scores,
                                    std::vector<OrganRecall>* recalls) const
{
  if (recalls && !impl_->whole) // without it there are no levels either
    throw InvalidArgumentError("ReconstructionEvaluator: no ground truth set");
  // One job per part of a level, and one for the organs' distances (the largest, so
  // first).
  std::vector<std::pair<std::size_t, std::size_t>> parts; // (level, part)
  if (scores)
    for (std::size_t l = 0; l < levels_.size(); ++l)
      for (std::size_t p = 0; p < impl_->parts[l].size(); ++p)
        parts.emplace_back(l, p);
  const long long organ_jobs = recalls ? 1 : 0;
  const long long jobs = organ_jobs + static_cast<long long>(parts.size());
  // On two threads or more the jobs run side by side, one thread each: much of a job is
  // serial (its crop, the reconstruction's tree), and its numbers do not depend on its
  // threads.
  const int threads = threads_ > 0 ? threads_ : omp_get_max_threads();
  const bool side_by_side = threads > 1 && jobs > 1;
  const int job_threads = side_by_side ? 1 : threads;
  std::vector<MetricsResult> results(parts.size());
  std::vector<double> to_mine; // only whether each is below the resolution matters
  std::exception_ptr error;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1) if (side_by_side)
  for (long long j = 0; j < jobs; ++j) {
    try {
      if (j < organ_jobs) {
        ReconstructionMetrics& metrics = *impl_->whole;
        metrics.setNumberOfThreads(job_threads);
        metrics.setReconstruction(cloud);
        metrics.computeDistancesBelow(resolution_m_, to_mine);
      } else {
        const auto [l, p] = parts[static_cast<std::size_t>(j - organ_jobs)];
        ReconstructionMetrics& metrics = *impl_->metrics[l][p];
        metrics.setNumberOfThreads(job_threads);
        metrics.setReconstruction(crop(cloud, impl_->parts[l][p]));
        results[static_cast<std::size_t>(j - organ_jobs)] = metrics.compute();
      }
    } catch (...) {
#pragma omp critical(plantnbv_evaluator_error)
      if (!error)
        error = std::current_exception();
    }
  }
  if (error)
    std::rethrow_exception(error);

  if (scores) { // each level's parts summed in order
    scores->assign(levels_.size(), LevelScore{});
    std::vector<double> chamfer_sum(levels_.size(), 0.0);
    std::vector<std::size_t> chamfer_count(levels_.size(), 0);
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const std::size_t l = parts[i].first;
      const MetricsResult& m = results[i];
      LevelScore& s = (*scores)[l];
      s.precision += m.precision;
      s.recall += m.recall;
      s.f1 += m.f1;
      s.reference_points += m.reference_points;
      s.reconstruction_points += m.reconstruction_points;
      if (m.valid && std::isfinite(m.chamfer)) {
        chamfer_sum[l] += m.chamfer;
        ++chamfer_count[l];
      }
    }
    for (std::size_t l = 0; l < levels_.size(); ++l) {
      LevelScore& s = (*scores)[l];
      const double n = double(impl_->parts[l].size());
      s.precision /= n;
      s.recall /= n;
      s.f1 /= n;
      s.chamfer = chamfer_count[l] ? chamfer_sum[l] / double(chamfer_count[l])
                                   : std::numeric_limits<double>::quiet_NaN();
    }
  }
  if (recalls) {
    const std::vector<PartLabel>& organs = evaluatedOrgans();
    std::vector<std::size_t> found(organs.size(), 0);
    recalls->assign(organs.size(), OrganRecall{});
    for (std::size_t o = 0; o < organs.size(); ++o)
      (*recalls)[o].organ = organs[o];
    for (std::size_t i = 0; i < impl_->voxel_labels.size(); ++i)
      for (std::size_t o = 0; o < organs.size(); ++o)
        if (impl_->voxel_labels[i] & (1u << static_cast<std::uint32_t>(organs[o]))) {
          ++(*recalls)[o].reference_points;
          if (to_mine[i] < resolution_m_)
            ++found[o];
        }
    for (std::size_t o = 0; o < organs.size(); ++o)
      (*recalls)[o].recall =
          (*recalls)[o].reference_points
              ? double(found[o]) / double((*recalls)[o].reference_points)
              : std::numeric_limits<double>::quiet_NaN();
  }
}

void ReconstructionEvaluator::classify(const CloudXYZ& reconstruction, std::size_t level,
                                       VoxelOutcomes& outcomes) const
{
  if (level >= levels_.size())
    throw InvalidArgumentError("evaluation level " + std::to_string(level) +
                               " does not exist (" + std::to_string(levels_.size()) +
                               " levels)");
  const Roi& roi = levels_[level].roi;
  const CloudXYZ::ConstPtr mine = crop(withoutBackground(reconstruction), roi);
  const CloudXYZ::ConstPtr truth = crop(impl_->ground_truth, roi);
  ReconstructionMetrics metrics;
  metrics.setThreshold(resolution_m_);
  metrics.setNumberOfThreads(threads_);
  metrics.setReference(truth);
  metrics.setReconstruction(mine);
  std::vector<double> to_truth, to_mine;
  metrics.computeDistances(to_truth, to_mine);
  outcomes = VoxelOutcomes{};
  for (std::size_t i = 0; i < mine->size(); ++i)
    (to_truth[i] < resolution_m_ ? outcomes.correct : outcomes.wrong)
        .push_back((*mine)[i].getVector3fMap());
  for (std::size_t i = 0; i < truth->size(); ++i)
    if (!(to_mine[i] < resolution_m_))
      outcomes.missed.push_back((*truth)[i].getVector3fMap());
}

} // namespace plantnbv
