#pragma once
/// \file cylindrical_sector_sampler.h
/// \brief Candidate views on the paper's cylindrical sector around the stem (section
/// 3.1, Table 1), drawn pseudo-randomly per grid cell (section 3.3.1, Stage II).

#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/planning/viewpoint_sampler.h>

namespace plantnbv {

/// \brief The paper's cylindrical sector (section 3.1, Table 1): the part of a vertical
/// cylinder around the stem on which the camera may be placed.
///
/// Points of the sector: axis_base + (radius cos(phi), radius sin(phi), z - axis_base.z)
/// for azimuth phi in [facing - angle / 2, facing + angle / 2] and z in
/// [axis_base.z + bottom_m, axis_base.z + bottom_m + height_m]. Defaults are the paper's:
/// radius 0.4 m, height 0.7 m, opening angle 90 deg, facing the robot.
struct CylindricalSector {
  /// A point on the (vertical) stem axis: the plant base (metres, world). Default the
  /// paper's (1.0, 0, 0.8).
  Eigen::Vector3d axis_base{1.0, 0.0, 0.8};
  double radius_m = 0.4; ///< distance of the camera from the axis (metres), > 0
  /// The sector spans z in [axis_base.z + bottom_m, + height_m] (metres), > 0.
  double height_m = 0.7;
  double bottom_m = 0.0; ///< height of the sector's lower edge above axis_base (metres)
  double angle_rad = M_PI / 2; ///< 2*theta, the full opening angle, in (0, 2 pi]
  /// Azimuth (world, rad, from +x towards +y) of the sector's centre line as seen from
  /// the axis. NaN (default) = facing the robot at the world origin:
  /// atan2(-axis_base.y, -axis_base.x).
  double facing_rad = std::numeric_limits<double>::quiet_NaN();

  /// \brief Checks every field. \throws InvalidArgumentError naming the first bad field,
  /// its value and the expected range (also when facing_rad is NaN and the axis passes
  /// through the world origin, where "facing the robot" is undefined).
  void validate() const;
  /// \brief facing_rad, or for NaN the azimuth of the world origin seen from the axis, in
  /// (-pi, pi]. \throws InvalidArgumentError as validate() when it is undefined.
  double facingAzimuth() const;
};

/// \brief Samples candidate views on a CylindricalSector, pseudo-randomly per cell of a
/// rows x cols grid (the paper's 3 x 3 grid with 1, 3 or 5 samples per cell: 9, 27 or 45
/// candidates).
///
/// Every viewpoint looks horizontally at the stem axis: it is on the cylinder at
/// (azimuth phi, height z) with yaw phi + pi (towards the axis point at the same height),
/// pitch 0 and roll 0, like the paper's v0. Cells are indexed row * cols + col, row 0 at
/// the bottom, col 0 at the smallest azimuth.
///
/// Thread safety: const methods may run concurrently; setters must not run concurrently
/// with anything else.
class CylindricalSectorSampler : public ViewpointSampler {
public:
  using Ptr = std::shared_ptr<CylindricalSectorSampler>;            ///< shared sampler
  using ConstPtr = std::shared_ptr<const CylindricalSectorSampler>; ///< shared, read-only

  /// \brief The paper's sector, 3 x 3 grid, 3 samples per cell (27 candidates).
  CylindricalSectorSampler();
  /// \brief `sector`, 3 x 3 grid, 3 samples per cell.
  /// \throws InvalidArgumentError as CylindricalSector::validate().
  explicit CylindricalSectorSampler(const CylindricalSector& sector);

  /// \throws InvalidArgumentError as CylindricalSector::validate().
  void setSector(const CylindricalSector& sector);
  /// \brief The sector the candidates are drawn on.
  const CylindricalSector& getSector() const { return sector_; }

  /// \brief The grid: `rows` along z, `cols` along the arc; both >= 1 (default 3 x 3).
  /// \throws InvalidArgumentError naming the bad value.
  void setGrid(int rows, int cols);
  /// \brief Grid rows (along z).
  int getRows() const { return rows_; }
  /// \brief Grid columns (along the arc).
  int getCols() const { return cols_; }
  /// \brief rows x cols.
  int getCellCount() const { return rows_ * cols_; }

  /// \brief Samples per cell, >= 1 (default 3); 1, 3, 5 give 9, 27, 45 on a 3 x 3 grid.
  /// \throws InvalidArgumentError naming the bad value.
  void setSamplesPerCell(int k);
  /// \brief Viewpoints drawn per cell.
  int getSamplesPerCell() const { return samples_per_cell_; }

  /// \brief Uniform on the sector's surface within each cell (uniform in arc angle and
  /// in z: the surface element is r dphi dz, so uniform in phi and z is area-uniform),
  /// cells in a fixed order (row-major, row 0 = bottom, col 0 = the smallest azimuth),
  /// k draws per cell, each a viewpoint at that surface point looking at the stem axis
  /// horizontally (yaw towards the axis point at the same height, pitch 0, roll 0, like
  /// the paper's v0). Each draw takes rng.uniform() for the azimuth, then rng.uniform()
  /// for z: rows * cols * k viewpoints, those of cell c at [c * k, (c + 1) * k).
  void sample(Rng& rng, std::vector<Viewpoint>& out) const override;

  /// \brief The rows * cols cell centres (same order), as viewpoints looking at the axis.
  std::vector<Viewpoint> gridCellCentres() const;

  /// \brief The viewpoint at (azimuth, z) on the cylinder looking at the axis.
  /// \param[in] azimuth_rad world azimuth of the camera as seen from the axis (rad).
  /// \param[in] z height of the camera (metres, world).
  Viewpoint viewpointAt(double azimuth_rad, double z) const;

  /// \brief The cell (row * cols + col) holding (azimuth, z), or -1 if it lies outside
  /// the sector (azimuth taken modulo 2 pi).
  int cellOf(double azimuth_rad, double z) const;

private:
  CylindricalSector sector_;
  int rows_ = 3;
  int cols_ = 3;
  int samples_per_cell_ = 3;
};

} // namespace plantnbv
