#pragma once
/// \file plant.h
/// \brief A plant model with ground truth: its triangle mesh (with a part label per
/// triangle) and its anatomy (stem axis, leaves and leaf nodes, trusses and fruits).
///
/// Frames and units: metres; the plant frame has its origin at the base of the stem
/// (where it leaves the pot) and z up. A generated plant is in the plant frame;
/// posePlant() moves mesh and anatomy together into the world, so every position below
/// is in the plant's current frame (the world frame once posed).

#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/common/triangle_mesh.h>

namespace plantnbv {

/// \brief A leaf node: the point where a leaf's petiole joins the main stem.
struct LeafNode {
  int leaf_index = 0; ///< 0 = lowest (oldest) leaf, counting up the stem
  /// Where the petiole's axis crosses the stem surface (metres).
  Eigen::Vector3d position{Eigen::Vector3d::Zero()};
  /// The point of the stem axis at the node's height (metres).
  Eigen::Vector3d stem_point{Eigen::Vector3d::Zero()};
  /// Unit direction of the petiole where it leaves the stem (points up and out).
  Eigen::Vector3d petiole_direction{Eigen::Vector3d::UnitX()};
};

/// \brief One leaflet of a compound leaf (the blade is a curved, serrated surface).
struct Leaflet {
  Eigen::Vector3d base{Eigen::Vector3d::Zero()}; ///< where the blade meets the rachis
  Eigen::Vector3d tip{Eigen::Vector3d::Zero()};  ///< end of the midrib
  double length_m = 0.0;                         ///< midrib length, before curving
  double width_m = 0.0;                          ///< largest width
  bool terminal = false;                         ///< the odd leaflet at the rachis tip
};

/// \brief A compound leaf: petiole and rachis along `axis`, leaflets in pairs plus one
/// terminal leaflet.
struct Leaf {
  LeafNode node; ///< where the leaf joins the main stem
  /// Centre line of petiole + rachis, from inside the stem to the rachis tip (metres).
  std::vector<Eigen::Vector3d> axis;
  double length_m = 0.0; ///< arc length of petiole + rachis, from the stem surface
  /// The leaflets present in the mesh (a simplified plant keeps about half of them).
  std::vector<Leaflet> leaflets;
  int full_leaflet_count = 0; ///< leaflets of the unsimplified leaf (odd, 5-9)
};

/// \brief A tomato fruit: an oblate spheroid whose equatorial radius is `radius_m`; the
/// sphere of that radius around `center` holds it.
struct Fruit {
  Eigen::Vector3d center{Eigen::Vector3d::Zero()}; ///< centre (metres)
  double radius_m = 0.0;                           ///< equatorial radius (metres)
};

/// \brief A truss (inflorescence): a peduncle from the stem, between two leaves, and
/// its fruits hanging from it on short pedicels.
struct Truss {
  int leaf_below = 0; ///< index of the leaf just below the peduncle's attachment
  /// Where the peduncle's axis crosses the stem surface (metres).
  Eigen::Vector3d attachment{Eigen::Vector3d::Zero()};
  /// Centre line of the peduncle and the truss rachis (metres).
  std::vector<Eigen::Vector3d> peduncle;
  std::vector<Fruit> fruits; ///< the truss's fruits
};

/// \brief Where the parts of a plant are: ground truth a mesh file alone does not give.
struct PlantAnatomy {
  /// Main stem centre line from the base (first point) to the apex (last point).
  std::vector<Eigen::Vector3d> stem_axis;
  /// Stem radius at each point of `stem_axis` (metres; 0 at the apex tip).
  std::vector<double> stem_radius_m;
  double stem_height_m = 0.0; ///< apex above the base, along the plant z axis
  double top_height_m = 0.0;  ///< highest point of the mesh above the base
  std::vector<Leaf> leaves;   ///< bottom (index 0) to top
  std::vector<Truss> trusses; ///< bottom to top
};

/// \brief A plant: mesh + anatomy, and the pose they are in.
struct Plant {
  std::string name;  ///< e.g. "tomato_seed3" or "tomato_seed3_simplified"
  TriangleMesh mesh; ///< part label per triangle, node names per part
  /// A plant given as a point cloud (a scan, e.g. Pheno4D or TomatoWUR): its points and
  /// their labels (one each, or none). Empty for mesh plants; a scan plant has no mesh.
  std::vector<Eigen::Vector3f> scan_points;
  std::vector<PartLabel> scan_labels; ///< one per scan point, or empty (unlabelled)
  /// Where the parts are, in the current frame; a loaded model or scan has only the
  /// stem axis (plant_model.h).
  PlantAnatomy anatomy;
  /// Position of the stem base in the current frame (origin until posed).
  Eigen::Vector3d base_position{Eigen::Vector3d::Zero()};
  /// Rotation about the plant's vertical axis relative to the generated plant (rad).
  double yaw_rad = 0.0;

  /// \brief Bounds of the mesh vertices and scan points.
  /// \throws InvalidArgumentError when the plant has neither.
  void bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const;

  /// \brief Number of leaf nodes (= leaves).
  std::size_t leafNodeCount() const { return anatomy.leaves.size(); }
  /// \brief The stem axis point at `height_m` above the base (linear interpolation of
  /// `anatomy.stem_axis` in z; the end points beyond the stem).
  /// \throws InvalidArgumentError if the plant has no stem axis.
  Eigen::Vector3d stemPointAtHeight(double height_m) const;
};

/// \brief Puts a plant at `base_position` (metres) turned by `yaw_rad` about its vertical
/// stem axis: x' = base_position + Rz(yaw) x for x in the generated plant's frame.
///
/// The pose is absolute: posing an already posed plant first undoes its current pose,
/// so posePlant(p, b, a) twice equals once (up to float rounding of the mesh vertices,
/// < 1e-7 m). Mesh vertices, stem axis, leaf nodes (positions and petiole directions),
/// leaflets, trusses and fruits move together, so ROIs computed afterwards (plant_rois.h)
/// move with the plant. The rotation uses portable trigonometry: bit-identical results
/// on every machine. The paper places its plants at (1.0, 0, 0.8) and turns them in 12
/// steps of 30 degrees.
/// \throws InvalidArgumentError if a value is not finite.
void posePlant(Plant& plant, const Eigen::Vector3d& base_position, double yaw_rad);

} // namespace plantnbv
