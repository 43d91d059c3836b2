#include "window_image.h"

#include <cstring>
#include <string>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkRenderWindow.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <plantnbv/common/error.h>

namespace plantnbv {
namespace viz {
namespace detail {

RgbImage readWindowImage(vtkRenderWindow* window, int width, int height)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  vtkImageData* pixels = grab->GetOutput();
  int dims[3];
  pixels->GetDimensions(dims);
  auto* scalars =
      vtkUnsignedCharArray::SafeDownCast(pixels->GetPointData()->GetScalars());
  if (dims[0] != width || dims[1] != height || scalars == nullptr ||
      scalars->GetNumberOfComponents() != 3)
    throw Error("VTK returned a " + std::to_string(dims[0]) + " x " +
                std::to_string(dims[1]) + " image instead of " + std::to_string(width) +
                " x " + std::to_string(height) + " RGB pixels");
  RgbImage image;
  image.width = width;
  image.height = height;
  image.rgb.resize(std::size_t(3) * width * height);
  const std::uint8_t* src = scalars->GetPointer(0);
  const std::size_t row_bytes = std::size_t(3) * width;
  // VTK's rows start at the bottom.
  for (int y = 0; y < height; ++y)
    std::memcpy(image.rgb.data() + y * row_bytes, src + (height - 1 - y) * row_bytes,
                row_bytes);
  grab->SetInput(nullptr);
  return image;
}

} // namespace detail
} // namespace viz
} // namespace plantnbv
