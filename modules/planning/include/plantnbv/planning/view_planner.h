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
  bool stop = false; ///< best gain < the stop threshold (NBV only)
  /// The NBV planner ranked the candidates by their gain in its exploration region
  /// (AttentionNbvPlanner::setExploration); `utility` is that gain then.
  bool explored = false;
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
  /// \brief Records a position the camera has taken a frame from (world frame, metres;
  /// ActiveVisionSession records every frame it integrates), for
  /// AttentionNbvPlanner::setViewSpacing.
  void addVisitedPosition(const Eigen::Vector3d& position_W)
  {
    visited_W_.push_back(position_W);
  }
  /// \brief Replaces the recorded positions (world frame, metres), e.g. a new planner
  /// taking over a session's.
  void setVisitedPositions(std::vector<Eigen::Vector3d> positions_W)
  {
    visited_W_ = std::move(positions_W);
  }
  /// \brief The positions recorded by addVisitedPosition, oldest first.
  const std::vector<Eigen::Vector3d>& getVisitedPositions() const { return visited_W_; }
  /// \brief Forgets the visited positions (a new map, a new plant).
  void clearVisitedPositions() { visited_W_.clear(); }
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
  std::vector<Eigen::Vector3d> visited_W_;  ///< where frames were taken from
  InformationGain gain_;   ///< the gain calculator (config, ROI, threads)
  std::uint64_t seed_ = 0; ///< the seed of rng_
  Rng rng_{0};             ///< draws candidates; reseeded by setSeed()
};

/// \brief AttentionNbvPlanner's default view spacing (metres), chosen by the main study
/// (docs/planning.md, "What the gain counts"); the paper's planner has none (0).
constexpr double kDefaultViewSpacingM = 0.2;

/// \brief The attention-driven NBV planner (paper Algorithm 1): draws candidates from
/// the sampler, computes the gain of every one in the ROI, and picks the arg max (ties:
/// the lowest index).
///
/// Optional, beyond the paper: with a travel-cost weight lambda > 0 the chosen candidate
/// maximises the utility gain - lambda * |position - current position| (metres; needs
/// setCurrentView()). With an exploration share, it explores once the ROI has little
/// left to give (setExploration).
class AttentionNbvPlanner : public ViewPlanner {
public:
  /// \brief Optional, beyond the paper (Zaenker et al.'s switch from the ROI to
  /// exploration): once the best gain in the ROI falls below `share` times the largest
  /// best gain of the planner's steps so far, the candidates are ranked by their gain in
  /// `region` instead (same GainConfig; empty region: every voxel), until the ROI's gain
  /// rises again. The travel cost applies to either. Calling it starts the count of
  /// steps afresh. share in [0, 1]; 0 (default) never explores. \throws
  /// InvalidArgumentError for a share outside [0, 1] or a bad region box (as
  /// InformationGain::setRoi).
  void setExploration(double share, const Roi& region = Roi());
  /// \brief The exploration share (0: never explores).
  double getExplorationShare() const { return explore_share_; }
  /// \brief Beyond the paper: while at most `views` views have been taken (the visited
  /// positions, addVisitedPosition), the candidates are ranked by their gain in
  /// setExploration's region, whatever the ROI's gain. For an ROI that knows only what
  /// the frames showed (detections): after one view it holds the nodes that view saw,
  /// and a view chosen for them rarely shows the hidden ones (docs/planning.md). 0
  /// (default): never. \throws InvalidArgumentError for views < 0.
  void setExplorationViews(int views);
  /// \brief The views up to which the planner explores (0: none).
  int getExplorationViews() const { return explore_views_; }
  /// \brief True while setExplorationViews' rule holds: few enough views taken.
  bool exploresTheFirstViews() const
  {
    return explore_views_ > 0 &&
           visited_W_.size() <= static_cast<std::size_t>(explore_views_);
  }
  /// \brief Beyond the paper: a candidate closer than `spacing_m` to a visited position
  /// (addVisitedPosition) is chosen only when every candidate is; greedy views otherwise
  /// cluster where the gain's sparse rays still see something, and leave parts of the
  /// sector unvisited (docs/planning.md). Metres, >= 0; default kDefaultViewSpacingM; 0
  /// (the paper's): no spacing. \throws InvalidArgumentError for a negative or non-finite
  /// spacing.
  void setViewSpacing(double spacing_m);
  /// \brief The view spacing in metres (0: none).
  double getViewSpacing() const { return view_spacing_m_; }

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
  /// The arg max of utility(i) - lambda * travel distance over the candidates far
  /// enough from visited positions (all when none is); strict > keeps the lowest index
  /// on ties. Returns the index, and the best utility in `best_utility`.
  template <typename Utility>
  std::size_t argMax(Utility utility, double& best_utility) const;

  double stop_gain_ = 0.0;
  double travel_cost_weight_ = 0.0;
  double explore_share_ = 0.0;
  int explore_views_ = 0;
  double view_spacing_m_ = kDefaultViewSpacingM;
  double peak_gain_ = 0.0;       ///< the largest best ROI gain since setExploration()
  InformationGain explore_gain_; ///< the gain in the exploration region
  std::vector<Viewpoint> views_;
  std::vector<ViewGain> gains_;
  std::vector<ViewGain> explore_gains_;
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
