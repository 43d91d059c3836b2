#pragma once
/// \file active_vision_session.h
/// \brief ActiveVisionSession: the NBV loop of a robot, with no simulator: depth frames
/// and poses in, the ranked next views out. Trials drive the same class with the
/// simulated camera; `plantnbv integrate` / `plan` and the frames folder of
/// docs/real-robot.md drive it with anyone's frames.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/camera/depth_image.h>
#include <plantnbv/common/box.h>
#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/common/pose.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/planning/cylindrical_sector_sampler.h>
#include <plantnbv/planning/information_gain.h>
#include <plantnbv/planning/view_planner.h>

namespace plantnbv {

/// \brief A candidate of a planning step, with both of its poses.
struct RankedView {
  std::size_t index = 0; ///< in the planner's candidate list (NextViewResult::candidates)
  Viewpoint viewpoint;   ///< the body frame (x forward, y left, z up), as trials use it
  Pose optical_pose;     ///< T_W_O (z forward, x right, y down), as frames folders use it
  ViewGain gain;         ///< NaN gain where the planner computed none (baselines)
};

/// \brief What nextBestView() returns: the planner's result and the candidates ranked.
struct NextBestView {
  NextViewResult result; ///< result.view is the chosen view (the best for NBV)
  /// The chosen candidate first, then the others by decreasing gain (ties: the lower
  /// index; candidates without a gain last).
  std::vector<RankedView> ranking;
};

/// \brief The active-vision loop over one occupancy map: integrate frames, set the ROI,
/// ask for the next-best view, save the map.
///
/// \code
/// ActiveVisionSession session;               // the paper's map, sector and planner
/// session.setCamera(intrinsics);             // the candidates' frusta
/// session.setRoi(roi);                       // what to attend to (empty: everything)
/// session.integrate(depth, intrinsics, T_W_O);
/// NextBestView next;
/// session.nextBestView(next);                // next.ranking[0].optical_pose: go there
/// session.writeMap("map.ot");
/// \endcode
///
/// Links the camera model, the map and the planner only: no ray caster, no plant
/// generator, no renderer. Deterministic: the same frames, ROI and seed give the same
/// map and the same views on any number of threads.
class ActiveVisionSession {
public:
  /// \brief The map, the candidates and the planner's parameters. Defaults: the paper's
  /// (Table 1, data/paper.yaml).
  struct Config {
    OccupancyMap::Config map; ///< resolution, sensor model, max range
    /// Where candidates lie (the plant's stem axis at axis_base).
    CylindricalSector sector;
    int grid_rows = 3;        ///< sector grid rows (along z), >= 1
    int grid_cols = 3;        ///< sector grid columns (along the arc), >= 1
    int samples_per_cell = 3; ///< 27 candidates on the 3 x 3 grid
    /// Rays and range of the gain; the fields of view are replaced by the camera's.
    GainConfig gain;
    std::uint64_t seed = 0; ///< the planner's draws
    int threads = 0;        ///< 0: OpenMP's default; results do not depend on it

    /// \throws InvalidArgumentError naming the first bad field.
    void validate() const;
  };

  /// \brief The paper's configuration, an empty map, the L515 at 640 x 480, the
  /// attention NBV planner and no ROI.
  ActiveVisionSession();
  /// \throws InvalidArgumentError as Config::validate().
  explicit ActiveVisionSession(const Config& config);
  ~ActiveVisionSession();

  /// \brief The configuration the session was made with.
  const Config& getConfig() const { return config_; }

  /// \brief The camera whose frusta the candidates have (only its fields of view count).
  /// \throws InvalidArgumentError as CameraIntrinsics::validate().
  void setCamera(const CameraIntrinsics& intrinsics);
  /// \brief The camera whose fields of view the candidates have.
  const CameraIntrinsics& getCamera() const { return camera_; }
  /// \brief The planner (AttentionNbvPlanner by default); the session gives it its map,
  /// sampler, ROI, gain, seed and threads. \throws InvalidArgumentError if null.
  void setPlanner(ViewPlanner::Ptr planner);
  /// \brief The planner (to set its own options, e.g. a stop gain).
  ViewPlanner& getPlanner() { return *planner_; }
  /// \brief Replaces the candidates of the config's sector (e.g. a robot's reachable
  /// poses). \throws InvalidArgumentError if null.
  void setCandidateSampler(ViewpointSampler::ConstPtr sampler);
  /// \brief Where candidates come from (the config's sector unless replaced).
  const ViewpointSampler::ConstPtr& getCandidateSampler() const { return sampler_; }
  /// \brief What the gain counts; empty: every voxel. May change at any time.
  /// \throws InvalidArgumentError as InformationGain::setRoi.
  void setRoi(const Roi& roi);
  /// \brief What the gain counts (empty: every voxel).
  const Roi& getRoi() const { return planner_->getRoi(); }
  /// \brief The camera's body pose now (for the planner's travel cost).
  void setCurrentView(const Viewpoint& view);

  /// \brief Integrates a depth frame: depthToCloud (camera/depth_image.h), then the
  /// map's update from the optical centre.
  /// \param[in] T_W_O the optical frame (z forward, x right, y down) in the world.
  /// \throws InvalidArgumentError as CameraIntrinsics::validate, depthToCloud and
  /// OccupancyMap::insert.
  void integrate(const DepthImage& depth, const CameraIntrinsics& intrinsics,
                 const Pose& T_W_O);
  /// \brief Integrates a cloud in the world frame seen from `origin_W`.
  void integrate(const CloudXYZ& cloud_W, const Eigen::Vector3d& origin_W);
  /// \brief As above, for a labelled cloud (the labels are not used).
  void integrate(const CloudXYZL& cloud_W, const Eigen::Vector3d& origin_W);

  /// \brief One planning step on the current map. \throws InvalidArgumentError as the
  /// planner's compute().
  void nextBestView(NextBestView& out);

  /// \brief The map (shared with the planner).
  const std::shared_ptr<OccupancyMap>& getMap() const { return map_; }
  /// \brief Replaces the map (e.g. one read from a file). \throws InvalidArgumentError
  /// if null.
  void setMap(std::shared_ptr<OccupancyMap> map);
  /// \brief Replaces the map by one that holds the frames integrated so far and one more
  /// seen from `origin_W` (e.g. a kept copy of that frame's integration): the session is
  /// then as after integrate() of that frame, its origin recorded for the planner's view
  /// spacing. \throws InvalidArgumentError if null.
  void setMapWithFrame(std::shared_ptr<OccupancyMap> map,
                       const Eigen::Vector3d& origin_W);
  /// \brief Reads a map (OccupancyMap::read with the config's map parameters).
  /// \return false if the file was a .bt (maximum likelihood: no uncertainty left).
  bool readMap(const std::string& path);
  /// \brief Writes the map, .ot (log-odds, what planning needs) or .bt, by extension.
  void writeMap(const std::string& path) const { map_->write(path); }

private:
  /// What every frame leaves besides the map: its origin, a visited position.
  void recordFrame(const Eigen::Vector3d& origin_W);

  Config config_;
  CameraIntrinsics camera_;
  std::shared_ptr<OccupancyMap> map_;
  ViewpointSampler::ConstPtr sampler_;
  ViewPlanner::Ptr planner_;
  std::unique_ptr<CloudXYZ> frame_W_; ///< scratch of integrate(depth, ...)
};

/// \brief The one rule for a depth frame into a map: intrinsics checked, depthToCloud
/// into `scratch_W`, then the map's update from the optical centre T_W_O.position.
/// \throws InvalidArgumentError as CameraIntrinsics::validate, depthToCloud and
/// OccupancyMap::insert.
void integrateDepthFrame(OccupancyMap& map, const DepthImage& depth,
                         const CameraIntrinsics& intrinsics, const Pose& T_W_O,
                         CloudXYZ& scratch_W);

/// \brief The ranking of a planning step's candidates (NextBestView::ranking's order).
std::vector<RankedView> rankCandidates(const NextViewResult& result);

} // namespace plantnbv
