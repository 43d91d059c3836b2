#pragma once
/// \file view_planner.h
/// \brief View planners: the attention-driven NBV planner (the paper's Algorithm 1) and
/// the paper's baselines, pre-defined and random (section 3.3.2).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <plantnbv/common/box.h>
#include <plantnbv/common/pose.h>
#include <plantnbv/common/random.h>
#include <plantnbv/planning/information_gain.h>
#include <plantnbv/planning/viewpoint_sampler.h>

namespace plantnbv {

class OccupancyMap;

/// \brief A candidate and what it would see.
struct CandidateView {
  Viewpoint view; ///< the candidate's camera body pose in the world
  /// Its gain; baselines compute only the chosen one's, the others have gain NaN.
  ViewGain gain;
};

/// \brief The result of one planning step.
struct NextViewResult {
  Viewpoint view;         ///< the chosen next view
  std::size_t chosen = 0; ///< its index in `candidates`
  /// Its gain (bits; the planner's GainConfig and ROI).
  double gain = std::numeric_limits<double>::quiet_NaN();
  /// Its utility: gain - lambda * travel distance (AttentionNbvPlanner with a travel
  /// cost); equal to `gain` otherwise.
  double utility = std::numeric_limits<double>::quiet_NaN();
  /// Every candidate considered (baselines: the ones drawn / the grid).
  std::vector<CandidateView> candidates;
  bool stop = false;    ///< best gain < the stop threshold (NBV only)
  double sample_ms = 0; ///< drawing the candidates
  double gain_ms = 0;   ///< gains, including update_ms
  double update_ms = 0; ///< rebuilding the map snapshot (InformationGain::update)
  double total_ms = 0;  ///< the whole compute()
};

/// \brief A view planner: the planner is to maps what a filter is to clouds
/// (docs/architecture.md). Set the map, the candidate sampler and the parameters, then
/// `compute(result)` gives the next view.
///
/// Randomness: the planner owns an Rng (setSeed, default seed 0); candidates are drawn
/// from it sequentially, so results depend on the seed and the number of compute()
/// calls since, never on the thread count.
///
/// Thread safety: one planner must not be used from several threads at once; several
/// planners may share a map (read-only while they compute) and a sampler.
class ViewPlanner {
public:
  using Ptr = std::shared_ptr<ViewPlanner>; ///< shared planner

  virtual ~ViewPlanner() = default;

  /// \brief The map (not copied; it must not change during compute()).
  /// \throws InvalidArgumentError if null.
  void setInputMap(std::shared_ptr<const OccupancyMap> map);
  /// \brief Where candidates come from. \throws InvalidArgumentError if null.
  void setCandidateSampler(ViewpointSampler::ConstPtr sampler);
  /// \brief The camera's current view (for a travel cost).
  void setCurrentView(const Viewpoint& view) { current_view_ = view; }
  /// \brief The attention ROI (also used to report the chosen view's gain for the
  /// baselines); empty = everything counts. \throws InvalidArgumentError as
  /// InformationGain::setRoi.
  void setRoi(const Roi& roi);
  /// \throws InvalidArgumentError as GainConfig::validate().
  void setGainConfig(const GainConfig& config);
  /// \brief Reseeds the planner's Rng.
  void setSeed(std::uint64_t seed);
  /// \brief Threads of the gain computation; 0 = OpenMP's default. Results do not
  /// depend on it. \throws InvalidArgumentError if < 0.
  void setNumberOfThreads(int threads);

  /// \brief The map, or null before setInputMap().
  const std::shared_ptr<const OccupancyMap>& getInputMap() const { return map_; }
  /// \brief The candidate sampler, or null before setCandidateSampler().
  const ViewpointSampler::ConstPtr& getCandidateSampler() const { return sampler_; }
  /// \brief The camera's current view, if set.
  const std::optional<Viewpoint>& getCurrentView() const { return current_view_; }
  /// \brief The attention ROI (empty: everything counts).
  const Roi& getRoi() const { return gain_.getRoi(); }
  /// \brief How candidates are ray-traced.
  const GainConfig& getGainConfig() const { return gain_.getConfig(); }
  /// \brief The seed last given to setSeed() (default 0).
  std::uint64_t getSeed() const { return seed_; }
  /// \brief The planner's gain calculator (its statistics: getLastStats()).
  const InformationGain& getInformationGain() const { return gain_; }

  /// \brief One planning step. \throws InvalidArgumentError when inputs are missing (no
  /// map, no sampler, or what the planner needs beyond them).
  virtual void compute(NextViewResult& out) = 0;
  /// \brief "nbv", "predefined", "random".
  virtual std::string name() const = 0;

protected:
  /// Throws unless the map and the sampler are set.
  void requireInputs(const char* who) const;

  std::shared_ptr<const OccupancyMap> map_; ///< the map (setInputMap)
  ViewpointSampler::ConstPtr sampler_;      ///< the candidates' source
  std::optional<Viewpoint> current_view_;   ///< the camera's view, if set
  InformationGain gain_;   ///< the gain calculator (config, ROI, threads)
  std::uint64_t seed_ = 0; ///< the seed of rng_
  Rng rng_{0};             ///< draws candidates; reseeded by setSeed()
};

/// \brief The attention-driven NBV planner (paper Algorithm 1): draws candidates from
/// the sampler, computes the gain of every one in the ROI, and picks the arg max (ties:
/// the lowest index).
///
/// Optional, beyond the paper: with a travel-cost weight lambda > 0 the chosen candidate
/// maximises the utility gain - lambda * |position - current position| (metres; needs
/// setCurrentView()).
class AttentionNbvPlanner : public ViewPlanner {
public:
  /// \brief `stop` is set when the best gain is below `bits` (default 0: never).
  /// \throws InvalidArgumentError for NaN.
  void setStopGain(double bits);
  /// \brief The stop threshold in bits (0: never stop).
  double getStopGain() const { return stop_gain_; }
  /// \brief Travel-cost weight lambda (bits per metre, >= 0; default 0: the paper's
  /// arg max of the gain). \throws InvalidArgumentError if negative or not finite.
  void setTravelCostWeight(double lambda);
  /// \brief The travel-cost weight lambda, bits per metre (0: none).
  double getTravelCostWeight() const { return travel_cost_weight_; }

  /// \throws InvalidArgumentError without map or sampler, or with a travel cost and no
  /// current view.
  void compute(NextViewResult& out) override;
  std::string name() const override { return "nbv"; }

private:
  double stop_gain_ = 0.0;
  double travel_cost_weight_ = 0.0;
  std::vector<Viewpoint> views_;
  std::vector<ViewGain> gains_;
};

/// \brief The pre-defined baseline: the centres of the sampler's grid cells
/// (CylindricalSectorSampler::gridCellCentres, 9 on the paper's 3 x 3 grid) in one of
/// four visiting orders, looping when more views are needed (paper section 3.3.2,
/// Fig. 4; docs/planning.md draws the orders). The k-th compute() since reset() takes
/// cell patternOrder(pattern)[k % cells].
class PredefinedPlanner : public ViewPlanner {
public:
  /// \brief The visiting order, 1..4 (default 1):
  /// 1 row-wise zig-zag from the bottom-left cell, 2 column-wise zig-zag from the
  /// bottom-left cell, 3 a spiral from the centre cell outwards, 4 anti-diagonals from
  /// the bottom-left cell (each from its bottom end). \throws InvalidArgumentError
  /// outside 1..4.
  void setPattern(int pattern);
  /// \brief The visiting order, 1..4.
  int getPattern() const { return pattern_; }
  /// \brief Starts the order again at its first cell.
  void reset() { step_ = 0; }
  /// \brief compute() calls since reset().
  std::size_t getStep() const { return step_; }

  /// \brief The cell indices (row * cols + col, row 0 at the bottom, col 0 at the
  /// smallest azimuth) of `pattern` on a rows x cols grid; each cell once.
  /// \throws InvalidArgumentError for a pattern outside 1..4 or rows, cols < 1.
  static std::vector<int> patternOrder(int pattern, int rows = 3, int cols = 3);

  /// \throws InvalidArgumentError without map or sampler, or if the sampler is not a
  /// CylindricalSectorSampler.
  void compute(NextViewResult& out) override;
  std::string name() const override { return "predefined"; }

private:
  int pattern_ = 1;
  std::size_t step_ = 0;
};

/// \brief The random baseline: draws candidates from the sampler like the NBV planner
/// and picks one uniformly (Rng::index) (paper section 3.3.2).
class RandomPlanner : public ViewPlanner {
public:
  void compute(NextViewResult& out) override;
  std::string name() const override { return "random"; }

private:
  std::vector<Viewpoint> views_;
};

} // namespace plantnbv
