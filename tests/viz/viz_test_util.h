#pragma once
// Shared by the viz tests: PNGs read back with VTK, pixel counts, an environment guard,
// and the paper's plant with its three ROIs.

#include <cstdlib>
#include <memory>
#include <optional>
#include <string>

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/viz/snapshot.h>

namespace plantnbv {
namespace test {

/// A PNG read with VTK (independent of writePng), rows from the top; empty on failure.
inline viz::RgbImage readPng(const std::string& path)
{
  viz::RgbImage image;
  vtkNew<vtkPNGReader> reader;
  if (!reader->CanReadFile(path.c_str()))
    return image;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  int dims[3];
  data->GetDimensions(dims);
  auto* scalars = vtkUnsignedCharArray::SafeDownCast(data->GetPointData()->GetScalars());
  if (scalars == nullptr || scalars->GetNumberOfComponents() < 3)
    return image;
  const int channels = scalars->GetNumberOfComponents();
  image.width = dims[0];
  image.height = dims[1];
  image.rgb.resize(std::size_t(3) * dims[0] * dims[1]);
  for (int y = 0; y < dims[1]; ++y)
    for (int x = 0; x < dims[0]; ++x)
      for (int c = 0; c < 3; ++c)
        image.at(x, y)[c] = scalars->GetValue(
            (std::size_t(dims[1] - 1 - y) * dims[0] + x) * channels + c);
  return image;
}

/// Pixels within `tolerance` (per channel, of 255) of `color`.
inline std::size_t countNear(const viz::RgbImage& image, const viz::Rgb& color,
                             int tolerance)
{
  const int want[3] = {int(color.r * 255 + 0.5f), int(color.g * 255 + 0.5f),
                       int(color.b * 255 + 0.5f)};
  std::size_t n = 0;
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) {
    bool near = true;
    for (int c = 0; c < 3; ++c)
      near = near && std::abs(int(image.rgb[i + c]) - want[c]) <= tolerance;
    n += near;
  }
  return n;
}

/// Sets (or, with nullopt, unsets) an environment variable until destroyed.
class ScopedEnv {
public:
  ScopedEnv(const char* name, std::optional<std::string> value) : name_(name)
  {
    if (const char* old = std::getenv(name))
      old_ = old;
    if (value)
      ::setenv(name, value->c_str(), 1);
    else
      ::unsetenv(name);
  }
  ~ScopedEnv()
  {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
  const char* name_;
  std::optional<std::string> old_;
};

/// Default plant 0 at the paper's base (1.0, 0, 0.8), generated once per process.
inline const Plant& paperPlant()
{
  static const std::unique_ptr<Plant> plant = [] {
    auto p =
        std::make_unique<Plant>(TomatoPlantGenerator(defaultPlantConfig(0)).generate());
    posePlant(*p, Eigen::Vector3d(1.0, 0.0, 0.8), 0.0);
    return p;
  }();
  return *plant;
}

} // namespace test
} // namespace plantnbv
