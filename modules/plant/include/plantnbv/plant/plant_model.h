#pragma once
/// \file plant_model.h
/// \brief Plants from mesh files (a Gazebo model, a CAD export): part labels from node,
/// geometry or material names, and placement in the plant frame.

#include <string>
#include <vector>

#include <plantnbv/plant/plant.h>

namespace plantnbv {

/// \brief Triangles whose node name, geometry name or material name fully matches
/// `pattern` (ECMAScript regular expression) get `label`.
struct PartLabelRule {
  PartLabel label = PartLabel::unknown; ///< the label the matching triangles get
  std::string pattern; ///< ECMAScript regex matched against a triangle's three names
};

/// \brief Parses "stem=Branch.*,leaflet=Leaf.*,fruit=Fruit.*": comma-separated
/// `part=regex` pairs; part names as partLabelName() gives them.
/// \throws InvalidArgumentError naming the pair for an unknown part name, a pair without
/// '=', an empty pattern or an invalid regular expression.
std::vector<PartLabelRule> parsePartLabelRules(const std::string& spec);

/// \brief Labels every triangle by the first rule that one of its names matches (node,
/// geometry or material name: TriangleMesh::namesOf); triangles that match none keep
/// their label (or get `unknown` if the mesh had no labels). Returns the number of
/// triangles each rule labelled, in rule order.
std::vector<std::size_t> applyPartLabelRules(TriangleMesh& mesh,
                                             const std::vector<PartLabelRule>& rules);

/// \brief A plant from a loaded mesh (metres, Z up, as io::loadMesh gives it).
///
/// Without `keep_frame` the mesh is moved so that the centre of the bottom face of its
/// bounding box is the origin of the plant frame, where a generated plant has its base;
/// posePlant() then places it like a generated one. With `keep_frame` the coordinates are
/// kept and base_position is that bottom-face centre. The anatomy a mesh does not give is
/// left empty (no leaves, no trusses); the stem axis is the vertical through the bottom
/// face centre up to the top of the bounding box, and top_height_m is the model's height,
/// so ROIs that need only the axis (wholePlantRoi, mainStemRoi) and boundingBoxRoi()
/// work. \throws InvalidArgumentError for an empty mesh.
Plant plantFromMesh(TriangleMesh mesh, const std::string& name, bool keep_frame = false);

/// \brief A plant from a scanned point cloud (finite points only), placed like
/// plantFromMesh places a mesh; `labels` is empty or holds one label per point.
/// \throws InvalidArgumentError for no points, non-finite points or a label count that
/// differs from the point count.
Plant plantFromScan(std::vector<Eigen::Vector3f> points, std::vector<PartLabel> labels,
                    const std::string& name, bool keep_frame = false);

} // namespace plantnbv
