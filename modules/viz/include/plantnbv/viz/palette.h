#pragma once
/// \file palette.h
/// \brief Colours of the snapshots: the fixed colour of each plant part and a few
/// distinct colours for ROIs and point clouds, chosen to stay apart from the plant's.

#include <cstddef>

#include <plantnbv/common/triangle_mesh.h>

namespace plantnbv {
namespace viz {

/// \brief A colour: red, green and blue in [0, 1] (sRGB, as written to the PNG).
struct Rgb {
  float r = 0.0f; ///< red
  float g = 0.0f; ///< green
  float b = 0.0f; ///< blue
};

/// \brief The colour plant parts of `label` are drawn in: stem brown, petiole
/// yellow-green, leaflet green, peduncle light green, fruit red, flower pale yellow,
/// background grey, unknown light grey. Shading darkens or lightens it in the image.
/// \throws InvalidArgumentError for a value outside PartLabel.
Rgb partLabelColor(PartLabel label);

/// \brief The i-th of 8 saturated colours that differ from each other and from the
/// part colours (blue, orange, magenta, cyan, purple, yellow, teal, black), repeating
/// after 8: one per ROI or point cloud in a snapshot. The first three are used for the
/// paper's whole-plant, main-stem and leaf-node ROIs throughout the project.
Rgb distinctColor(std::size_t i);

/// \brief The i-th colour of Okabe and Ito's palette for charts, which readers with any
/// common colour-vision deficiency tell apart (M. Okabe, K. Ito, "Color Universal
/// Design", 2008): 0 black `#000000`, 1 orange `#E69F00`, 2 sky blue `#56B4E9`, 3 bluish
/// green `#009E73`, 4 yellow `#F0E442`, 5 blue `#0072B2`, 6 vermillion `#D55E00`, 7
/// reddish purple `#CC79A7`; repeating after 8. Curves of a chart take these
/// (LineChartFigure), each with its own line pattern or marker as well; snapshots keep
/// distinctColor.
Rgb chartColor(std::size_t i);

} // namespace viz
} // namespace plantnbv
