#include <cstring>
#include <string>
#include <string_view>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>
#include <plantnbv/viz/snapshot.h>

namespace plantnbv {
namespace viz {

void writePng(const RgbImage& image, const std::string& png_path)
{
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != std::size_t(3) * image.width * image.height)
    throw InvalidArgumentError("cannot write a " + std::to_string(image.width) + " x " +
                               std::to_string(image.height) + " image of " +
                               std::to_string(image.rgb.size()) +
                               " bytes: expected a positive size and 3 bytes per pixel");
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* dst = static_cast<std::uint8_t*>(data->GetScalarPointer());
  const std::size_t row_bytes = std::size_t(3) * image.width;
  // VTK's rows start at the bottom.
  for (int y = 0; y < image.height; ++y)
    std::memcpy(dst + y * row_bytes,
                image.rgb.data() + (image.height - 1 - y) * row_bytes, row_bytes);

  // Encoded in memory and written here: VTK's own file writing reports failures only on
  // its log, and we want an IoError with the system's reason.
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(data);
  writer->SetCompressionLevel(6);
  writer->WriteToMemoryOn();
  writer->Write();
  vtkUnsignedCharArray* png = writer->GetResult();
  if (png == nullptr || png->GetNumberOfValues() == 0)
    throw Error("VTK could not encode a " + std::to_string(image.width) + " x " +
                std::to_string(image.height) + " PNG");

  writeFileAtomically(png_path,
                      std::string_view(reinterpret_cast<const char*>(png->GetPointer(0)),
                                       std::size_t(png->GetNumberOfValues())));
}

} // namespace viz
} // namespace plantnbv
