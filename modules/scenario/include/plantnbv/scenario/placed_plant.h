#pragma once
/// \file placed_plant.h
/// \brief The plant a trial or a tool works on: a generated tomato plant (a seed) or a
/// model file (mesh or scanned cloud), placed in the world as the paper's scene has it,
/// with the ROIs it comes with.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/common/box.h>
#include <plantnbv/common/roi_kind.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/plant/plant.h>

namespace plantnbv {
namespace scenario {

/// \brief The largest turn of a plant about its stem, either way: one revolution
/// (degrees).
constexpr double kMaxPlantYawDeg = 360.0;

/// \brief Where a plant comes from and where it stands. Set a seed or a model.
struct PlantSource {
  std::optional<std::uint64_t> seed; ///< a generated tomato plant (0-9: the default set)
  std::optional<double> stage;       ///< its growth stage in [0, 1] (default: seed/9)
  bool simplified = false;           ///< half of the leaflets of every leaf removed
  std::string
      model; ///< or a mesh (.dae .obj .ply .stl .wrl) or scanned cloud (.pcd .ply)
  /// Further mesh files of the same model (a plant split into several files, e.g. one
  /// per part), merged with `model` into one mesh.
  std::vector<std::string> model_parts;
  std::string labels; ///< part label rules of a mesh, e.g. "stem=Branch.*,leaflet=Leaf.*"
  /// A model's metres per file unit (0.01: centimetres); 0 = the file's (Collada's
  /// `<unit>`, else metres). Replaces the file's unit (io::MeshLoadOptions::scale).
  double scale = 0.0;
  /// A model's up axis in its file (io::MeshLoadOptions::up_axis): from_file reads
  /// Collada's `<up_axis>` and VRML as y up, other formats as z up; y for an OBJ
  /// exported y up (Blender's default). A scanned cloud: from_file is z.
  io::MeshLoadOptions::UpAxis up_axis = io::MeshLoadOptions::UpAxis::from_file;
  std::string rois;        ///< the user's ROI file (world frame): the level "model_rois"
  bool keep_frame = false; ///< a model: keep the file's coordinates (no base, no yaw)
  double yaw_deg = 0.0;    ///< turn about the stem (degrees), within +-kMaxPlantYawDeg
  Eigen::Vector3d base{1.0, 0.0, 0.8}; ///< plant base, world frame (Table 1 of the paper)
};

/// \brief A plant posed in the world frame with its ROIs.
struct PlacedPlant {
  PlantSource source; ///< what it was made from
  Plant plant;        ///< mesh (or scan) and anatomy, posed in the world frame
  /// The plant's own ROIs, world frame: every kind for a generated plant (fruit only
  /// when it has fruit); whole_plant (the bounding box) for a model, and fruit (one box
  /// per connected group of fruit triangles, labelledPartRoi) when it has any.
  std::map<RoiKind, Roi> rois;
  /// The boxes of PlantSource::rois (the user's ROI file); empty otherwise.
  Roi model_rois;
  std::string description; ///< e.g. "seed 3, growth stage 0.333"
  /// What the user should hear about the source, one line each: a label rule that
  /// labelled nothing, a scan's labels beyond ours, a Collada file without a unit, an ROI
  /// box that misses the plant.
  std::vector<std::string> warnings;

  /// \brief The ROI of `kind`, or nullptr when the plant has none.
  const Roi* roi(RoiKind kind) const;
};

/// \brief Generates or loads the plant and places it: base at `base`, turned by
/// `yaw_deg` about its stem (a model: the centre of its bounding box's bottom face is the
/// base, unless keep_frame).
/// \throws InvalidArgumentError for a source with neither or both of seed and model,
/// labels, scale, an up axis or keep_frame without a model, a negative or non-finite
/// scale, a non-finite base, a yaw outside
/// [-kMaxPlantYawDeg, kMaxPlantYawDeg]; the io and plant errors of the files and the
/// generator.
PlacedPlant makePlacedPlant(const PlantSource& source);

/// \brief The neighbours of `target` in a greenhouse row (paper section 5.4): one on each
/// side, `spacing_m` from its base, along the row, which runs across `facing_rad` (the
/// azimuth from the plant towards the camera's side, CylindricalSector::facingAzimuth),
/// at the base's height. A generated plant's neighbours are the next two seeds of the
/// default set (seed + 1 and + 2, cyclically within 0-9; beyond it, seed + 1 and + 2),
/// with its growth-stage rule and simplification; a model's are the same model. They are
/// turned by the target's yaw plus 120 and 240 degrees, so that no leaf repeats.
/// \throws InvalidArgumentError for a spacing that is not finite and > 0, a non-finite
/// facing, or a target with keep_frame (a kept frame has no base to space from); as
/// makePlacedPlant.
std::vector<PlacedPlant> rowNeighbours(const PlantSource& target, double spacing_m,
                                       double facing_rad);

} // namespace scenario
} // namespace plantnbv
