#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/common/error.h>
#include <plantnbv/session/active_vision_session.h>

namespace plantnbv {

void ActiveVisionSession::Config::validate() const
{
  map.validate();
  sector.validate();
  gain.validate();
  const auto bad = [](const std::string& field, int value, const char* expected) {
    throw InvalidArgumentError("session config: " + field + " = " +
                               std::to_string(value) + ", expected " + expected);
  };
  if (grid_rows < 1)
    bad("grid_rows", grid_rows, ">= 1");
  if (grid_cols < 1)
    bad("grid_cols", grid_cols, ">= 1");
  if (samples_per_cell < 1)
    bad("samples_per_cell", samples_per_cell, ">= 1");
  if (threads < 0)
    bad("threads", threads, ">= 0 (0: OpenMP's default)");
}

ActiveVisionSession::ActiveVisionSession() : ActiveVisionSession(Config()) {}

ActiveVisionSession::ActiveVisionSession(const Config& config)
    : config_(config), camera_(CameraIntrinsics::l515(L515Mode::vga_640x480)),
      frame_W_(std::make_unique<CloudXYZ>())
{
  config_.validate();
  map_ = std::make_shared<OccupancyMap>(config_.map);
  map_->setNumberOfThreads(config_.threads);
  auto sampler = std::make_shared<CylindricalSectorSampler>(config_.sector);
  sampler->setGrid(config_.grid_rows, config_.grid_cols);
  sampler->setSamplesPerCell(config_.samples_per_cell);
  sampler_ = std::move(sampler);
  setPlanner(std::make_shared<AttentionNbvPlanner>());
}

ActiveVisionSession::~ActiveVisionSession() = default;

void ActiveVisionSession::setCamera(const CameraIntrinsics& intrinsics)
{
  intrinsics.validate();
  camera_ = intrinsics;
  GainConfig gain = config_.gain;
  gain.horizontal_fov_rad = camera_.horizontalFov();
  gain.vertical_fov_rad = camera_.verticalFov();
  planner_->setGainConfig(gain);
}

void ActiveVisionSession::setPlanner(ViewPlanner::Ptr planner)
{
  if (!planner)
    throw InvalidArgumentError("ActiveVisionSession::setPlanner: the planner is null");
  const Roi roi = planner_ ? planner_->getRoi() : Roi();
  const std::optional<Viewpoint> current =
      planner_ ? planner_->getCurrentView() : std::nullopt;
  std::vector<Eigen::Vector3d> visited =
      planner_ ? planner_->getVisitedPositions() : std::vector<Eigen::Vector3d>();
  planner_ = std::move(planner);
  planner_->setVisitedPositions(std::move(visited));
  planner_->setInputMap(map_);
  planner_->setCandidateSampler(sampler_);
  planner_->setRoi(roi);
  planner_->setSeed(config_.seed);
  planner_->setNumberOfThreads(config_.threads);
  if (current)
    planner_->setCurrentView(*current);
  setCamera(camera_);
}

void ActiveVisionSession::setCandidateSampler(ViewpointSampler::ConstPtr sampler)
{
  if (!sampler)
    throw InvalidArgumentError("ActiveVisionSession::setCandidateSampler: the sampler "
                               "is null");
  sampler_ = std::move(sampler);
  planner_->setCandidateSampler(sampler_);
}

void ActiveVisionSession::setRoi(const Roi& roi)
{
  planner_->setRoi(roi);
}

void ActiveVisionSession::setCurrentView(const Viewpoint& view)
{
  planner_->setCurrentView(view);
}

void ActiveVisionSession::integrate(const DepthImage& depth,
                                    const CameraIntrinsics& intrinsics, const Pose& T_W_O)
{
  integrateDepthFrame(*map_, depth, intrinsics, T_W_O, *frame_W_);
  recordFrame(T_W_O.position);
}

void integrateDepthFrame(OccupancyMap& map, const DepthImage& depth,
                         const CameraIntrinsics& intrinsics, const Pose& T_W_O,
                         CloudXYZ& scratch_W)
{
  intrinsics.validate();
  depthToCloud(depth, intrinsics, T_W_O, scratch_W);
  map.insert(scratch_W, T_W_O.position);
}

void ActiveVisionSession::integrate(const CloudXYZ& cloud_W,
                                    const Eigen::Vector3d& origin_W)
{
  map_->insert(cloud_W, origin_W);
  recordFrame(origin_W);
}

void ActiveVisionSession::integrate(const CloudXYZL& cloud_W,
                                    const Eigen::Vector3d& origin_W)
{
  map_->insert(cloud_W, origin_W);
  recordFrame(origin_W);
}

void ActiveVisionSession::nextBestView(NextBestView& out)
{
  planner_->compute(out.result);
  out.ranking = rankCandidates(out.result);
}

void ActiveVisionSession::setMap(std::shared_ptr<OccupancyMap> map)
{
  if (!map)
    throw InvalidArgumentError("ActiveVisionSession::setMap: the map is null");
  map->setNumberOfThreads(config_.threads);
  planner_->setInputMap(map);
  map_ = std::move(map);
}

void ActiveVisionSession::setMapWithFrame(std::shared_ptr<OccupancyMap> map,
                                          const Eigen::Vector3d& origin_W)
{
  setMap(std::move(map));
  recordFrame(origin_W);
}

void ActiveVisionSession::recordFrame(const Eigen::Vector3d& origin_W)
{
  planner_->addVisitedPosition(origin_W);
}

bool ActiveVisionSession::readMap(const std::string& path)
{
  bool maximum_likelihood = false;
  setMap(OccupancyMap::read(path, config_.map, &maximum_likelihood));
  return !maximum_likelihood;
}

std::vector<RankedView> rankCandidates(const NextViewResult& result)
{
  const std::vector<CandidateView>& c = result.candidates;
  std::vector<std::size_t> order(c.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto before = [&](std::size_t a, std::size_t b) {
    if (a == result.chosen || b == result.chosen)
      return a == result.chosen && b != result.chosen;
    const double ga = c[a].gain.gain, gb = c[b].gain.gain;
    if (std::isnan(ga) || std::isnan(gb))
      return !std::isnan(ga) && std::isnan(gb);
    return ga > gb;
  };
  std::stable_sort(order.begin(), order.end(), before);
  std::vector<RankedView> ranking;
  ranking.reserve(order.size());
  for (std::size_t i : order) {
    RankedView r;
    r.index = i;
    r.viewpoint = c[i].view;
    r.optical_pose = opticalFrame(c[i].view);
    r.gain = c[i].gain;
    ranking.push_back(r);
  }
  return ranking;
}

} // namespace plantnbv
