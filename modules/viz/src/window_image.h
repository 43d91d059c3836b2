#pragma once
// Private to viz: reads a rendered VTK window back into our RgbImage (rows from the top).

#include <plantnbv/viz/snapshot.h>

class vtkRenderWindow;

namespace plantnbv {
namespace viz {
namespace detail {

/// \brief The RGB pixels of `window`'s back buffer, which must be width x height.
/// \throws Error when VTK returns another size or format.
RgbImage readWindowImage(vtkRenderWindow* window, int width, int height);

} // namespace detail
} // namespace viz
} // namespace plantnbv
