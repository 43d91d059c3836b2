#include <cmath>
#include <sstream>

#include <plantnbv/common/error.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/planning/cylindrical_sector_sampler.h>
#include <plantnbv/planning/view_planner.h>

namespace plantnbv {

namespace {

/// A baseline's result: `views[chosen]` is the next view; only its gain is computed (the
/// other candidates report gain NaN). `start` is when the planner's compute() began.
void fillBaselineResult(InformationGain& gain, const std::vector<Viewpoint>& views,
                        std::size_t chosen, const Stopwatch& start, NextViewResult& out)
{
  const double sample_ms = start.ms();
  const Stopwatch gain_start;
  const ViewGain chosen_gain = gain.compute(views[chosen]);
  out.gain_ms = gain_start.ms();
  out.update_ms = gain.getLastStats().rebuilt ? gain.getLastStats().update_ms : 0.0;
  out.candidates.assign(views.size(), CandidateView{});
  for (std::size_t i = 0; i < views.size(); ++i) {
    out.candidates[i].view = views[i];
    out.candidates[i].gain.gain = std::numeric_limits<double>::quiet_NaN();
  }
  out.candidates[chosen].gain = chosen_gain;
  out.chosen = chosen;
  out.view = views[chosen];
  out.gain = chosen_gain.gain;
  out.utility = chosen_gain.gain;
  out.stop = false;
  out.sample_ms = sample_ms;
  out.total_ms = start.ms();
}

} // namespace

void ViewPlanner::setInputMap(std::shared_ptr<const OccupancyMap> map)
{
  if (!map)
    throw InvalidArgumentError("ViewPlanner::setInputMap: the map is null");
  gain_.setInputMap(map);
  map_ = std::move(map);
}

void ViewPlanner::setCandidateSampler(ViewpointSampler::ConstPtr sampler)
{
  if (!sampler)
    throw InvalidArgumentError("ViewPlanner::setCandidateSampler: the sampler is null");
  sampler_ = std::move(sampler);
}

void ViewPlanner::setRoi(const Roi& roi)
{
  gain_.setRoi(roi);
}

void ViewPlanner::setGainConfig(const GainConfig& config)
{
  gain_.setConfig(config);
}

void ViewPlanner::setSeed(std::uint64_t seed)
{
  seed_ = seed;
  rng_ = Rng(seed);
}

void ViewPlanner::setNumberOfThreads(int threads)
{
  gain_.setNumberOfThreads(threads);
}

void ViewPlanner::requireInputs(const char* who) const
{
  if (!map_)
    throw InvalidArgumentError(std::string(who) + ": no map set (setInputMap)");
  if (!sampler_)
    throw InvalidArgumentError(std::string(who) +
                               ": no candidate sampler set (setCandidateSampler)");
}

// --- AttentionNbvPlanner ---------------------------------------------------------------

void AttentionNbvPlanner::setStopGain(double bits)
{
  if (std::isnan(bits))
    throw InvalidArgumentError("AttentionNbvPlanner::setStopGain: NaN must be a number "
                               "of bits (0: never stop)");
  stop_gain_ = bits;
}

void AttentionNbvPlanner::setTravelCostWeight(double lambda)
{
  if (!(std::isfinite(lambda) && lambda >= 0.0)) {
    std::ostringstream s;
    s << "AttentionNbvPlanner::setTravelCostWeight: lambda = " << lambda
      << " must be finite and >= 0 (bits per metre; 0: no travel cost)";
    throw InvalidArgumentError(s.str());
  }
  travel_cost_weight_ = lambda;
}

void AttentionNbvPlanner::setExploration(double share, const Roi& region)
{
  if (!(share >= 0.0 && share <= 1.0)) {
    std::ostringstream s;
    s << "AttentionNbvPlanner::setExploration: share = " << share
      << " must be in [0, 1] (0: never explore)";
    throw InvalidArgumentError(s.str());
  }
  explore_gain_.setRoi(region);
  explore_share_ = share;
  peak_gain_ = 0.0;
}

void AttentionNbvPlanner::setExplorationViews(int views)
{
  if (views < 0)
    throw InvalidArgumentError("AttentionNbvPlanner::setExplorationViews: views = " +
                               std::to_string(views) + " must be >= 0 (0: never)");
  explore_views_ = views;
}

void AttentionNbvPlanner::setViewSpacing(double spacing_m)
{
  if (!(std::isfinite(spacing_m) && spacing_m >= 0.0)) {
    std::ostringstream s;
    s << "AttentionNbvPlanner::setViewSpacing: " << spacing_m
      << " must be finite and >= 0 (metres; 0: no spacing)";
    throw InvalidArgumentError(s.str());
  }
  view_spacing_m_ = spacing_m;
}

template <typename Utility>
std::size_t AttentionNbvPlanner::argMax(Utility utility, double& best_utility) const
{
  std::vector<bool> spaced(views_.size(), true);
  bool any_spaced = false;
  for (std::size_t i = 0; i < views_.size(); ++i) {
    for (const Eigen::Vector3d& p : visited_W_)
      if ((views_[i].position - p).norm() < view_spacing_m_)
        spaced[i] = false;
    any_spaced = any_spaced || spaced[i];
  }
  std::size_t best = 0;
  best_utility = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < views_.size(); ++i) {
    if (any_spaced && !spaced[i])
      continue;
    double u = utility(i);
    if (travel_cost_weight_ > 0.0)
      u -= travel_cost_weight_ * (views_[i].position - current_view_->position).norm();
    if (u > best_utility) {
      best_utility = u;
      best = i;
    }
  }
  return best;
}

void AttentionNbvPlanner::compute(NextViewResult& out)
{
  requireInputs("AttentionNbvPlanner::compute");
  if (travel_cost_weight_ > 0.0 && !current_view_)
    throw InvalidArgumentError("AttentionNbvPlanner::compute: a travel cost weight of " +
                               std::to_string(travel_cost_weight_) +
                               " needs the current view (setCurrentView)");
  const Stopwatch start;
  sampler_->sample(rng_, views_);
  const double sample_ms = start.ms();
  if (views_.empty())
    throw InvalidArgumentError(
        "AttentionNbvPlanner::compute: the sampler drew no candidate");
  const Stopwatch gain_start;
  gain_.compute(views_, gains_);
  double update_ms = gain_.getLastStats().rebuilt ? gain_.getLastStats().update_ms : 0.0;

  double max_gain = -std::numeric_limits<double>::infinity();
  for (const ViewGain& g : gains_)
    max_gain = std::max(max_gain, g.gain);
  peak_gain_ = std::max(peak_gain_, max_gain);
  out.explored = exploresTheFirstViews() ||
                 (explore_share_ > 0.0 && max_gain < explore_share_ * peak_gain_);

  std::size_t best;
  double best_utility;
  if (out.explored) {
    explore_gain_.setConfig(gain_.getConfig());
    explore_gain_.setNumberOfThreads(gain_.getNumberOfThreads());
    if (explore_gain_.getInputMap() != map_)
      explore_gain_.setInputMap(map_);
    explore_gain_.compute(views_, explore_gains_);
    if (explore_gain_.getLastStats().rebuilt)
      update_ms += explore_gain_.getLastStats().update_ms;
    best = argMax([&](std::size_t i) { return explore_gains_[i].gain; }, best_utility);
  } else {
    best = argMax([&](std::size_t i) { return gains_[i].gain; }, best_utility);
  }
  const double gain_ms = gain_start.ms();

  out.candidates.resize(views_.size());
  for (std::size_t i = 0; i < views_.size(); ++i)
    out.candidates[i] = CandidateView{views_[i], gains_[i]};
  out.chosen = best;
  out.view = views_[best];
  out.gain = gains_[best].gain;
  out.utility = best_utility;
  out.stop = max_gain < stop_gain_;
  out.sample_ms = sample_ms;
  out.gain_ms = gain_ms;
  out.update_ms = update_ms;
  out.total_ms = start.ms();
}

// --- PredefinedPlanner -----------------------------------------------------------------

void PredefinedPlanner::setPattern(int pattern)
{
  if (pattern < 1 || pattern > 4)
    throw InvalidArgumentError("PredefinedPlanner::setPattern: pattern " +
                               std::to_string(pattern) + " must be in 1..4");
  pattern_ = pattern;
}

std::vector<int> PredefinedPlanner::patternOrder(int pattern, int rows, int cols)
{
  if (pattern < 1 || pattern > 4)
    throw InvalidArgumentError("PredefinedPlanner::patternOrder: pattern " +
                               std::to_string(pattern) + " must be in 1..4");
  if (rows < 1 || cols < 1)
    throw InvalidArgumentError(
        "PredefinedPlanner::patternOrder: rows = " + std::to_string(rows) +
        ", cols = " + std::to_string(cols) + ": both must be >= 1");
  std::vector<int> order;
  order.reserve(static_cast<std::size_t>(rows * cols));
  auto cell = [cols](int row, int col) { return row * cols + col; };
  switch (pattern) {
  case 1: // rows bottom to top, alternating left-right / right-left
    for (int r = 0; r < rows; ++r)
      for (int i = 0; i < cols; ++i)
        order.push_back(cell(r, r % 2 == 0 ? i : cols - 1 - i));
    break;
  case 2: // columns left to right, alternating up / down
    for (int c = 0; c < cols; ++c)
      for (int i = 0; i < rows; ++i)
        order.push_back(cell(c % 2 == 0 ? i : rows - 1 - i, c));
    break;
  case 3: { // spiral from the centre: right 1, up 1, left 2, down 2, right 3, ...
    int r = (rows - 1) / 2, c = (cols - 1) / 2;
    order.push_back(cell(r, c));
    const int dr[4] = {0, 1, 0, -1}, dc[4] = {1, 0, -1, 0};
    for (int leg = 0; static_cast<int>(order.size()) < rows * cols; ++leg) {
      const int length = leg / 2 + 1;
      for (int s = 0; s < length; ++s) {
        r += dr[leg % 4];
        c += dc[leg % 4];
        if (r >= 0 && r < rows && c >= 0 && c < cols)
          order.push_back(cell(r, c));
      }
    }
    break;
  }
  case 4: // anti-diagonals row + col = s, each from its bottom end
    for (int s = 0; s <= rows + cols - 2; ++s)
      for (int r = std::max(0, s - (cols - 1)); r <= std::min(rows - 1, s); ++r)
        order.push_back(cell(r, s - r));
    break;
  }
  return order;
}

void PredefinedPlanner::compute(NextViewResult& out)
{
  requireInputs("PredefinedPlanner::compute");
  const auto* sector = dynamic_cast<const CylindricalSectorSampler*>(sampler_.get());
  if (!sector)
    throw InvalidArgumentError(
        "PredefinedPlanner::compute: the candidate sampler must be a "
        "CylindricalSectorSampler (its grid cell centres are the "
        "pre-defined views)");
  const Stopwatch start;
  const std::vector<Viewpoint> centres = sector->gridCellCentres();
  const std::vector<int> order =
      patternOrder(pattern_, sector->getRows(), sector->getCols());
  const std::size_t chosen = static_cast<std::size_t>(order[step_ % order.size()]);
  ++step_;
  fillBaselineResult(gain_, centres, chosen, start, out);
}

// --- RandomPlanner ---------------------------------------------------------------------

void RandomPlanner::compute(NextViewResult& out)
{
  requireInputs("RandomPlanner::compute");
  const Stopwatch start;
  sampler_->sample(rng_, views_);
  if (views_.empty())
    throw InvalidArgumentError("RandomPlanner::compute: the sampler drew no candidate");
  const std::size_t chosen = static_cast<std::size_t>(rng_.index(views_.size()));
  fillBaselineResult(gain_, views_, chosen, start, out);
}

} // namespace plantnbv
