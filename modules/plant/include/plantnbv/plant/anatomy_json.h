#pragma once
/// \file anatomy_json.h
/// \brief A plant's anatomy as JSON text (written to anatomy.json by the tools), in the
/// plant's current frame, metres and radians. Keys follow the fields of plant.h:
/// \code{.json}
/// { "format": "plantnbv-anatomy", "version": 1, "name": "tomato_seed3",
///   "base_position": [1.0, 0.0, 0.8], "yaw_rad": 0.0,
///   "stem": { "axis": [[x, y, z], ...], "radius_m": [...], "height_m": 0.53,
///             "top_height_m": 0.6 },
///   "leaves": [ { "node": { "leaf_index": 0, "position": [...], "stem_point": [...],
///                           "petiole_direction": [...] },
///                 "axis": [[...]], "length_m": 0.2, "full_leaflet_count": 7,
///                 "leaflets": [ { "base": [...], "tip": [...], "length_m": 0.05,
///                                 "width_m": 0.03, "terminal": false } ] } ],
///   "trusses": [ { "leaf_below": 3, "attachment": [...], "peduncle": [[...]],
///                  "fruits": [ { "center": [...], "radius_m": 0.02 } ] } ] }
/// \endcode

#include <string>

#include <plantnbv/plant/plant.h>

namespace plantnbv {

/// \brief The anatomy of `plant`, with its name and pose, as indented JSON.
std::string anatomyToJson(const Plant& plant);

/// \brief Reads what anatomyToJson wrote into `plant` (name, pose and anatomy; the mesh
/// is left as it is). Numbers round-trip exactly.
/// \throws FormatError naming the JSON path of the first missing, mistyped or non-finite
/// value (e.g. "leaves[2].node.position: expected 3 numbers"), or for text that is not
/// JSON or not a plantnbv anatomy.
void anatomyFromJson(const std::string& json, Plant& plant);

} // namespace plantnbv
