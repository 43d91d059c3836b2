#include <string>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/palette.h>

namespace plantnbv {
namespace viz {

Rgb partLabelColor(PartLabel label)
{
  switch (label) {
  case PartLabel::unknown:
    return {0.80f, 0.80f, 0.80f};
  case PartLabel::stem:
    return {0.48f, 0.36f, 0.20f};
  case PartLabel::petiole:
    return {0.58f, 0.72f, 0.22f};
  case PartLabel::leaflet:
    return {0.22f, 0.56f, 0.18f};
  case PartLabel::peduncle:
    return {0.70f, 0.88f, 0.45f};
  case PartLabel::fruit:
    return {0.86f, 0.10f, 0.08f};
  case PartLabel::background:
    return {0.55f, 0.55f, 0.55f};
  case PartLabel::flower:
    return {1.00f, 0.90f, 0.45f}; // pale yellow: the ROI palette has the saturated one
  }
  throw InvalidArgumentError("unknown part label value " +
                             std::to_string(static_cast<unsigned>(label)));
}

Rgb distinctColor(std::size_t i)
{
  // Saturated hues that none of the part colours comes close to, so ROI lines stand out
  // against the plant and the white background.
  static constexpr Rgb kColors[] = {
      {0.10f, 0.30f, 0.95f}, // blue
      {1.00f, 0.50f, 0.00f}, // orange
      {0.90f, 0.05f, 0.80f}, // magenta
      {0.00f, 0.75f, 0.90f}, // cyan
      {0.45f, 0.15f, 0.70f}, // purple
      {0.95f, 0.85f, 0.00f}, // yellow
      {0.00f, 0.50f, 0.50f}, // teal
      {0.00f, 0.00f, 0.00f}, // black
  };
  return kColors[i % (sizeof(kColors) / sizeof(kColors[0]))];
}

Rgb chartColor(std::size_t i)
{
  // Okabe & Ito (2008), as 8-bit sRGB.
  static constexpr unsigned char kColors[][3] = {
      {0, 0, 0},       // black
      {230, 159, 0},   // orange
      {86, 180, 233},  // sky blue
      {0, 158, 115},   // bluish green
      {240, 228, 66},  // yellow
      {0, 114, 178},   // blue
      {213, 94, 0},    // vermillion
      {204, 121, 167}, // reddish purple
  };
  const unsigned char* c = kColors[i % (sizeof(kColors) / sizeof(kColors[0]))];
  return {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f};
}

} // namespace viz
} // namespace plantnbv
